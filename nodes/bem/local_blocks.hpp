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

// All blocks of one element pair at once, as the assembly needs them. Same formulas as above,
// rewritten with M_beta = [c_beta]_x (cross-product matrix of the curl c_beta = n x grad lambda_beta):
//   M_b^T M_a = (c_a.c_b) I - c_a c_b^T,   -M_a^T P M_b = [c_a]_x P [c_b]_x,
// and, because the curls of the three hats sum to zero, blocks of vertex 2 are minus the sum of
// those of vertices 0 and 1 (every block is linear in each curl).
struct PairBlocks {
    Mat3 U;                                // single layer (if requested)
    std::array<Mat3, 3> Kb;                // K[a, (b, beta)]
    std::array<Mat3, 3> Ka;                // K[b, (a, alpha)] (the pair seen from b)
    std::array<std::array<Mat3, 3>, 3> H;  // D[(a, alpha), (b, beta)], H[alpha][beta]
};
void pair_blocks(const ElementGeometry& a, const ElementGeometry& b, const PairIntegrals& p, const ElasticConstants& c,
                 bool single_layer, PairBlocks& out);

}  // namespace cf::bem
