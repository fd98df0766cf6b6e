#include "nodes/bem/pair_integrals.hpp"

#include "nodes/domain/isa_clones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <mutex>

namespace cf::bem {

namespace {

// Pads a pair rule to a multiple of pair_rule_padding points with zero-weight copies of its last
// point (a copy, not zeros, so that the padded lanes never divide by r = 0).
PairRule padded(PairRule r) {
    while (r.size() % pair_rule_padding) {
        r.sx.push_back(r.sx.back());
        r.tx.push_back(r.tx.back());
        r.sy.push_back(r.sy.back());
        r.ty.push_back(r.ty.back());
        r.w.push_back(0.0);
    }
    return r;
}

}  // namespace

PairRule tensor_pair_rule(const TriangleRule& t) {
    PairRule r;
    const std::size_t m = t.size();
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = 0; j < m; ++j) {
            r.sx.push_back(t.s[i]);
            r.tx.push_back(t.t[i]);
            r.sy.push_back(t.s[j]);
            r.ty.push_back(t.t[j]);
            r.w.push_back(t.w[i] * t.w[j]);
        }
    return padded(std::move(r));
}

PairQuadrature::PairQuadrature(const QuadratureSettings& s) : settings_(s) {
    id_ = padded(sauter_schwab_rule(PairKind::identical, s.singular_order));
    edge_ = padded(sauter_schwab_rule(PairKind::common_edge, s.singular_order));
    vert_ = padded(sauter_schwab_rule(PairKind::common_vertex, s.singular_order));
    if (s.fixed_regular > 0) fixed_ = tensor_pair_rule(collapsed_gauss_triangle_rule(s.fixed_regular));
    if (s.fold_angle > 0) {
        fold_cos_ = -std::cos(s.fold_angle * M_PI / 180);
        edge_fold_ = padded(sauter_schwab_rule(PairKind::common_edge, s.fold_order));
        vert_fold_ = padded(sauter_schwab_rule(PairKind::common_vertex, s.fold_order));
    }
    for (int z = 0; z < num_regular_zones; ++z) zones_[z] = tensor_pair_rule(regular_zone_rule(z));
}

const PairQuadrature& shared_pair_quadrature(const QuadratureSettings& s) {
    static std::mutex mutex;
    static std::deque<PairQuadrature> built;  // a deque never moves its elements
    const std::lock_guard<std::mutex> lock(mutex);
    for (const PairQuadrature& q : built) {
        const QuadratureSettings& t = q.settings();
        if (t.singular_order == s.singular_order && t.farfield_boost == s.farfield_boost && t.fixed_regular == s.fixed_regular &&
            t.fold_angle == s.fold_angle && t.fold_order == s.fold_order)
            return q;
    }
    return built.emplace_back(s);
}

double separation_ratio(const ElementGeometry& a, const ElementGeometry& b) {
    return (a.centroid - b.centroid).norm() / std::max(a.diameter, b.diameter);
}

namespace {

// Sums over the points of a pair rule, with the points given in reordered local coordinates:
//   d = x - y = c + sx A1 + tx A2 - sy B1 - ty B2,  c = A0 - B0,
// g = {c(3), A1(3), A2(3), B1(3), B2(3), n_a(3), n_b(3)}. out = {I1, Rxx, Ryy, Rzz, Rxy, Rxz, Ryz,
// sum fb, sum fb sy, sum fb ty, sum fa, sum fa sx, sum fa tx} with fb = w d.n_b / r^3 and
// fa = -w d.n_a / r^3 (unscaled by the areas). n is a multiple of pair_rule_padding.
// Eight lanes (Lanes8) of GCC vector extensions: the compiler lowers them to SSE2, AVX2 or AVX-512 and the
// function is cloned per ISA level (chosen at load time), so no -march flag is needed. Each lane
// accumulates its own points and the lanes are summed in a fixed order at the end, so the result
// does not depend on the thread count.
static_assert(pair_rule_padding == 8, "pair_rule_padding must equal the kernel's lane count");

CF_ISA_LEVEL_CLONES  // nodes/domain/isa_clones.hpp
void pair_kernel(const double* sx, const double* tx, const double* sy, const double* ty, const double* w, std::size_t n,
                 const double* g, double* out) {
    Lanes8 i1 = {}, rxx = {}, ryy = {}, rzz = {}, rxy = {}, rxz = {}, ryz = {};
    Lanes8 kb = {}, kbs = {}, kbt = {}, ka = {}, kas = {}, kat = {};
    for (std::size_t q = 0; q < n; q += 8) {
        Lanes8 s1, t1, s2, t2, W;
        std::memcpy(&s1, sx + q, sizeof s1);
        std::memcpy(&t1, tx + q, sizeof t1);
        std::memcpy(&s2, sy + q, sizeof s2);
        std::memcpy(&t2, ty + q, sizeof t2);
        std::memcpy(&W, w + q, sizeof W);
        const Lanes8 dx = g[0] + s1 * g[3] + t1 * g[6] - s2 * g[9] - t2 * g[12];
        const Lanes8 dy = g[1] + s1 * g[4] + t1 * g[7] - s2 * g[10] - t2 * g[13];
        const Lanes8 dz = g[2] + s1 * g[5] + t1 * g[8] - s2 * g[11] - t2 * g[14];
        const Lanes8 r2 = dx * dx + dy * dy + dz * dz;
        Lanes8 r;
        for (int l = 0; l < 8; ++l) r[l] = std::sqrt(r2[l]);  // vectorised (-fno-math-errno)
        const Lanes8 ri = 1.0 / r;
        const Lanes8 wi = W * ri;
        const Lanes8 w3 = wi * ri * ri;
        i1 += wi;
        rxx += w3 * dx * dx;
        ryy += w3 * dy * dy;
        rzz += w3 * dz * dz;
        rxy += w3 * dx * dy;
        rxz += w3 * dx * dz;
        ryz += w3 * dy * dz;
        const Lanes8 fa = -w3 * (dx * g[15] + dy * g[16] + dz * g[17]);
        const Lanes8 fb = w3 * (dx * g[18] + dy * g[19] + dz * g[20]);
        kb += fb;
        kbs += fb * s2;
        kbt += fb * t2;
        ka += fa;
        kas += fa * s1;
        kat += fa * t1;
    }
    const Lanes8* acc[13] = {&i1, &rxx, &ryy, &rzz, &rxy, &rxz, &ryz, &kb, &kbs, &kbt, &ka, &kas, &kat};
    for (int k = 0; k < 13; ++k) {
        double s = 0;
        for (int l = 0; l < 8; ++l) s += (*acc[k])[l];
        out[k] = s;
    }
}

PairIntegrals integrate_pair(const ElementGeometry& a, const int* perm_a, const ElementGeometry& b, const int* perm_b,
                             const PairRule& r) {
    const Vec3 A0 = a.p[perm_a[0]], B0 = b.p[perm_b[0]];
    const Vec3 c = A0 - B0, A1 = a.p[perm_a[1]] - A0, A2 = a.p[perm_a[2]] - A0;
    const Vec3 B1 = b.p[perm_b[1]] - B0, B2 = b.p[perm_b[2]] - B0;
    const double g[21] = {c.x(),  c.y(),  c.z(),  A1.x(), A1.y(), A1.z(), A2.x(), A2.y(), A2.z(),  B1.x(),  B1.y(),
                          B1.z(), B2.x(), B2.y(), B2.z(), a.normal.x(), a.normal.y(), a.normal.z(), b.normal.x(),
                          b.normal.y(), b.normal.z()};
    double s[13];
    pair_kernel(r.sx.data(), r.tx.data(), r.sy.data(), r.ty.data(), r.w.data(), r.size(), g, s);
    const double scale = 4 * a.area * b.area;
    PairIntegrals out;
    out.I1 = s[0] * scale;
    for (int k = 0; k < 6; ++k) out.IR[k] = s[1 + k] * scale;
    // lambda_0 = 1 - s - t, lambda_1 = s, lambda_2 = t on the reordered vertices.
    out.IKb[perm_b[0]] = (s[7] - s[8] - s[9]) * scale;
    out.IKb[perm_b[1]] = s[8] * scale;
    out.IKb[perm_b[2]] = s[9] * scale;
    out.IKa[perm_a[0]] = (s[10] - s[11] - s[12]) * scale;
    out.IKa[perm_a[1]] = s[11] * scale;
    out.IKa[perm_a[2]] = s[12] * scale;
    return out;
}

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
    const PairRule& r = kind != PairKind::separated ? q.touching(kind, a.normal.dot(b.normal)) : q.regular_pairs(separation_ratio(a, b));
    return integrate_pair(a, perm_a, b, perm_b, r);
}

PairIntegrals separated_pair_integrals(const ElementGeometry& a, const ElementGeometry& b, const PairRule& r) {
    const int perm[3] = {0, 1, 2};
    return integrate_pair(a, perm, b, perm, r);
}

}  // namespace cf::bem
