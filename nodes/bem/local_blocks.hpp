#pragma once
// 3x3 blocks of V, K and D for one element pair, from the pair integrals (sgbem-math.md §2).
#include "nodes/bem/element_geometry.hpp"
#include "nodes/bem/pair_integrals.hpp"

namespace cf::bem {

struct ElasticConstants {
    double mu = 0, nu = 0;
    ElasticConstants() = default;
    ElasticConstants(double E, double nu_) : mu(E / (2 * (1 + nu_))), nu(nu_) {}
};

// Integrated Kelvin tensor int int U* = ((3-4nu) I1 I + IR) / (16 pi mu (1-nu)).
Mat3 single_layer_block(const PairIntegrals& p, const ElasticConstants& c);
// P = ((1-2nu) I1 I + IR) / (8 pi (1-nu)): the combined Guenter terms of K and D.
Mat3 guenter_kernel(const PairIntegrals& p, const ElasticConstants& c);
// K[a, (b, beta)] = IK/(4 pi) I + P M_beta  (Kupradze/Guenter form).
Mat3 double_layer_block(double ik, const Mat3& P, const Mat3& M_beta);
// D[(a,alpha), (b,beta)] = mu/(4pi) I1 ((c_a.c_b) I + M_b^T M_a) - 2 mu M_a^T P M_b.
Mat3 hypersingular_block(const ElementGeometry& a, int alpha, const ElementGeometry& b, int beta, double I1, const Mat3& P,
                         const ElasticConstants& c);

}  // namespace cf::bem
