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

namespace {
// [c]_x T: the cross product of c with each column of T.
Mat3 cross_columns(const Vec3& c, const Mat3& T) {
    Mat3 out;
    for (int j = 0; j < 3; ++j) out.col(j) = c.cross(T.col(j));
    return out;
}
// P [c]_x: column j is P (c x e_j).
Mat3 times_cross(const Mat3& P, const Vec3& c) {
    Mat3 X;
    X << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0;
    return P * X;
}
}  // namespace

void pair_blocks(const ElementGeometry& a, const ElementGeometry& b, const PairIntegrals& p, const ElasticConstants& c,
                 bool single_layer, PairBlocks& out) {
    const Mat3 R = ir_matrix(p);
    if (single_layer) {
        const double k = 1.0 / (16 * M_PI * c.mu * (1 - c.nu));
        out.U = k * R;
        out.U.diagonal().array() += k * (3 - 4 * c.nu) * p.I1;
    }
    const double kp = 1.0 / (8 * M_PI * (1 - c.nu));
    Mat3 P = kp * R;
    P.diagonal().array() += kp * (1 - 2 * c.nu) * p.I1;
    // K blocks: IK/(4 pi) I + P M.
    std::array<Mat3, 3> Tb, Ta;
    for (int k = 0; k < 2; ++k) {
        Tb[k] = times_cross(P, b.curl[k]);
        Ta[k] = times_cross(P, a.curl[k]);
    }
    Tb[2] = -Tb[0] - Tb[1];
    Ta[2] = -Ta[0] - Ta[1];
    for (int k = 0; k < 3; ++k) {
        out.Kb[k] = Tb[k];
        out.Kb[k].diagonal().array() += p.IKb[k] / (4 * M_PI);
        out.Ka[k] = Ta[k];
        out.Ka[k].diagonal().array() += p.IKa[k] / (4 * M_PI);
    }
    // D blocks: mu/(4 pi) I1 (2 (c_a.c_b) I - c_a c_b^T) + 2 mu [c_a]_x P [c_b]_x.
    const double g = c.mu / (4 * M_PI) * p.I1, m2 = 2 * c.mu;
    for (int al = 0; al < 2; ++al)
        for (int be = 0; be < 2; ++be) {
            Mat3& B = out.H[al][be];
            B.noalias() = m2 * cross_columns(a.curl[al], Tb[be]);
            B.noalias() -= g * (a.curl[al] * b.curl[be].transpose());
            B.diagonal().array() += 2 * g * a.curl[al].dot(b.curl[be]);
        }
    for (int al = 0; al < 2; ++al) out.H[al][2] = -out.H[al][0] - out.H[al][1];
    for (int be = 0; be < 3; ++be) out.H[2][be] = -out.H[0][be] - out.H[1][be];
}

}  // namespace cf::bem
