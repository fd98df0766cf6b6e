#include "nodes/bem/tip_elements.hpp"

#include "nodes/bem/solver.hpp"
#include "nodes/domain/isa_clones.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace cf::bem {

bool same_tip_kind(const TipElementKind& x, const TipElementKind& y) {
    return x.type == y.type && x.local == y.local && x.front == y.front && x.chord == y.chord &&
           x.chord_value[0] == y.chord_value[0] && x.chord_value[1] == y.chord_value[1] && x.chord_value[2] == y.chord_value[2];
}

TipBasis tip_basis(const SurfaceMesh& cracks) {
    TipBasis b;
    const std::vector<char> interior = crack_interior_nodes(cracks);
    b.front.assign(cracks.num_vertices(), 0);
    for (const Tri& t : cracks.triangles)
        for (int v : t) b.front[v] = !interior[v];
    // Per edge: its triangles' third nodes.
    std::map<std::pair<int, int>, std::vector<int>> opposite;
    for (const Tri& t : cracks.triangles)
        for (int k = 0; k < 3; ++k)
            opposite[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}].push_back(t[(k + 2) % 3]);
    b.kind.resize(cracks.num_triangles());
    for (std::size_t e = 0; e < cracks.num_triangles(); ++e) {
        const Tri& t = cracks.triangles[e];
        TipElementKind& k = b.kind[e];
        int nf = 0, last_front = -1, last_inner = -1, boundary_edges = 0;
        for (int i = 0; i < 3; ++i) {
            if (b.front[t[i]]) {
                ++nf;
                last_front = i;
                k.front |= static_cast<unsigned char>(1 << i);
            } else {
                last_inner = i;
            }
            const int p = t[(i + 1) % 3], q = t[(i + 2) % 3];
            const std::vector<int>& opp = opposite[{std::min(p, q), std::max(p, q)}];
            boundary_edges += opp.size() == 1;
            if (opp.size() == 1 || !b.front[p] || !b.front[q]) continue;
            k.chord |= static_cast<unsigned char>(1 << i);
            // rho at the chord's midpoint: the share of the front side's height, h_front / (h_front +
            // h_inner), when exactly one of its triangles has its third node off the front (rho there ~
            // distance to the front over the distance of the first node row, as lambda_m on edge elements);
            // 1/2 otherwise.
            double c = 0.5;
            if (opp.size() == 2 && b.front[opp[0]] != b.front[opp[1]]) {
                const Vec3 P = cracks.vertices[p], u = (cracks.vertices[q] - P).normalized();
                auto height = [&](int x) { return ((cracks.vertices[x] - P) - (cracks.vertices[x] - P).dot(u) * u).norm(); };
                const int xf = b.front[opp[0]] ? opp[0] : opp[1], xi = b.front[opp[0]] ? opp[1] : opp[0];
                const double hf = height(xf), hi = height(xi);
                if (hf + hi > 0) c = std::clamp(0.5 * hf / (hf + hi), 0.01, 1.0);
            }
            k.chord_value[i] = c;
        }
        if (nf == 0) k.type = TipElementKind::plain;
        else if (k.chord) k.type = TipElementKind::general;
        else if (nf == 1) { k.type = TipElementKind::vertex; k.local = last_front; }
        else if (nf == 2) { k.type = TipElementKind::edge; k.local = last_inner; }
        else k.type = boundary_edges == 3 ? TipElementKind::zero : TipElementKind::general;
    }
    return b;
}

double front_edge_rho_slope(const TipElementKind& k, int m) {
    if (k.type == TipElementKind::edge) return k.local == m ? 1.0 : 0.0;
    if (k.type != TipElementKind::general) return 0.0;
    // g_m on the opposite edge (lambda_m = 0): r_m + 4 c per chord (o, m), o = j or k, the same all along the
    // edge; g_j = g_k = 0 there (front nodes, and their chords other than j-k end at m).
    double slope = (k.front >> m) & 1 ? 0.0 : 1.0;
    for (int e = 0; e < 3; ++e)
        if (e != m && ((k.chord >> e) & 1)) slope += 4 * k.chord_value[e];  // the chord opposite e != m ends at m
    return slope;
}

TriangleRule tip_triangle_rule(const TipElementKind& k, int n) {
    if (k.type != TipElementKind::edge && k.type != TipElementKind::vertex) return collapsed_gauss_triangle_rule(n, true);
    std::vector<double> g, w;
    gauss_legendre_01(n, g, w);
    TriangleRule r;
    const int m = k.local, j = (m + 1) % 3, o = (m + 2) % 3;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double u = g[a], v = g[b];
            std::array<double, 3> l{};
            double jac;
            if (k.type == TipElementKind::edge) {
                l[m] = u * u;
                l[j] = (1 - u * u) * v;
                l[o] = (1 - u * u) * (1 - v);
                jac = 2 * u * (1 - u * u);
            } else {
                l[m] = 1 - u * u;
                l[j] = u * u * v;
                l[o] = u * u * (1 - v);
                jac = 2 * u * u * u;
            }
            r.s.push_back(l[1]);
            r.t.push_back(l[2]);
            r.w.push_back(w[a] * w[b] * jac);
        }
    return r;
}

namespace {

// rho and d rho / d lambda_i on a general element (tip_elements.hpp).
double general_rho(const TipElementKind& k, const std::array<double, 3>& l, std::array<double, 3>& g) {
    double rho = 0;
    for (int i = 0; i < 3; ++i) {
        g[i] = (k.front >> i) & 1 ? 0.0 : 1.0;
        rho += g[i] * l[i];
    }
    for (int e = 0; e < 3; ++e)
        if ((k.chord >> e) & 1) {
            const int p = (e + 1) % 3, q = (e + 2) % 3;
            const double c4 = 4 * k.chord_value[e], sum = l[p] + l[q];
            if (!(sum > 0)) continue;  // at the third node: the term and its gradient are 0 (bounded)
            rho += c4 * l[p] * l[q] / sum;
            g[p] += c4 * l[q] * l[q] / (sum * sum);
            g[q] += c4 * l[p] * l[p] / (sum * sum);
        }
    return rho;
}

// tip_point's body, inlined into the quadrature loops below (a call per point, with its 128-byte
// result, cost as much as the point's kernel on touching pairs).
__attribute__((always_inline)) inline TipPoint tip_point_inline(const ElementGeometry& g, const TipElementKind& k, double s, double t) {
    TipPoint p;
    const std::array<double, 3> l = {1 - s - t, s, t};
    p.lambda = l;
    p.x = l[0] * g.p[0] + l[1] * g.p[1] + l[2] * g.p[2];
    double rho = 1;
    switch (k.type) {
    case TipElementKind::plain: break;
    case TipElementKind::zero: rho = 0; break;
    case TipElementKind::edge: rho = l[k.local]; p.g[k.local] = 1; break;
    case TipElementKind::vertex:
        rho = 1 - l[k.local];
        for (int i = 0; i < 3; ++i) p.g[i] = i == k.local ? 0.0 : 1.0;
        break;
    case TipElementKind::general: rho = general_rho(k, l, p.g); break;
    }
    if (k.type == TipElementKind::zero || !(rho > 0)) {
        p.sq = 0;
        p.q = {0, 0, 0};
        p.psi = {0, 0, 0};
        return p;
    }
    const double sr = std::sqrt(rho);
    p.sq = sr;
    for (int i = 0; i < 3; ++i) {
        p.q[i] = k.type == TipElementKind::plain ? 0.0 : l[i] / (2 * sr);
        p.psi[i] = sr * l[i];
    }
    return p;
}

}  // namespace

TipPoint tip_point(const ElementGeometry& g, const TipElementKind& k, double s, double t) {
    return tip_point_inline(g, k, s, t);
}

Vec3 rho_curl(const ElementGeometry& g, const TipElementKind& k) {
    if (k.type == TipElementKind::edge) return g.curl[k.local];
    if (k.type == TipElementKind::vertex) return -g.curl[k.local];
    return Vec3::Zero();
}

namespace {

// Weight functions of one side of a pair (times the pull-back Jacobian): index 0 is sqrt(rho) (1 on
// plain elements), then lambda_a / (2 sqrt(rho)) (edge, vertex: 1 + a) or lambda_a g_i / (2 sqrt(rho))
// (general: 1 + 3a + i). The curl of psi_a = sqrt(rho) lambda_a is
//   sqrt(rho) c_a + lambda_a / (2 sqrt(rho)) curl(rho),  curl(rho) = rho_curl (edge, vertex) or sum_i g_i c_i.
constexpr int max_weights = 10;
int weight_count(const TipElementKind& k) {
    switch (k.type) {
    case TipElementKind::plain:
    case TipElementKind::zero: return 1;
    case TipElementKind::general: return 10;
    default: return 4;
    }
}
void weights_at(const TipElementKind& k, const TipPoint& p, double* f) {
    f[0] = p.sq;
    if (k.type == TipElementKind::edge || k.type == TipElementKind::vertex) {
        for (int a = 0; a < 3; ++a) f[1 + a] = p.q[a];
    } else if (k.type == TipElementKind::general) {
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < 3; ++i) f[1 + 3 * a + i] = p.q[a] * p.g[i];
    }
}

// Weighted kernel sums over a pair rule: S1 = sum w f g / r, SR = sum w f g d d^T / r^3 (xx, yy, zz,
// xy, xz, yz), SK[b] = sum w psi_b(y) (x - y).n_b / r^3 (a plain). Only [0, na) x [0, nb) is used.
// S1 and SR of a weight pair are one row of eight (S1, the six SR, and a slot that stays zero), so
// the point loops below add all seven with one eight-wide operation; each entry still gets the same
// products added in the same order as one by one.
// An unaligned load as a statement expression (a function returning a 32-byte vector by value changes
// its ABI without AVX, -Wpsabi).
#define CF_LOAD4(p)                               \
    __extension__({                               \
        Lanes4 v_;                                \
        std::memcpy(&v_, (p), sizeof(Lanes4));    \
        v_;                                       \
    })
inline double sum4(const Lanes4* v) { return ((*v)[0] + (*v)[1]) + ((*v)[2] + (*v)[3]); }
// One weight pair's row of eight (Lanes8): S1, the six SR and a slot that stays zero (one AVX-512
// register, two AVX2 ones, four SSE2 ones).
struct TipSums {
    int na = 1, nb = 1;
    Lanes8 S[max_weights][max_weights];
    double SK[3] = {};
    TipSums(int na_, int nb_) : na(na_), nb(nb_) {
        for (int i = 0; i < na; ++i)
            for (int j = 0; j < nb; ++j) S[i][j] = Lanes8{};
    }
    double S1(int i, int j) const { return S[i][j][0]; }
    const double* SR(int i, int j) const { return reinterpret_cast<const double*>(&S[i][j]) + 1; }
};

// Separated pairs (tip_triangle_rule on edge and vertex elements, measured against 14 x 14 graded
// rules on 60 random pairs per separation, worst relative error of the weighted integrals; the
// weights' moments limit it at large separations, not the kernel):
//   rho >= 6: 3 x 3 (7.2e-4 at rho 6, 1.6e-4 at 16);  [2, 6): 4 x 4 (6.4e-5 at 3, 8.9e-5 at 2);
//   rho < 2: 5 x 5 (1.1e-5 at 1.5, 2.1e-5 at 1.25).
// The graded collapsed 4 x 4 rule used before gave 4-6.5e-4 at rho >= 3 and 1.7e-3 at 1.5. The
// touching pairs' error is 1.6e-3 (n = 7); 3 x 3 from rho 4 on, or 4 x 4 everywhere, moved the penny
// crack's K_I by < 0.01 %. General elements (rare: sheet corners) keep an 8 x 8 graded rule; plain
// ones the far-field zone rule of P1.
struct TipRules {
    PairRule id, edge, vert;
    PairRule general_edge, general_vert;  // n on pairs with a general element (corner slivers are sensitive)
    std::array<std::array<TriangleRule, 3>, 3> edge_rules, vertex_rules;  // [n - 3][local]
    TriangleRule general_rule;
    explicit TipRules(int n) {
        id = sauter_schwab_rule(PairKind::identical, n, true);
        edge = sauter_schwab_rule(PairKind::common_edge, n - 2, true);
        // n = 7 (production) on every touching pair cost about 45 % of a step. Edge and vertex pairs
        // use n - 2 (a third of the points; the identical pair, whose rule error matters most, keeps n).
        // Penny crack, 294 triangles, side 20a, front-average / worst node K_I error: all n: 0.247 /
        // 0.633 %; vertex n - 2: 0.243 / 0.631 %; edge and vertex n - 2: 0.259 / 0.647 %. Convergence
        // case: 0.52, 0.38, 0.33, 0.31 % (monotone, finest below the 0.5 % bar).
        vert = sauter_schwab_rule(PairKind::common_vertex, n - 2, true);
        general_edge = sauter_schwab_rule(PairKind::common_edge, n, true);
        general_vert = sauter_schwab_rule(PairKind::common_vertex, n, true);
        for (int i = 0; i < 3; ++i)
            for (int l = 0; l < 3; ++l) {
                TipElementKind k;
                k.local = l;
                k.type = TipElementKind::edge;
                edge_rules[i][l] = tip_triangle_rule(k, 3 + i);
                k.type = TipElementKind::vertex;
                vertex_rules[i][l] = tip_triangle_rule(k, 3 + i);
            }
        general_rule = collapsed_gauss_triangle_rule(8, true);
    }
    const TriangleRule& separated(const TipElementKind& k, double rho) const {
        const int i = rho >= 6 ? 0 : rho >= 2 ? 1 : 2;
        switch (k.type) {
        case TipElementKind::edge: return edge_rules[i][k.local];
        case TipElementKind::vertex: return vertex_rules[i][k.local];
        case TipElementKind::general: return general_rule;
        default: return regular_zone_rule(regular_zone(rho, 0));
        }
    }
};

// The rules for order n, built on first use and kept for the process (immutable; any thread reads
// them): every BEM step needs them, and they were built anew per step on one core (the identical
// pairs' rule alone is 6 x 7^4 points at n = 7).
const TipRules& shared_tip_rules(int n) {
    static std::mutex mutex;
    static std::map<int, std::unique_ptr<const TipRules>> built;
    const std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<const TipRules>& r = built[n];
    if (!r) r = std::make_unique<const TipRules>(n);
    return *r;
}

// One point pair: adds w fa_i fb_j k to the sums.
__attribute__((always_inline)) inline void accumulate(const double* fa, const double* fb, double w, const Lanes8& k,
                                                      TipSums& out) {
    for (int i = 0; i < out.na; ++i) {
        const double wi = w * fa[i];
        if (wi == 0) continue;
        for (int j = 0; j < out.nb; ++j) {
            const double v = wi * fb[j];
            out.S[i][j] += v * k;
        }
    }
}

void scale_sums(const ElementGeometry& a, const ElementGeometry& b, TipSums& out) {
    const double scale = 4 * a.area * b.area;
    for (int i = 0; i < out.na; ++i)
        for (int j = 0; j < out.nb; ++j) out.S[i][j] *= scale;
    for (double& v : out.SK) v *= scale;
}

// Four points of one side of a touching pair at once: positions, weights (weights_at) and psi per lane.
struct SidePoints4 {
    Lanes4 x[3];
    Lanes4 f[max_weights];
    Lanes4 psi[3];
};
// Lane by lane (by reference: returning a 32-byte vector changes its ABI without AVX, -Wpsabi).
__attribute__((always_inline)) inline void lanes_sqrt(const Lanes4& v, Lanes4& r) {
    for (int l = 0; l < 4; ++l) r[l] = std::sqrt(v[l]);
}
bool four_wide(const TipElementKind& k) {
    return k.type == TipElementKind::plain || k.type == TipElementKind::edge || k.type == TipElementKind::vertex;
}
// Plain, edge and vertex elements (four_wide): each lane runs tip_point_inline's and weights_at's IEEE
// operations in their order (no FMA: isa_clones.hpp), so every value is the one the scalar code gives
// bit for bit; only the divisions and square roots, the touching pairs' bottleneck, are issued four at
// a time. Other kinds (general, zero: sheet corners, rare) go through tip_point_inline lane by lane.
// s, t: the four points' local coordinates in the pair's reordered frame.
__attribute__((always_inline)) inline void side_points4(const ElementGeometry& g, const TipElementKind& k, const int* perm,
                                                        const double* s, const double* t, SidePoints4& out) {
    Lanes4 l[3];
    const Lanes4 S = CF_LOAD4(s), T = CF_LOAD4(t);
    // Reordered local (s, t) -> barycentric in the element's own order -> its (s, t).
    l[perm[0]] = 1 - S - T;
    l[perm[1]] = S;
    l[perm[2]] = T;
    if (!four_wide(k)) {
        for (int lane = 0; lane < 4; ++lane) {
            const TipPoint P = tip_point_inline(g, k, l[1][lane], l[2][lane]);
            double f[max_weights];
            weights_at(k, P, f);
            for (int c = 0; c < 3; ++c) out.x[c][lane] = P.x[c];
            for (int i = 0; i < weight_count(k); ++i) out.f[i][lane] = f[i];
            for (int i = 0; i < 3; ++i) out.psi[i][lane] = P.psi[i];
        }
        return;
    }
    // tip_point_inline takes (s, t) = (l[1], l[2]) and forms l[0] = 1 - s - t again.
    const Lanes4 l0 = 1 - l[1] - l[2];
    const Lanes4 L[3] = {l0, l[1], l[2]};
    for (int c = 0; c < 3; ++c) out.x[c] = L[0] * g.p[0][c] + L[1] * g.p[1][c] + L[2] * g.p[2][c];
    Lanes4 rho;
    switch (k.type) {
    case TipElementKind::edge: rho = L[k.local]; break;
    case TipElementKind::vertex: rho = 1 - L[k.local]; break;
    default: rho = Lanes4{1, 1, 1, 1}; break;  // plain
    }
    Lanes4 sr;
    lanes_sqrt(rho, sr);
    const Lanes4 two_sr = 2 * sr;
    Lanes4 q[3];
    for (int i = 0; i < 3; ++i) {
        q[i] = L[i] / two_sr;
        out.psi[i] = sr * L[i];
    }
    out.f[0] = sr;
    const bool plain = k.type == TipElementKind::plain;
    for (int a = 0; a < 3; ++a) out.f[1 + a] = plain ? Lanes4{} : q[a];
    // !(rho > 0): the scalar code sets sq, q and psi to 0.
    for (int lane = 0; lane < 4; ++lane)
        if (!(rho[lane] > 0)) {
            for (int a = 0; a < 4; ++a) out.f[a][lane] = 0;
            for (int i = 0; i < 3; ++i) out.psi[i][lane] = 0;
        }
}

// Touching pairs: a Sauter-Schwab rule in reordered local coordinates, four points at a time (a last
// partial batch padded with copies of its last point, which are not summed); the sums take the points
// one by one in the rule's order.
CF_AVX512_CLONE
void integrate(const ElementGeometry& a, const TipElementKind& ka, const int* pa, const ElementGeometry& b,
               const TipElementKind& kb, const int* pb, const PairRule& r, bool want_k, TipSums& out) {
    const std::size_t Q = r.size();
    SidePoints4 A, B;
    for (std::size_t q0 = 0; q0 < Q; q0 += 4) {
        const std::size_t n = std::min<std::size_t>(4, Q - q0);
        double pad[4][4];  // sx, tx, sy, ty of a last partial batch
        const double *sx = &r.sx[q0], *tx = &r.tx[q0], *sy = &r.sy[q0], *ty = &r.ty[q0];
        if (n < 4) {
            for (int lane = 0; lane < 4; ++lane) {
                const std::size_t q = q0 + std::min<std::size_t>(lane, n - 1);
                pad[0][lane] = r.sx[q];
                pad[1][lane] = r.tx[q];
                pad[2][lane] = r.sy[q];
                pad[3][lane] = r.ty[q];
            }
            sx = pad[0], tx = pad[1], sy = pad[2], ty = pad[3];
        }
        side_points4(a, ka, pa, sx, tx, A);
        side_points4(b, kb, pb, sy, ty, B);
        const Lanes4 dx = A.x[0] - B.x[0], dy = A.x[1] - B.x[1], dz = A.x[2] - B.x[2];
        const Lanes4 r2 = dx * dx + dy * dy + dz * dz;  // Eigen's squaredNorm order
        Lanes4 rr;
        lanes_sqrt(r2, rr);
        const Lanes4 ri = 1.0 / rr;
        const Lanes4 r3 = ri * ri * ri;
        // 1/r and d_i d_j / r^3 (xx, yy, zz | xy, xz, yz, 0), as accumulate takes them.
        const Lanes4 xx = r3 * dx * dx, yy = r3 * dy * dy, zz = r3 * dz * dz, xy = r3 * dx * dy, xz = r3 * dx * dz,
                     yz = r3 * dy * dz;
        for (std::size_t lane = 0; lane < n; ++lane) {
            const std::size_t q = q0 + lane;
            if (r.w[q] == 0) continue;
            double fa[max_weights], fb[max_weights];
            for (int i = 0; i < out.na; ++i) fa[i] = A.f[i][lane];
            for (int j = 0; j < out.nb; ++j) fb[j] = B.f[j][lane];
            const Lanes8 k = {ri[lane], xx[lane], yy[lane], zz[lane], xy[lane], xz[lane], yz[lane], 0.0};
            accumulate(fa, fb, r.w[q], k, out);
            if (want_k) {
                const Vec3 d(dx[lane], dy[lane], dz[lane]);
                const double f = r.w[q] * d.dot(b.normal) / (d.squaredNorm() * d.norm());
                for (int j = 0; j < 3; ++j) out.SK[j] += f * B.psi[j][lane];
            }
        }
    }
    scale_sums(a, b, out);
}

// Separated pairs: the tensor product of one triangle rule per side, each side's weights evaluated
// once per point of its own rule. For each point x of a the kernel values at all points of b are
// computed into arrays, then contracted with b's weighted functions (dot products over b's points),
// four lanes at a time with GCC vector extensions (b's points padded with zero weights to a multiple of
// four; the lanes are summed in a fixed order, so results do not depend on the thread count); a's
// weights multiply the contracted sums.
struct SidePoints {
    std::vector<double> x, y, z, w;
    std::vector<double> f;    // weight_count values per point (point-major)
    std::vector<double> wf;   // b side: w_q f_j(q), function-major (j * Qp + q), Qp = Q padded to 4
    std::vector<double> wpsi; // b side: w_q psi_j(q), function-major
};
std::size_t padded4(std::size_t n) { return (n + 3) / 4 * 4; }
void side_points(const ElementGeometry& g, const TipElementKind& k, const TriangleRule& r, SidePoints& out) {
    const int nw = weight_count(k);
    const std::size_t Q = r.size(), Qp = padded4(Q);
    out.x.assign(Qp, 0);
    out.y.assign(Qp, 0);
    out.z.assign(Qp, 0);
    out.w.assign(Qp, 0);
    out.f.assign(Qp * nw, 0);
    out.wf.assign(Qp * nw, 0);
    out.wpsi.assign(Qp * 3, 0);
    for (std::size_t q = 0; q < Qp; ++q) {
        // Padding: a copy of the last point (so r > 0) with weight 0.
        const std::size_t src = std::min(q, Q - 1);
        const TipPoint P = tip_point_inline(g, k, r.s[src], r.t[src]);
        out.x[q] = P.x.x();
        out.y[q] = P.x.y();
        out.z[q] = P.x.z();
        if (q >= Q) continue;
        out.w[q] = r.w[q];
        weights_at(k, P, &out.f[q * nw]);
        for (int j = 0; j < nw; ++j) out.wf[j * Qp + q] = r.w[q] * out.f[q * nw + j];
        for (int j = 0; j < 3; ++j) out.wpsi[j * Qp + q] = r.w[q] * P.psi[j];
    }
}
CF_AVX512_CLONE
void integrate_separated(const ElementGeometry& a, const TipElementKind& ka, const TriangleRule& ra, const ElementGeometry& b,
                         const TipElementKind& kb, const TriangleRule& rb, bool want_k, TipSums& out) {
    // The last side evaluated is kept (a surface loop pairs one crack element with every surface element).
    // The rule is recognised by its size and sample values, not its address (a temporary rule may
    // reuse the address of another).
    struct Key {
        std::array<Vec3, 3> p;
        std::array<double, 5> rule{};
        TipElementKind kind;
        static std::array<double, 5> sample(const TriangleRule& r) {
            const std::size_t n = r.size();
            return {double(n), r.s[0], r.t[0], r.w[0], r.s[n - 1] + 3 * r.t[n / 2] + 7 * r.w[n - 1]};
        }
        bool same(const ElementGeometry& g, const TipElementKind& k, const TriangleRule& r) const {
            return rule == sample(r) && p == g.p && kind.type == k.type && kind.local == k.local && kind.front == k.front &&
                   kind.chord == k.chord && kind.chord_value[0] == k.chord_value[0] && kind.chord_value[1] == k.chord_value[1] &&
                   kind.chord_value[2] == k.chord_value[2];
        }
        void set(const ElementGeometry& g, const TipElementKind& k, const TriangleRule& r) {
            p = g.p;
            rule = sample(r);
            kind = k;
        }
    };
    thread_local SidePoints A, B;
    thread_local Key key_a, key_b;
    thread_local std::vector<double> kbuf;
    if (!key_a.same(a, ka, ra)) {
        side_points(a, ka, ra, A);
        key_a.set(a, ka, ra);
    }
    if (!key_b.same(b, kb, rb)) {
        side_points(b, kb, rb, B);
        key_b.set(b, kb, rb);
    }
    const int na = out.na, nb = out.nb;
    const std::size_t P = ra.size(), Qp = B.w.size();
    kbuf.resize(8 * Qp);
    double* k = kbuf.data();  // 1/r, then d_i d_j / r^3 (xx, yy, zz, xy, xz, yz), then d.n_b / r^3
    const double nbx = b.normal.x(), nby = b.normal.y(), nbz = b.normal.z();
    for (std::size_t p = 0; p < P; ++p) {
        const double px = A.x[p], py = A.y[p], pz = A.z[p];
        for (std::size_t q = 0; q < Qp; q += 4) {
            const Lanes4 dx = px - CF_LOAD4(&B.x[q]), dy = py - CF_LOAD4(&B.y[q]), dz = pz - CF_LOAD4(&B.z[q]);
            const Lanes4 r2 = dx * dx + dy * dy + dz * dz;
            Lanes4 r;
            for (int l = 0; l < 4; ++l) r[l] = std::sqrt(r2[l]);
            const Lanes4 ri = 1.0 / r;
            const Lanes4 r3 = ri * ri * ri;
            const Lanes4 v[8] = {ri, r3 * dx * dx, r3 * dy * dy, r3 * dz * dz, r3 * dx * dy, r3 * dx * dz, r3 * dy * dz,
                                 r3 * (dx * nbx + dy * nby + dz * nbz)};
            for (int m = 0; m < 8; ++m) std::memcpy(k + m * Qp + q, &v[m], sizeof(Lanes4));
        }
        Lanes8 t[max_weights];
        for (int j = 0; j < nb; ++j) {
            const double* wf = &B.wf[j * Qp];
            Lanes4 acc[7] = {};
            for (std::size_t q = 0; q < Qp; q += 4) {
                const Lanes4 w = CF_LOAD4(wf + q);
                for (int m = 0; m < 7; ++m) acc[m] += w * CF_LOAD4(k + m * Qp + q);
            }
            t[j] = Lanes8{sum4(&acc[0]), sum4(&acc[1]), sum4(&acc[2]), sum4(&acc[3]),
                          sum4(&acc[4]), sum4(&acc[5]), sum4(&acc[6]), 0.0};
        }
        for (int i = 0; i < na; ++i) {
            const double c = A.w[p] * A.f[p * na + i];
            if (c == 0) continue;
            for (int j = 0; j < nb; ++j) out.S[i][j] += c * t[j];
        }
        if (want_k) {
            const double* kn = k + 7 * Qp;
            for (int j = 0; j < 3; ++j) {
                const double* wp = &B.wpsi[j * Qp];
                Lanes4 acc = {};
                for (std::size_t q = 0; q < Qp; q += 4) acc += CF_LOAD4(wp + q) * CF_LOAD4(kn + q);
                out.SK[j] += A.w[p] * sum4(&acc);
            }
        }
    }
    scale_sums(a, b, out);
}

// Integrates a pair with the graded Sauter-Schwab rule of its touching kind, or as separated with
// TipRules::separated on each side.
void integrate_pair(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                    bool same_mesh, const TipRules& rules, bool want_k, TipSums& s) {
    int perm_a[3] = {0, 1, 2}, perm_b[3] = {0, 1, 2};
    if (same_mesh) {
        int ia[3], ib[3], ns = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (a.nodes[i] == b.nodes[j]) { ia[ns] = i; ib[ns] = j; ++ns; }
        const PairRule* r = nullptr;
        const bool general = ka.type == TipElementKind::general || kb.type == TipElementKind::general;
        if (ns == 3) {
            for (int k = 0; k < 3; ++k) perm_b[k] = ib[k];
            r = &rules.id;
        } else if (ns == 2) {
            perm_a[0] = ia[0]; perm_a[1] = ia[1]; perm_a[2] = 3 - ia[0] - ia[1];
            perm_b[0] = ib[0]; perm_b[1] = ib[1]; perm_b[2] = 3 - ib[0] - ib[1];
            r = general ? &rules.general_edge : &rules.edge;
        } else if (ns == 1) {
            perm_a[0] = ia[0]; perm_a[1] = ia[0] == 0 ? 1 : 0; perm_a[2] = ia[0] == 2 ? 1 : 2;
            perm_b[0] = ib[0]; perm_b[1] = ib[0] == 0 ? 1 : 0; perm_b[2] = ib[0] == 2 ? 1 : 2;
            r = general ? &rules.general_vert : &rules.vert;
        }
        if (r) {
            integrate(a, ka, perm_a, b, kb, perm_b, *r, want_k, s);
            return;
        }
    }
    const double rho = separation_ratio(a, b);
    integrate_separated(a, ka, rules.separated(ka, rho), b, kb, rules.separated(kb, rho), want_k, s);
}

Mat3 cross_matrix(const Vec3& c) {
    Mat3 X;
    X << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0;
    return X;
}

Mat3 kernel_p(double I1, const double* R, const ElasticConstants& c) {
    const double kp = 1.0 / (8 * M_PI * (1 - c.nu));
    Mat3 P;
    P << R[0], R[3], R[4], R[3], R[1], R[5], R[4], R[5], R[2];
    P *= kp;
    P.diagonal().array() += kp * (1 - 2 * c.nu) * I1;
    return P;
}

// mu/(4 pi) I1 (2 (u.v) I - u v^T) + 2 mu [u]_x P [v]_x: the D block of two constant curls u, v
// (local_blocks.cpp), here with weighted kernel integrals.
Mat3 hyper_block(const Vec3& u, const Vec3& v, double I1, const Mat3& P, const ElasticConstants& c) {
    const double g = c.mu / (4 * M_PI) * I1;
    Mat3 B = (2 * c.mu) * cross_matrix(u) * P * cross_matrix(v);
    B.noalias() -= g * (u * v.transpose());
    B.diagonal().array() += 2 * g * u.dot(v);
    return B;
}

// The curl of psi_alpha as a sum of (weight index, constant vector) terms (weights_at's order).
struct CurlTerms {
    int n = 0;
    int weight[4];
    Vec3 v[4];
};
CurlTerms curl_terms(const ElementGeometry& g, const TipElementKind& k, int alpha) {
    CurlTerms t;
    t.weight[0] = 0;
    t.v[0] = g.curl[alpha];
    t.n = 1;
    if (k.type == TipElementKind::edge || k.type == TipElementKind::vertex) {
        t.weight[1] = 1 + alpha;
        t.v[1] = rho_curl(g, k);
        t.n = 2;
    } else if (k.type == TipElementKind::general) {
        for (int i = 0; i < 3; ++i) {
            t.weight[1 + i] = 1 + 3 * alpha + i;
            t.v[1 + i] = g.curl[i];
        }
        t.n = 4;
    }
    return t;
}

void blocks_from_sums(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                      const TipSums& s, const ElasticConstants& c, bool want_k, TipPairBlocks& out) {
    CurlTerms ta[3], tb[3];
    for (int al = 0; al < 3; ++al) ta[al] = curl_terms(a, ka, al);
    for (int be = 0; be < 3; ++be) tb[be] = curl_terms(b, kb, be);
    // P depends only on the weight pair; a weight index occurs in up to three (al, be) blocks, so
    // it is evaluated once per pair here (the same values as evaluating it in the loops below).
    Mat3 P[max_weights][max_weights];
    for (int i = 0; i < s.na; ++i)
        for (int j = 0; j < s.nb; ++j) P[i][j] = kernel_p(s.S1(i, j), s.SR(i, j), c);
    for (int al = 0; al < 3; ++al)
        for (int be = 0; be < 3; ++be) {
            Mat3 B = Mat3::Zero();
            for (int i = 0; i < ta[al].n; ++i)
                for (int j = 0; j < tb[be].n; ++j) {
                    const int wi = ta[al].weight[i], wj = tb[be].weight[j];
                    B += hyper_block(ta[al].v[i], tb[be].v[j], s.S1(wi, wj), P[wi][wj], c);
                }
            out.H[al][be] = B;
        }
    if (want_k) {
        // a is a plain P0 test element: weight index 0 only on its side.
        for (int be = 0; be < 3; ++be) {
            Mat3 K = Mat3::Zero();
            for (int j = 0; j < tb[be].n; ++j) {
                const int wj = tb[be].weight[j];
                K += P[0][wj] * cross_matrix(tb[be].v[j]);
            }
            K.diagonal().array() += s.SK[be] / (4 * M_PI);
            out.Kb[be] = K;
        }
    }
}

void tip_pair_blocks_with(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                          bool same_mesh, const TipRules& rules, const ElasticConstants& c, bool want_k, TipPairBlocks& out) {
    TipSums s(weight_count(ka), weight_count(kb));
    integrate_pair(a, ka, b, kb, same_mesh, rules, want_k, s);
    blocks_from_sums(a, ka, b, kb, s, c, want_k, out);
}

}  // namespace

void tip_pair_blocks(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                     bool same_mesh, int n, const ElasticConstants& c, bool want_k, TipPairBlocks& out) {
    const TipRules& rules = shared_tip_rules(n);
    tip_pair_blocks_with(a, ka, b, kb, same_mesh, rules, c, want_k, out);
}

double tip_pair_scalar(const ElementGeometry& a, const TipElementKind& ka, int fa, const ElementGeometry& b,
                       const TipElementKind& kb, int fb, bool same_mesh, int n) {
    const TipRules& rules = shared_tip_rules(n);
    TipSums s(weight_count(ka), weight_count(kb));
    integrate_pair(a, ka, b, kb, same_mesh, rules, false, s);
    return s.S1(fa, fb);
}

double tip_separated_scalar(const ElementGeometry& a, const TipElementKind& ka, int fa, const TriangleRule& ra,
                            const ElementGeometry& b, const TipElementKind& kb, int fb, const TriangleRule& rb) {
    TipSums s(weight_count(ka), weight_count(kb));
    integrate_separated(a, ka, ra, b, kb, rb, false, s);
    return s.S1(fa, fb);
}

namespace {

// tip_crack_operators' steps, in the order it calls them.

// Where an element is: its node ids and positions (what its corrections depend on besides the kind).
struct Place {
    Tri nodes{};
    std::array<Vec3, 3> p;
    explicit Place(const ElementGeometry& g) : nodes(g.nodes), p(g.p) {}
    Place() = default;
};
bool same_place(const Place& x, const ElementGeometry& y) { return x.nodes == y.nodes && x.p == y.p; }

}  // namespace

// The square-root corrections of one step, kept for the next: an element's or a pair's correction
// depends only on the geometry and kinds involved (the surface is the same as long as its blocks
// are reused), so elements whose kind did not change (a front that stood still) are not integrated
// again. Entries are immutable and shared between steps.
struct TipCache {
    // Surface columns of one crack element b: W and X rows of every surface element / node against b's
    // three nodes (tip minus P1).
    struct Columns {
        Place where;
        TipElementKind kind;
        Matrix W, X;  // 3 M x 9, 3 N x 9
    };
    // One crack pair, owned by b (the touched element of larger index): D[al][be] goes to
    // HY(nodes(a)[al], nodes(b)[be]). It holds for the kinds of a and b in `kind` below and their
    // places in the geometry of the operators this cache belongs to: an entry is either integrated
    // for them or kept because they did not change. (Kinds and places per pair made an entry 1 KiB
    // instead of 664 bytes: 374 MB of cube_compressive's 657 MB peak.)
    struct Pair {
        std::array<std::array<Mat3, 3>, 3> D;
    };
    const SurfaceOperators* surface = nullptr;
    std::vector<TipElementKind> kind;  // per crack element of the step this cache belongs to
    std::map<int, std::shared_ptr<const Columns>> columns;
    // Sorted by key (b, a): built in that order each step and read back with a cursor, so a step with
    // hundreds of thousands of kept pairs costs no tree of them.
    std::vector<std::pair<std::pair<int, int>, std::shared_ptr<const Pair>>> pairs;

    // Every kept pair costs a reference count taken here and released with the cache of the step
    // before, each a cache miss on a control block scattered over the heap (300 k a step in
    // cube_compressive, 2.8 % of its CPU); both passes go in order and fetch the control block of
    // an entry a few places ahead.
    static void prefetch_count(const std::shared_ptr<const Pair>& p) {
        // make_shared puts the counts just before the object.
        if (p) __builtin_prefetch(reinterpret_cast<const char*>(p.get()) - 8, 1);
    }
    static constexpr std::size_t kAhead = 16;
    ~TipCache() {
        for (std::size_t i = 0; i < pairs.size(); ++i) {
            if (i + kAhead < pairs.size()) prefetch_count(pairs[i + kAhead].second);
            pairs[i].second.reset();
        }
    }
};

namespace {

// The rules of the square-root pair integrals: two more points per direction than the P1 rules on
// touching pairs (graded rules converge more slowly: n = 5 / 7 / 9 gave front-average K_I errors of
// 0.96 / 0.52 / 0.42 % on the 294-triangle penny crack).
const TipRules& tip_rules_for(const SurfaceOperators& surface) {
    return shared_tip_rules(surface.options.quadrature.singular_order + 2);
}

// Bytes of kept corrections: 9 columns of W and X per front element, 81 numbers per crack pair.
double correction_bytes(const SurfaceOperators& surface, std::size_t front_elements, std::size_t crack_pairs) {
    return 8.0 * (9.0 * double(front_elements) * 3.0 * double(surface.geometry.size() + surface.mesh.num_vertices()) +
                  81.0 * double(crack_pairs));
}

// Surface columns of crack element b, empty (zero) for every surface element / node.
std::shared_ptr<TipCache::Columns> empty_columns(const SurfaceOperators& surface, const ElementGeometry& gb, const TipElementKind& kb) {
    auto c = std::make_shared<TipCache::Columns>();
    c->where = Place(gb);
    c->kind = kb;
    c->W = Matrix::Zero(3 * static_cast<Eigen::Index>(surface.geometry.size()), 9);
    c->X = Matrix::Zero(3 * static_cast<Eigen::Index>(surface.mesh.num_vertices()), 9);
    return c;
}

// Surface element a's part of b's columns: its square-root blocks in, its P1 blocks `p1` out.
void add_surface_correction(TipCache::Columns& c, const SurfaceOperators& surface, std::size_t a, const ElementGeometry& gb,
                            const TipElementKind& kb, const TipRules& rules, const PairBlocks& p1) {
    const ElementGeometry& ga = surface.geometry[a];
    const TipElementKind plain;
    TipPairBlocks tip;
    tip_pair_blocks_with(ga, plain, gb, kb, false, rules, surface.elastic, true, tip);
    for (int be = 0; be < 3; ++be) {
        c.W.block<3, 3>(3 * a, 3 * be) += tip.Kb[be] - p1.Kb[be];
        for (int al = 0; al < 3; ++al) c.X.block<3, 3>(3 * ga.nodes[al], 3 * be) += tip.H[al][be] - p1.H[al][be];
    }
}

// Every surface element against crack element b, in order.
std::shared_ptr<const TipCache::Columns> surface_columns(const SurfaceOperators& surface, const ElementGeometry& gb,
                                                         const TipElementKind& kb, const TipRules& rules,
                                                         const PairQuadrature& quad) {
    auto c = empty_columns(surface, gb, kb);
    PairBlocks blk;
    for (std::size_t a = 0; a < surface.geometry.size(); ++a) {
        const PairIntegrals p = pair_integrals(surface.geometry[a], gb, false, quad);
        pair_blocks(surface.geometry[a], gb, p, surface.elastic, false, blk);
        add_surface_correction(*c, surface, a, gb, kb, rules, blk);
    }
    return c;
}

// Crack pair (a, b) owned by b, with its P1 blocks `p1` (of the pair (min, max)).
void pair_correction(const std::vector<ElementGeometry>& gc, const TipBasis& basis, int a, int b, const ElasticConstants& ec,
                     const TipRules& rules, const PairBlocks& p1, TipCache::Pair& c) {
    const int lo = std::min(a, b), hi = std::max(a, b);
    TipPairBlocks tip;
    tip_pair_blocks_with(gc[lo], basis.kind[lo], gc[hi], basis.kind[hi], true, rules, ec, false, tip);
    const double half = a == b ? 0.5 : 1.0;
    for (int al = 0; al < 3; ++al)
        for (int be = 0; be < 3; ++be) {
            const Mat3 d = half * (tip.H[al][be] - p1.H[al][be]);  // rows lo's node al, columns hi's node be
            if (a == lo) c.D[al][be] = d;
            else c.D[be][al] = d.transpose();
        }
}

// Crack pair (a, b) owned by b, its P1 blocks integrated here.
std::shared_ptr<const TipCache::Pair> integrated_pair_correction(const std::vector<ElementGeometry>& gc, const TipBasis& basis, int a,
                                                                 int b, const ElasticConstants& ec, const TipRules& rules,
                                                                 const PairQuadrature& quad) {
    auto c = std::make_shared<TipCache::Pair>();
    const int lo = std::min(a, b), hi = std::max(a, b);
    PairBlocks blk;
    const PairIntegrals p = pair_integrals(gc[lo], gc[hi], true, quad);
    pair_blocks(gc[lo], gc[hi], p, ec, false, blk);
    pair_correction(gc, basis, a, b, ec, rules, blk, *c);
    return c;
}

}  // namespace

// The corrections of the pairs with a new element, made as the append hands over their P1 blocks.
struct TipCorrectionsOfAppend::Impl {
    Impl(const SurfaceOperators& s, const SurfaceMesh& cracks)
        : surface(s), basis(tip_basis(cracks)), rules(tip_rules_for(s)),
          crack_vertices(cracks.num_vertices()) {}
    const SurfaceOperators& surface;
    const TipBasis basis;
    const TipRules& rules;
    const std::size_t crack_vertices;
    const std::vector<ElementGeometry>* gc = nullptr;
    std::size_t first = 0;
    std::vector<std::shared_ptr<TipCache::Columns>> columns;                 // [b - first], front elements b
    std::vector<std::vector<std::shared_ptr<TipCache::Pair>>> pairs;         // [hi - first][lo], pairs with a front element

    bool front(std::size_t e) const { return basis.kind[e].type != TipElementKind::plain; }
    std::shared_ptr<const TipCache::Columns> column(std::size_t b) const {
        return b >= first && b - first < columns.size() ? columns[b - first] : nullptr;
    }
    std::shared_ptr<const TipCache::Pair> pair(std::size_t lo, std::size_t hi) const {
        return hi >= first && hi - first < pairs.size() && lo < pairs[hi - first].size() ? pairs[hi - first][lo] : nullptr;
    }
};

TipCorrectionsOfAppend::TipCorrectionsOfAppend(const SurfaceOperators& surface, const SurfaceMesh& cracks)
    : impl_(std::make_unique<Impl>(surface, cracks)) {}
TipCorrectionsOfAppend::~TipCorrectionsOfAppend() = default;

void TipCorrectionsOfAppend::begin(const std::vector<ElementGeometry>& crack_geometry, std::size_t first_new) {
    Impl& m = *impl_;
    if (crack_geometry.size() != m.basis.kind.size())
        throw std::logic_error("TipCorrectionsOfAppend: made for " + std::to_string(m.basis.kind.size()) + " crack elements, the append has " +
                               std::to_string(crack_geometry.size()));
    // Their share of the budget tip_crack_operators checks (which counts the kept ones too), before any is made.
    std::size_t front_new = 0, pairs = 0, front_before = 0;
    for (std::size_t e = 0; e < crack_geometry.size(); ++e) {
        if (e >= first_new) {
            front_new += m.front(e) ? 1 : 0;
            pairs += m.front(e) ? e + 1 : front_before;  // (a, e), a <= e, with a front element
        }
        front_before += m.front(e) ? 1 : 0;
    }
    const SurfaceOperators& s = m.surface;
    check_memory_budget(2 * crack_operator_bytes(s.mesh.num_triangles(), s.mesh.num_vertices(), m.crack_vertices) +
                            correction_bytes(s, front_new, pairs),
                        s.options.memory_budget_bytes,
                        "square-root crack-front elements for " + std::to_string(front_new) + " new front elements");
    m.gc = &crack_geometry;
    m.first = first_new;
    m.columns.assign(crack_geometry.size() - first_new, nullptr);
    m.pairs.assign(crack_geometry.size() - first_new, {});
    for (std::size_t b = first_new; b < crack_geometry.size(); ++b) m.pairs[b - first_new].resize(b + 1);
}

void TipCorrectionsOfAppend::surface_pair(int b, int a, const PairBlocks& p1) {
    Impl& m = *impl_;
    if (!m.front(std::size_t(b))) return;
    std::shared_ptr<TipCache::Columns>& c = m.columns[std::size_t(b) - m.first];
    if (a == 0) c = empty_columns(m.surface, (*m.gc)[std::size_t(b)], m.basis.kind[std::size_t(b)]);
    add_surface_correction(*c, m.surface, std::size_t(a), (*m.gc)[std::size_t(b)], m.basis.kind[std::size_t(b)], m.rules, p1);
}

void TipCorrectionsOfAppend::crack_pair(int a, int b, const PairBlocks& p1) {
    Impl& m = *impl_;
    const bool fa = m.front(std::size_t(a)), fb = m.front(std::size_t(b));
    if (!fa && !fb) return;
    // Owned by the front element of larger index (tip_crack_operators' keys).
    const int owner = fb ? b : a, other = fb ? a : b;
    auto c = std::make_shared<TipCache::Pair>();
    pair_correction(*m.gc, m.basis, other, owner, m.surface.elastic, m.rules, p1, *c);
    m.pairs[std::size_t(b) - m.first][std::size_t(a)] = std::move(c);
}

namespace {

// int psi_a per element (face loads): a third of the area on plain elements, a collapsed Gauss
// rule on the others.
std::vector<std::array<double, 3>> basis_integrals(const std::vector<ElementGeometry>& gc, const TipBasis& basis) {
    const TriangleRule tr = collapsed_gauss_triangle_rule(8, true);
    std::vector<std::array<double, 3>> out(gc.size(), {0, 0, 0});
    for (std::size_t e = 0; e < gc.size(); ++e) {
        if (basis.kind[e].type == TipElementKind::plain) {
            out[e] = {gc[e].area / 3, gc[e].area / 3, gc[e].area / 3};
            continue;
        }
        for (std::size_t q = 0; q < tr.size(); ++q) {
            const TipPoint P = tip_point(gc[e], basis.kind[e], tr.s[q], tr.t[q]);
            for (int i = 0; i < 3; ++i) out[e][i] += tr.w[q] * P.psi[i] * 2 * gc[e].area;
        }
    }
    return out;
}

// Which blocks of the step before can start this step's: every block is P1 plus the corrections
// that touch it, added in a fixed order (element, then pair key), so a block where neither the P1
// block nor the list of corrections touching it changed is bit for bit the previous step's, and only
// the others need the P1 block copied and their corrections added again. A node's column (W, X, HY)
// is rebuilt when the node is new, lies on a new element (its P1 column grew) or on an element whose
// surface columns changed; a single HY block (i, j) when a crack pair touching it changed.
class ChangedBlocks {
public:
    // Everything rebuilt (no usable step before).
    explicit ChangedBlocks(std::size_t nodes) : column_(nodes, 1), nodes_(nodes) {}
    ChangedBlocks(const CrackOperators& p1, const CrackOperators& previous, const TipCache& old, const TipCache& now)
        : column_(p1.cracks.num_vertices(), 0), nodes_(p1.cracks.num_vertices()),
          old_nodes_(previous.cracks.num_vertices()), pair_(nodes_ * old_nodes_ / 64 + 1, 0) {
        const auto& gc = p1.geometry;
        for (std::size_t n = old_nodes_; n < nodes_; ++n) column_[n] = 1;
        for (std::size_t e = previous.geometry.size(); e < gc.size(); ++e)
            for (int v : gc[e].nodes) column_[std::size_t(v)] = 1;
        auto changed_element = [&](int b) {
            for (int v : gc[std::size_t(b)].nodes) column_[std::size_t(v)] = 1;
        };
        for (const auto& [b, c] : now.columns) {
            const auto it = old.columns.find(b);
            if (it == old.columns.end() || it->second != c) changed_element(b);
        }
        for (const auto& [b, c] : old.columns)
            if (!now.columns.count(b)) changed_element(b);
        // Both pair lists are sorted by key: a pair stands when the same entry is under the same key.
        auto mark_pair = [&](const std::pair<int, int>& key) {
            const Tri& nb = gc[std::size_t(key.first)].nodes;
            const Tri& na = gc[std::size_t(key.second)].nodes;
            for (int i : na)
                for (int j : nb) mark(std::size_t(i), std::size_t(j));
        };
        std::size_t q = 0;
        for (const auto& [key, entry] : old.pairs) {
            while (q < now.pairs.size() && now.pairs[q].first < key) {
                mark_pair(now.pairs[q].first);  // a pair without a predecessor
                ++q;
            }
            if (q < now.pairs.size() && now.pairs[q].first == key) {
                if (now.pairs[q].second != entry) mark_pair(key);
                ++q;
            } else {
                mark_pair(key);  // a pair gone
            }
        }
        for (; q < now.pairs.size(); ++q) mark_pair(now.pairs[q].first);
    }
    bool column(std::size_t n) const { return column_[n] != 0; }
    // HY block (i, j) (block row i, block column j).
    bool block(std::size_t i, std::size_t j) const {
        if (column_[j]) return true;
        if (i >= old_nodes_) return true;
        const std::size_t k = i * nodes_ + j;
        return (pair_[k >> 6] >> (k & 63)) & 1;
    }
    std::size_t old_nodes() const { return old_nodes_; }

private:
    void mark(std::size_t i, std::size_t j) {
        if (i >= old_nodes_ || column_[j]) return;
        const std::size_t k = i * nodes_ + j;
        pair_[k >> 6] |= std::uint64_t(1) << (k & 63);
    }
    std::vector<char> column_;
    std::size_t nodes_ = 0, old_nodes_ = 0;
    std::vector<std::uint64_t> pair_;
};

// Whether `previous` (square-root blocks of the step before, on the same surface) was built on the P1
// blocks that `p1` extends: the same leading elements, no fewer nodes.
bool extends(const CrackOperators& p1, const CrackOperators& previous) {
    if (!previous.tip_elements || previous.geometry.size() > p1.geometry.size() ||
        previous.cracks.num_vertices() > p1.cracks.num_vertices() || previous.W.rows() != p1.W.rows() ||
        previous.X.rows() != p1.X.rows())
        return false;
    for (std::size_t e = 0; e < previous.geometry.size(); ++e)
        if (previous.geometry[e].nodes != p1.geometry[e].nodes || previous.geometry[e].p != p1.geometry[e].p) return false;
    return true;
}

// The dense blocks to start from: P1's where they changed, the step before's elsewhere (in parallel over
// columns; each entry copied once).
void start_blocks(const CrackOperators& p1, const CrackOperators* previous, const ChangedBlocks& changed, CrackOperators& out) {
    const Eigen::Index nodes = static_cast<Eigen::Index>(p1.cracks.num_vertices());
    out.W.resize(p1.W.rows(), p1.W.cols());
    out.X.resize(p1.X.rows(), p1.X.cols());
    out.HY.resize(p1.HY.rows(), p1.HY.cols());
    const Eigen::Index old_rows = 3 * static_cast<Eigen::Index>(changed.old_nodes());
    tbb::parallel_for(Eigen::Index(0), nodes, [&](Eigen::Index n) {
        const Eigen::Index c = 3 * n;
        if (!previous || changed.column(std::size_t(n))) {
            out.W.middleCols<3>(c) = p1.W.middleCols<3>(c);
            out.X.middleCols<3>(c) = p1.X.middleCols<3>(c);
            out.HY.middleCols<3>(c) = p1.HY.middleCols<3>(c);
            return;
        }
        out.W.middleCols<3>(c) = previous->W.middleCols<3>(c);
        out.X.middleCols<3>(c) = previous->X.middleCols<3>(c);
        out.HY.block(0, c, old_rows, 3) = previous->HY.block(0, c, old_rows, 3);
        out.HY.block(old_rows, c, out.HY.rows() - old_rows, 3) = p1.HY.block(old_rows, c, out.HY.rows() - old_rows, 3);
        for (std::size_t i = 0; i < changed.old_nodes(); ++i)
            if (changed.block(i, std::size_t(n))) out.HY.block<3, 3>(3 * Eigen::Index(i), c) = p1.HY.block<3, 3>(3 * Eigen::Index(i), c);
    });
}

}  // namespace

std::shared_ptr<const CrackOperators> tip_crack_operators(const SurfaceOperators& surface, const CrackOperators& p1,
                                                          const CrackOperators* previous, const TipCorrectionsOfAppend* appended) {
    const TipCorrectionsOfAppend::Impl* from_append = appended ? &appended->impl() : nullptr;
    if (from_append && from_append->gc != &p1.geometry)
        throw std::logic_error("tip_crack_operators: the corrections handed over were made during another append than the one that "
                               "made these P1 blocks");
    // A second copy of the crack blocks beside the append-only P1 ones.
    check_memory_budget(2 * crack_operator_bytes(surface.mesh.num_triangles(), surface.mesh.num_vertices(), p1.cracks.num_vertices()),
                        surface.options.memory_budget_bytes,
                        "square-root crack-front elements for " + std::to_string(p1.cracks.num_vertices()) +
                            " crack nodes (front_elements: square_root keeps a second copy of the crack blocks)");
    // The append's observer made the basis of this very mesh already.
    const TipBasis own_basis = from_append ? TipBasis{} : tip_basis(p1.cracks);
    const TipBasis& basis = from_append ? from_append->basis : own_basis;
    const auto& gc = p1.geometry;
    std::vector<int> touched;
    for (std::size_t e = 0; e < gc.size(); ++e)
        if (basis.kind[e].type != TipElementKind::plain) touched.push_back(static_cast<int>(e));
    std::vector<char> is_touched(gc.size(), 0);
    for (int e : touched) is_touched[e] = 1;
    const TipRules& rules = tip_rules_for(surface);
    const PairQuadrature& quad = shared_pair_quadrature(surface.options.quadrature);
    const TipCache* old = previous && previous->tip_cache && previous->tip_cache->surface == &surface ? previous->tip_cache.get() : nullptr;
    auto cache = std::make_shared<TipCache>();
    cache->surface = &surface;
    cache->kind = basis.kind;

    // Which corrections are new: every touched element's surface columns, and every crack pair with a
    // touched element (owned by the touched one of larger index), unless the previous step has them.
    std::vector<int> fresh_columns;
    for (int b : touched) {
        const auto it = old ? old->columns.find(b) : decltype(old->columns.end()){};
        if (old && it != old->columns.end() && same_tip_kind(it->second->kind, basis.kind[b]) && same_place(it->second->where, gc[b]))
            cache->columns[b] = it->second;
        else
            fresh_columns.push_back(b);
    }
    std::vector<std::size_t> fresh_pairs;  // indices into cache->pairs, whose entries are filled below
    // When p1 extends the blocks of the step before, every element kept its place (the leading
    // elements are checked equal), so a kept pair needs only its kinds compared.
    const bool from_previous = old && extends(p1, *previous);
    // The pairs (b, a) of each touched element b, a ascending, in b's order: the sorted list. Touched
    // b = touched[t] owns every a but the touched ones above it, so its entries start at a known offset
    // and each b's are written in place on its own task, from its own cursor into old->pairs (sorted the
    // same way): 300 k entries a step in cube_compressive, a serial pass of shared-pointer copies before.
    using PairEntry = std::pair<std::pair<int, int>, std::shared_ptr<const TipCache::Pair>>;
    std::vector<std::size_t> first_pair(touched.size() + 1, 0);
    for (std::size_t t = 0; t < touched.size(); ++t) first_pair[t + 1] = first_pair[t] + gc.size() - (touched.size() - 1 - t);
    cache->pairs.resize(first_pair.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, touched.size(), 8), [&](const tbb::blocked_range<std::size_t>& rg) {
        for (std::size_t t = rg.begin(); t != rg.end(); ++t) {
            const int b = touched[t];
            std::size_t out = first_pair[t];
            std::size_t cursor = 0;
            if (old)
                cursor = std::size_t(std::lower_bound(old->pairs.begin(), old->pairs.end(), std::pair<int, int>(b, 0),
                                                      [](const PairEntry& e, const std::pair<int, int>& k) { return e.first < k; }) -
                                     old->pairs.begin());
            for (std::size_t ai = 0; ai < gc.size(); ++ai) {
                const int a = static_cast<int>(ai);
                if (is_touched[a] && a > b) continue;  // that pair is a's
                const std::pair<int, int> key(b, a);
                std::shared_ptr<const TipCache::Pair> kept;
                if (old) {
                    while (cursor < old->pairs.size() && old->pairs[cursor].first < key) ++cursor;
                    if (cursor + TipCache::kAhead < old->pairs.size()) TipCache::prefetch_count(old->pairs[cursor + TipCache::kAhead].second);
                    // A pair of the step before has both elements from then (indices below its size); their
                    // places then are in `previous`, whose cache `old` is.
                    const auto& was = previous->geometry;
                    if (cursor < old->pairs.size() && old->pairs[cursor].first == key &&
                        same_tip_kind(old->kind[std::size_t(a)], basis.kind[a]) && same_tip_kind(old->kind[std::size_t(b)], basis.kind[b]) &&
                        (from_previous || (same_place(Place(was[std::size_t(a)]), gc[a]) && same_place(Place(was[std::size_t(b)]), gc[b]))))
                        kept = old->pairs[cursor].second;
                }
                cache->pairs[out++] = PairEntry(key, std::move(kept));
            }
        }
    });
    for (std::size_t q = 0; q < cache->pairs.size(); ++q)
        if (!cache->pairs[q].second) fresh_pairs.push_back(q);
    const double cache_bytes = correction_bytes(surface, touched.size(), cache->pairs.size());
    check_memory_budget(2 * crack_operator_bytes(surface.mesh.num_triangles(), surface.mesh.num_vertices(), p1.cracks.num_vertices()) +
                            cache_bytes,
                        surface.options.memory_budget_bytes,
                        "square-root crack-front elements for " + std::to_string(touched.size()) +
                            " front elements (their corrections are kept for the next step)");
    if (old && fresh_columns.empty() && fresh_pairs.empty() && previous->cracks.num_triangles() == p1.cracks.num_triangles() &&
        cache->columns.size() == old->columns.size() && cache->pairs.size() == old->pairs.size()) {
        // The front stood still everywhere and no element joined: the previous blocks are these.
        auto same = std::make_shared<CrackOperators>(*previous);
        same->tip_pairs_computed = 0;
        same->tip_pairs_in_append = 0;
        same->tip_pairs_reused = static_cast<std::int64_t>(touched.size() * surface.geometry.size() + cache->pairs.size());
        return same;
    }
    // P1's members without its dense blocks (start_blocks fills those).
    auto out = std::make_shared<CrackOperators>();
    out->cracks = p1.cracks;
    out->geometry = p1.geometry;
    out->pairs_computed = p1.pairs_computed;
    out->pairs_computed_last = p1.pairs_computed_last;
    out->tip_elements = true;
    // Integrate the new ones in parallel, each into its own entry.
    std::vector<std::shared_ptr<const TipCache::Columns>> new_columns(fresh_columns.size());
    std::vector<std::shared_ptr<const TipCache::Pair>> new_pairs(fresh_pairs.size());
    std::vector<char> in_append(fresh_columns.size() + fresh_pairs.size(), 0);  // taken from the append's observer
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, fresh_columns.size() + fresh_pairs.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                          for (std::size_t i = rg.begin(); i != rg.end(); ++i) {
                              if (i < fresh_columns.size()) {
                                  const int b = fresh_columns[i];
                                  if (from_append && (new_columns[i] = from_append->column(std::size_t(b)))) {
                                      in_append[i] = 1;
                                      continue;
                                  }
                                  new_columns[i] = surface_columns(surface, gc[b], basis.kind[b], rules, quad);
                              } else {
                                  const auto& ba = cache->pairs[fresh_pairs[i - fresh_columns.size()]].first;
                                  const auto [lo, hi] = std::minmax(ba.first, ba.second);
                                  std::shared_ptr<const TipCache::Pair>& slot = new_pairs[i - fresh_columns.size()];
                                  if (from_append && (slot = from_append->pair(std::size_t(lo), std::size_t(hi)))) {
                                      in_append[i] = 1;
                                      continue;
                                  }
                                  slot = integrated_pair_correction(gc, basis, ba.second, ba.first, surface.elastic, rules, quad);
                              }
                          }
                      });
    for (std::size_t i = 0; i < fresh_columns.size(); ++i) cache->columns[fresh_columns[i]] = new_columns[i];
    for (std::size_t i = 0; i < fresh_pairs.size(); ++i) cache->pairs[fresh_pairs[i]].second = new_pairs[i];
    const ChangedBlocks changed = from_previous ? ChangedBlocks(p1, *previous, *old, *cache) : ChangedBlocks(p1.cracks.num_vertices());
    start_blocks(p1, from_previous ? previous : nullptr, changed, *out);
    // Add every correction in a fixed order (element, then pair key), whatever was integrated now, to
    // the blocks rebuilt from P1 (the others hold the same sums from the step before).
    // In parallel over fixed row ranges (each entry is summed by one task in that same order, so
    // the blocks do not depend on the thread count): done one after the other, these adds were
    // 4 % of cube_compressive's run on one core while the other waited.
    auto add_columns = [&](Matrix& dst, Matrix TipCache::Columns::*part) {
        constexpr Eigen::Index kRows = 512;
        tbb::parallel_for(Eigen::Index(0), (dst.rows() + kRows - 1) / kRows, [&](Eigen::Index chunk) {
            const Eigen::Index r0 = chunk * kRows, n = std::min(kRows, dst.rows() - r0);
            for (const auto& kv : cache->columns)
                for (int be = 0; be < 3; ++be)
                    if (changed.column(std::size_t(gc[kv.first].nodes[be])))
                        dst.block(r0, 3 * gc[kv.first].nodes[be], n, 3) += ((*kv.second).*part).block(r0, 3 * be, n, 3);
        });
    };
    add_columns(out->W, &TipCache::Columns::W);
    add_columns(out->X, &TipCache::Columns::X);
    // HY by ranges of a's nodes (block rows): each (pair, a's local node) listed once under its
    // range, in pair order, so every block row is summed in the order above by one task.
    constexpr int kNodes = 128;
    const int crack_nodes = static_cast<int>(p1.cracks.num_vertices());
    std::vector<std::vector<std::pair<std::uint32_t, int>>> rows_of((crack_nodes + kNodes - 1) / kNodes);
    // Only (pair, node) whose blocks are rebuilt: late in a run nearly all are kept from the step before.
    for (std::size_t q = 0; q < cache->pairs.size(); ++q) {
        const ElementGeometry& ga = gc[cache->pairs[q].first.second];
        const ElementGeometry& gb = gc[cache->pairs[q].first.first];
        for (int al = 0; al < 3; ++al) {
            const std::size_t i = std::size_t(ga.nodes[al]);
            if (changed.block(i, std::size_t(gb.nodes[0])) || changed.block(i, std::size_t(gb.nodes[1])) ||
                changed.block(i, std::size_t(gb.nodes[2])))
                rows_of[i / kNodes].emplace_back(std::uint32_t(q), al);
        }
    }
    tbb::parallel_for(std::size_t(0), rows_of.size(), [&](std::size_t chunk) {
        for (const auto& [q, al] : rows_of[chunk]) {
            const auto& kv = cache->pairs[q];
            const ElementGeometry& gb = gc[kv.first.first];
            const ElementGeometry& ga = gc[kv.first.second];
            for (int be = 0; be < 3; ++be)
                if (changed.block(std::size_t(ga.nodes[al]), std::size_t(gb.nodes[be])))
                    out->HY.block<3, 3>(3 * ga.nodes[al], 3 * gb.nodes[be]) += kv.second->D[al][be];
        }
    });
    out->tip_pairs_computed = static_cast<std::int64_t>(fresh_columns.size() * surface.geometry.size() + fresh_pairs.size());
    for (std::size_t i = 0; i < in_append.size(); ++i)
        if (in_append[i]) out->tip_pairs_in_append += i < fresh_columns.size() ? static_cast<std::int64_t>(surface.geometry.size()) : 1;
    out->tip_pairs_reused = static_cast<std::int64_t>((touched.size() - fresh_columns.size()) * surface.geometry.size() +
                                                      (cache->pairs.size() - fresh_pairs.size()));
    out->tip_cache = cache;
    out->basis_integral = basis_integrals(gc, basis);
    return out;
}

std::vector<FrontEdgeSif> tip_element_sifs(const SurfaceMesh& cracks, const std::vector<Vec3>& coef, double E, double nu) {
    if (coef.size() != cracks.num_vertices())
        throw std::invalid_argument("square-root front coefficients (" + std::to_string(coef.size()) +
                                    ") do not match the crack mesh (" + std::to_string(cracks.num_vertices()) +
                                    " vertices); solve with tip elements");
    const TipBasis basis = tip_basis(cracks);
    std::map<std::pair<int, int>, std::vector<int>> edge_tris;
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = cracks.triangles[t][k], b = cracks.triangles[t][(k + 1) % 3];
            edge_tris[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
        }
    const double c12 = E / (8 * (1 - nu * nu)), c3 = E / (8 * (1 + nu));
    std::vector<FrontEdgeSif> out;
    for (const auto& e : edge_tris) {
        if (e.second.size() != 1) continue;
        FrontEdgeSif s;
        s.v0 = e.first.first;
        s.v1 = e.first.second;
        const int third = front_edge_frame(cracks, e.second[0], s.v0, s.v1, s.e1, s.e2, s.e3);
        s.interior = third;
        // Height of the front triangle over its front edge: rho = d / H on it.
        s.d = (cracks.vertices[s.v0] - cracks.vertices[third]).dot(s.e1);
        if (!(s.d > 0))
            throw std::invalid_argument("crack front triangle " + std::to_string(e.second[0]) + " is degenerate (height " +
                                        std::to_string(s.d) + " m over its front edge)");
        // Midpoint of the edge: rho = slope d / H and [u] = sqrt(slope d / H) (u_v0 + u_v1) / 2 as d -> 0
        // (slope 1 on edge elements; corner and strip elements with chords: front_edge_rho_slope).
        const Tri& tri = cracks.triangles[e.second[0]];
        const int m = tri[0] == third ? 0 : tri[1] == third ? 1 : 2;
        const double slope = front_edge_rho_slope(basis.kind[e.second[0]], m);
        const Vec3 a = 0.5 * (coef[s.v0] + coef[s.v1]);
        const double f = std::sqrt(2 * M_PI * slope / s.d);
        s.KI = c12 * f * a.dot(s.e2);
        s.KII = c12 * f * a.dot(s.e1);
        s.KIII = c3 * f * a.dot(s.e3);
        out.push_back(s);
    }
    return out;
}

}  // namespace cf::bem
