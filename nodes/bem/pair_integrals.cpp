#include "nodes/bem/pair_integrals.hpp"

#include <algorithm>
#include <cmath>

namespace cf::bem {

PairQuadrature::PairQuadrature(const QuadratureSettings& s)
    : settings_(s),
      id_(sauter_schwab_rule(PairKind::identical, s.singular_order)),
      edge_(sauter_schwab_rule(PairKind::common_edge, s.singular_order)),
      vert_(sauter_schwab_rule(PairKind::common_vertex, s.singular_order)) {
    if (s.fixed_regular > 0) fixed_ = collapsed_gauss_triangle_rule(s.fixed_regular);
}

double separation_ratio(const ElementGeometry& a, const ElementGeometry& b) {
    return (a.centroid - b.centroid).norm() / std::max(a.diameter, b.diameter);
}

namespace {

// Accumulates the integrands over points given in reordered local coordinates of a and b:
// x = Pa0 + sx (Pa1 - Pa0) + tx (Pa2 - Pa0), perm_a[k] = original local index of reordered vertex k.
struct Accumulator {
    double I1 = 0, R[6] = {0, 0, 0, 0, 0, 0}, Kb[3] = {0, 0, 0}, Ka[3] = {0, 0, 0};

    template <class PointsX, class PointsY>
    void run(const ElementGeometry& a, const int* perm_a, const ElementGeometry& b, const int* perm_b, std::size_t n,
             const double* w, PointsX px, PointsY py) {
        const Vec3 A0 = a.p[perm_a[0]], A1 = a.p[perm_a[1]] - A0, A2 = a.p[perm_a[2]] - A0;
        const Vec3 B0 = b.p[perm_b[0]], B1 = b.p[perm_b[1]] - B0, B2 = b.p[perm_b[2]] - B0;
        const Vec3 na = a.normal, nb = b.normal;
        double i1 = 0, rxx = 0, ryy = 0, rzz = 0, rxy = 0, rxz = 0, ryz = 0;
        double kb0 = 0, kb1 = 0, kb2 = 0, ka0 = 0, ka1 = 0, ka2 = 0;
        for (std::size_t q = 0; q < n; ++q) {
            double sx, tx, sy, ty;
            px(q, sx, tx);
            py(q, sy, ty);
            const double dx = A0.x() + sx * A1.x() + tx * A2.x() - (B0.x() + sy * B1.x() + ty * B2.x());
            const double dy = A0.y() + sx * A1.y() + tx * A2.y() - (B0.y() + sy * B1.y() + ty * B2.y());
            const double dz = A0.z() + sx * A1.z() + tx * A2.z() - (B0.z() + sy * B1.z() + ty * B2.z());
            const double r2 = dx * dx + dy * dy + dz * dz;
            const double ri = 1.0 / std::sqrt(r2);
            const double wi = w[q] * ri;
            const double w3 = wi * ri * ri;
            i1 += wi;
            rxx += w3 * dx * dx;
            ryy += w3 * dy * dy;
            rzz += w3 * dz * dz;
            rxy += w3 * dx * dy;
            rxz += w3 * dx * dz;
            ryz += w3 * dy * dz;
            const double fb = w3 * (dx * nb.x() + dy * nb.y() + dz * nb.z());
            const double fa = -w3 * (dx * na.x() + dy * na.y() + dz * na.z());
            kb0 += fb * (1 - sy - ty);
            kb1 += fb * sy;
            kb2 += fb * ty;
            ka0 += fa * (1 - sx - tx);
            ka1 += fa * sx;
            ka2 += fa * tx;
        }
        I1 = i1;
        R[0] = rxx; R[1] = ryy; R[2] = rzz; R[3] = rxy; R[4] = rxz; R[5] = ryz;
        Kb[perm_b[0]] = kb0; Kb[perm_b[1]] = kb1; Kb[perm_b[2]] = kb2;
        Ka[perm_a[0]] = ka0; Ka[perm_a[1]] = ka1; Ka[perm_a[2]] = ka2;
    }
};

}  // namespace

PairIntegrals pair_integrals(const ElementGeometry& a, const ElementGeometry& b, bool same_mesh, const PairQuadrature& q) {
    int perm_a[3] = {0, 1, 2}, perm_b[3] = {0, 1, 2};
    PairKind kind = PairKind::separated;
    if (same_mesh) {
        int ia[3], ib[3], ns = 0;  // local indices of shared vertices, in a's order
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (a.nodes[i] == b.nodes[j]) { ia[ns] = i; ib[ns] = j; ++ns; }
        if (ns == 3) {
            kind = PairKind::identical;
            for (int k = 0; k < 3; ++k) perm_b[k] = ib[k];  // b's local index of a's vertex k
        } else if (ns == 2) {
            kind = PairKind::common_edge;
            perm_a[0] = ia[0]; perm_a[1] = ia[1]; perm_a[2] = 3 - ia[0] - ia[1];
            perm_b[0] = ib[0]; perm_b[1] = ib[1]; perm_b[2] = 3 - ib[0] - ib[1];
        } else if (ns == 1) {
            kind = PairKind::common_vertex;
            // Shared vertex first, the other two in their original order.
            perm_a[0] = ia[0]; perm_a[1] = ia[0] == 0 ? 1 : 0; perm_a[2] = ia[0] == 2 ? 1 : 2;
            perm_b[0] = ib[0]; perm_b[1] = ib[0] == 0 ? 1 : 0; perm_b[2] = ib[0] == 2 ? 1 : 2;
        }
    }
    Accumulator acc;
    double scale = 4 * a.area * b.area;
    if (kind != PairKind::separated) {
        const PairRule& r = q.singular(kind);
        acc.run(a, perm_a, b, perm_b, r.size(), r.w.data(),
                [&](std::size_t k, double& s, double& t) { s = r.sx[k]; t = r.tx[k]; },
                [&](std::size_t k, double& s, double& t) { s = r.sy[k]; t = r.ty[k]; });
    } else {
        const TriangleRule& r = q.regular(separation_ratio(a, b));
        const std::size_t m = r.size();
        // Tensor product: index k = i * m + j (i on a, j on b).
        static thread_local std::vector<double> w;
        w.resize(m * m);
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < m; ++j) w[i * m + j] = r.w[i] * r.w[j];
        acc.run(a, perm_a, b, perm_b, m * m, w.data(),
                [&](std::size_t k, double& s, double& t) { s = r.s[k / m]; t = r.t[k / m]; },
                [&](std::size_t k, double& s, double& t) { s = r.s[k % m]; t = r.t[k % m]; });
    }
    PairIntegrals out;
    out.I1 = acc.I1 * scale;
    for (int k = 0; k < 6; ++k) out.IR[k] = acc.R[k] * scale;
    for (int k = 0; k < 3; ++k) {
        out.IKb[k] = acc.Kb[k] * scale;
        out.IKa[k] = acc.Ka[k] * scale;
    }
    return out;
}

}  // namespace cf::bem
