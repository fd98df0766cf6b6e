#include "nodes/bem/local_blocks.hpp"

#include <cmath>

namespace cf::bem {

namespace {
Mat3 ir_matrix(const PairIntegrals& p) {
    Mat3 R;
    R << p.IR[0], p.IR[3], p.IR[4], p.IR[3], p.IR[1], p.IR[5], p.IR[4], p.IR[5], p.IR[2];
    return R;
}
}  // namespace

Mat3 single_layer_block(const PairIntegrals& p, const ElasticConstants& c) {
    const double k = 1.0 / (16 * M_PI * c.mu * (1 - c.nu));
    return k * ((3 - 4 * c.nu) * p.I1 * Mat3::Identity() + ir_matrix(p));
}

Mat3 guenter_kernel(const PairIntegrals& p, const ElasticConstants& c) {
    const double k = 1.0 / (8 * M_PI * (1 - c.nu));
    return k * ((1 - 2 * c.nu) * p.I1 * Mat3::Identity() + ir_matrix(p));
}

Mat3 double_layer_block(double ik, const Mat3& P, const Mat3& M_beta) {
    Mat3 B = P * M_beta;
    B.diagonal().array() += ik / (4 * M_PI);
    return B;
}

Mat3 hypersingular_block(const ElementGeometry& a, int alpha, const ElementGeometry& b, int beta, double I1, const Mat3& P,
                         const ElasticConstants& c) {
    const Mat3& Ma = a.M[alpha];
    const Mat3& Mb = b.M[beta];
    Mat3 B = (c.mu / (4 * M_PI) * I1) * (Mb.transpose() * Ma);
    B.diagonal().array() += c.mu / (4 * M_PI) * I1 * a.curl[alpha].dot(b.curl[beta]);
    B.noalias() -= (2 * c.mu) * (Ma.transpose() * P * Mb);
    return B;
}

}  // namespace cf::bem
