#include "nodes/bem/tip_elements.hpp"

#include "nodes/bem/solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace cf::bem {

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

}  // namespace

TipPoint tip_point(const ElementGeometry& g, const TipElementKind& k, double s, double t) {
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
struct TipSums {
    int na = 1, nb = 1;
    double S1[max_weights][max_weights];
    double SR[max_weights][max_weights][6];
    double SK[3] = {};
    TipSums(int na_, int nb_) : na(na_), nb(nb_) {
        for (int i = 0; i < na; ++i)
            for (int j = 0; j < nb; ++j) {
                S1[i][j] = 0;
                for (double& v : SR[i][j]) v = 0;
            }
    }
};

// Separated pairs: graded collapsed Gauss on square-root elements (4x4, 6x6, 8x8 by separation),
// the far-field rule of the same zone on plain ones (symmetric 6-point, 4x4, 6x6).
struct TipRules {
    PairRule id, edge, vert;
    std::array<TriangleRule, 3> tip, plain;  // [zone]
    explicit TipRules(int n) {
        id = sauter_schwab_rule(PairKind::identical, n, true);
        edge = sauter_schwab_rule(PairKind::common_edge, n, true);
        vert = sauter_schwab_rule(PairKind::common_vertex, n, true);
        const int nt[3] = {4, 6, 8};
        for (int z = 0; z < 3; ++z) {
            tip[z] = collapsed_gauss_triangle_rule(nt[z], true);
            plain[z] = z == 0 ? symmetric_triangle_rule_6() : collapsed_gauss_triangle_rule(nt[z]);
        }
    }
};

// One point pair: adds w fa_i fb_j k to the sums.
inline void accumulate(const double* fa, const double* fb, double w, const Vec3& d, TipSums& out) {
    const double r2 = d.squaredNorm();
    const double ri = 1.0 / std::sqrt(r2);
    const double r3 = ri * ri * ri;
    const double k[7] = {ri, r3 * d.x() * d.x(), r3 * d.y() * d.y(), r3 * d.z() * d.z(),
                         r3 * d.x() * d.y(), r3 * d.x() * d.z(), r3 * d.y() * d.z()};
    for (int i = 0; i < out.na; ++i) {
        const double wi = w * fa[i];
        if (wi == 0) continue;
        for (int j = 0; j < out.nb; ++j) {
            const double v = wi * fb[j];
            out.S1[i][j] += v * k[0];
            double* sr = out.SR[i][j];
            for (int m = 0; m < 6; ++m) sr[m] += v * k[1 + m];
        }
    }
}

void scale_sums(const ElementGeometry& a, const ElementGeometry& b, TipSums& out) {
    const double scale = 4 * a.area * b.area;
    for (int i = 0; i < out.na; ++i)
        for (int j = 0; j < out.nb; ++j) {
            out.S1[i][j] *= scale;
            for (double& v : out.SR[i][j]) v *= scale;
        }
    for (double& v : out.SK) v *= scale;
}

// Touching pairs: a Sauter-Schwab rule in reordered local coordinates.
void integrate(const ElementGeometry& a, const TipElementKind& ka, const int* pa, const ElementGeometry& b,
               const TipElementKind& kb, const int* pb, const PairRule& r, bool want_k, TipSums& out) {
    double fa[max_weights], fb[max_weights];
    for (std::size_t q = 0; q < r.size(); ++q) {
        if (r.w[q] == 0) continue;
        // Reordered local (s, t) -> barycentric in the element's own order -> its (s, t).
        double la[3], lb[3];
        la[pa[0]] = 1 - r.sx[q] - r.tx[q];
        la[pa[1]] = r.sx[q];
        la[pa[2]] = r.tx[q];
        lb[pb[0]] = 1 - r.sy[q] - r.ty[q];
        lb[pb[1]] = r.sy[q];
        lb[pb[2]] = r.ty[q];
        const TipPoint X = tip_point(a, ka, la[1], la[2]);
        const TipPoint Y = tip_point(b, kb, lb[1], lb[2]);
        weights_at(ka, X, fa);
        weights_at(kb, Y, fb);
        const Vec3 d = X.x - Y.x;
        accumulate(fa, fb, r.w[q], d, out);
        if (want_k) {
            const double f = r.w[q] * d.dot(b.normal) / (d.squaredNorm() * d.norm());
            for (int j = 0; j < 3; ++j) out.SK[j] += f * Y.psi[j];
        }
    }
    scale_sums(a, b, out);
}

// Separated pairs: the tensor product of one triangle rule per side, each side's weights evaluated
// once per point of its own rule.
struct SidePoints {
    std::vector<Vec3> x;
    std::vector<double> w, f;  // f: weight_count values per point
    std::vector<std::array<double, 3>> psi;
};
void side_points(const ElementGeometry& g, const TipElementKind& k, const TriangleRule& r, SidePoints& out) {
    const int nw = weight_count(k);
    out.x.resize(r.size());
    out.w.resize(r.size());
    out.f.resize(r.size() * nw);
    out.psi.resize(r.size());
    for (std::size_t q = 0; q < r.size(); ++q) {
        const TipPoint P = tip_point(g, k, r.s[q], r.t[q]);
        out.x[q] = P.x;
        out.w[q] = r.w[q];
        weights_at(k, P, &out.f[q * nw]);
        out.psi[q] = P.psi;
    }
}
void integrate_separated(const ElementGeometry& a, const TipElementKind& ka, const TriangleRule& ra, const ElementGeometry& b,
                         const TipElementKind& kb, const TriangleRule& rb, bool want_k, TipSums& out) {
    thread_local SidePoints A, B;
    side_points(a, ka, ra, A);
    side_points(b, kb, rb, B);
    const int na = out.na, nb = out.nb;
    for (std::size_t i = 0; i < A.x.size(); ++i)
        for (std::size_t j = 0; j < B.x.size(); ++j) {
            const Vec3 d = A.x[i] - B.x[j];
            const double w = A.w[i] * B.w[j];
            accumulate(&A.f[i * na], &B.f[j * nb], w, d, out);
            if (want_k) {
                const double f = w * d.dot(b.normal) / (d.squaredNorm() * d.norm());
                for (int m = 0; m < 3; ++m) out.SK[m] += f * B.psi[j][m];
            }
        }
    scale_sums(a, b, out);
}

// Integrates a pair with the rules pair_integrals would choose for its touching kind (graded), or
// the graded tensor rules of its separation zone.
void integrate_pair(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                    bool same_mesh, const TipRules& rules, bool want_k, TipSums& s) {
    int perm_a[3] = {0, 1, 2}, perm_b[3] = {0, 1, 2};
    if (same_mesh) {
        int ia[3], ib[3], ns = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (a.nodes[i] == b.nodes[j]) { ia[ns] = i; ib[ns] = j; ++ns; }
        const PairRule* r = nullptr;
        if (ns == 3) {
            for (int k = 0; k < 3; ++k) perm_b[k] = ib[k];
            r = &rules.id;
        } else if (ns == 2) {
            perm_a[0] = ia[0]; perm_a[1] = ia[1]; perm_a[2] = 3 - ia[0] - ia[1];
            perm_b[0] = ib[0]; perm_b[1] = ib[1]; perm_b[2] = 3 - ib[0] - ib[1];
            r = &rules.edge;
        } else if (ns == 1) {
            perm_a[0] = ia[0]; perm_a[1] = ia[0] == 0 ? 1 : 0; perm_a[2] = ia[0] == 2 ? 1 : 2;
            perm_b[0] = ib[0]; perm_b[1] = ib[0] == 0 ? 1 : 0; perm_b[2] = ib[0] == 2 ? 1 : 2;
            r = &rules.vert;
        }
        if (r) {
            integrate(a, ka, perm_a, b, kb, perm_b, *r, want_k, s);
            return;
        }
    }
    const double rho = separation_ratio(a, b);
    const int z = rho >= 3 ? 0 : rho >= 1.5 ? 1 : 2;
    const bool ta = ka.type != TipElementKind::plain, tb = kb.type != TipElementKind::plain;
    integrate_separated(a, ka, ta ? rules.tip[z] : rules.plain[z], b, kb, tb ? rules.tip[z] : rules.plain[z], want_k, s);
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
    for (int al = 0; al < 3; ++al)
        for (int be = 0; be < 3; ++be) {
            Mat3 B = Mat3::Zero();
            for (int i = 0; i < ta[al].n; ++i)
                for (int j = 0; j < tb[be].n; ++j) {
                    const int wi = ta[al].weight[i], wj = tb[be].weight[j];
                    B += hyper_block(ta[al].v[i], tb[be].v[j], s.S1[wi][wj], kernel_p(s.S1[wi][wj], s.SR[wi][wj], c), c);
                }
            out.H[al][be] = B;
        }
    if (want_k) {
        // a is a plain P0 test element: weight index 0 only on its side.
        for (int be = 0; be < 3; ++be) {
            Mat3 K = Mat3::Zero();
            for (int j = 0; j < tb[be].n; ++j) {
                const int wj = tb[be].weight[j];
                K += kernel_p(s.S1[0][wj], s.SR[0][wj], c) * cross_matrix(tb[be].v[j]);
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

// Greedy colouring of a subset of elements: no two elements of one colour share a vertex.
std::vector<std::vector<int>> colour_subset(const std::vector<ElementGeometry>& g, const std::vector<int>& subset) {
    std::map<int, std::vector<int>> node_colours;
    std::vector<std::vector<int>> groups;
    for (int e : subset) {
        std::vector<char> used(groups.size() + 1, 0);
        for (int v : g[e].nodes)
            for (int c : node_colours[v]) used[c] = 1;
        int c = 0;
        while (used[c]) ++c;
        if (c == static_cast<int>(groups.size())) groups.emplace_back();
        groups[c].push_back(e);
        for (int v : g[e].nodes) node_colours[v].push_back(c);
    }
    return groups;
}

}  // namespace

void tip_pair_blocks(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                     bool same_mesh, int n, const ElasticConstants& c, bool want_k, TipPairBlocks& out) {
    const TipRules rules(n);
    tip_pair_blocks_with(a, ka, b, kb, same_mesh, rules, c, want_k, out);
}

double tip_pair_scalar(const ElementGeometry& a, const TipElementKind& ka, int fa, const ElementGeometry& b,
                       const TipElementKind& kb, int fb, bool same_mesh, int n) {
    const TipRules rules(n);
    TipSums s(weight_count(ka), weight_count(kb));
    integrate_pair(a, ka, b, kb, same_mesh, rules, false, s);
    return s.S1[fa][fb];
}

namespace {

// tip_crack_operators' steps, in the order it calls them.

// Re-integrates every pair of one element b touching the front: square-root blocks in, P1
// blocks out. Task b owns the columns nodes(b) of W, X and HY, so the tasks of one colour run in
// parallel; a pair of two touched elements is the later one's.
class TipColumns {
public:
    TipColumns(const SurfaceOperators& surface, const TipBasis& basis, const std::vector<char>& is_touched,
               const TipRules& rules, const PairQuadrature& quad, CrackOperators& out)
        : gs_(surface.geometry), gc_(out.geometry), basis_(basis), is_touched_(is_touched), rules_(rules), quad_(quad),
          ec_(surface.elastic), W_(out.W), X_(out.X), HY_(out.HY) {}

    void operator()(int b) const {
        const ElementGeometry& gb = gc_[b];
        PairBlocks blk;
        TipPairBlocks tip;
        for (std::size_t a = 0; a < gs_.size(); ++a) {
            const PairIntegrals p = pair_integrals(gs_[a], gb, false, quad_);
            pair_blocks(gs_[a], gb, p, ec_, false, blk);
            tip_pair_blocks_with(gs_[a], plain_, gb, basis_.kind[b], false, rules_, ec_, true, tip);
            for (int be = 0; be < 3; ++be) {
                W_.block<3, 3>(3 * a, 3 * gb.nodes[be]) += tip.Kb[be] - blk.Kb[be];
                for (int al = 0; al < 3; ++al)
                    X_.block<3, 3>(3 * gs_[a].nodes[al], 3 * gb.nodes[be]) += tip.H[al][be] - blk.H[al][be];
            }
        }
        for (std::size_t ai = 0; ai < gc_.size(); ++ai) {
            const int a = static_cast<int>(ai);
            if (is_touched_[a] && a > b) continue;  // that pair is task a's
            const int lo = std::min(a, b), hi = std::max(a, b);
            const PairIntegrals p = pair_integrals(gc_[lo], gc_[hi], true, quad_);
            pair_blocks(gc_[lo], gc_[hi], p, ec_, false, blk);
            tip_pair_blocks_with(gc_[lo], basis_.kind[lo], gc_[hi], basis_.kind[hi], true, rules_, ec_, false, tip);
            const double half = a == b ? 0.5 : 1.0;
            for (int al = 0; al < 3; ++al)
                for (int be = 0; be < 3; ++be) {
                    const Mat3 d = half * (tip.H[al][be] - blk.H[al][be]);
                    if (a == lo) HY_.block<3, 3>(3 * gc_[lo].nodes[al], 3 * gc_[hi].nodes[be]) += d;
                    else HY_.block<3, 3>(3 * gc_[hi].nodes[be], 3 * gc_[lo].nodes[al]) += d.transpose();
                }
        }
    }

private:
    const std::vector<ElementGeometry>& gs_;
    const std::vector<ElementGeometry>& gc_;
    const TipBasis& basis_;
    const std::vector<char>& is_touched_;
    const TipRules& rules_;
    const PairQuadrature& quad_;
    const ElasticConstants ec_;
    const TipElementKind plain_;
    Matrix& W_;
    Matrix& X_;
    Matrix& HY_;
};

// The pairs TipColumns integrates: every surface element, and the crack elements not left to a
// later touched element.
std::int64_t tip_pair_count(const std::vector<int>& touched, const std::vector<char>& is_touched, std::size_t surface_elements) {
    std::int64_t pairs = 0;
    for (int b : touched) {
        pairs += static_cast<std::int64_t>(surface_elements);
        for (std::size_t a = 0; a < is_touched.size(); ++a)
            if (!(is_touched[a] && static_cast<int>(a) > b)) ++pairs;
    }
    return pairs;
}

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

}  // namespace

std::shared_ptr<const CrackOperators> tip_crack_operators(const SurfaceOperators& surface, const CrackOperators& p1) {
    // A second copy of the crack blocks beside the append-only P1 ones.
    check_memory_budget(2 * crack_operator_bytes(surface.mesh.num_triangles(), surface.mesh.num_vertices(), p1.cracks.num_vertices()),
                        surface.options.memory_budget_bytes,
                        "square-root crack-front elements for " + std::to_string(p1.cracks.num_vertices()) +
                            " crack nodes (front_elements: square_root keeps a second copy of the crack blocks)");
    auto out = std::make_shared<CrackOperators>(p1);
    out->tip_elements = true;
    const TipBasis basis = tip_basis(p1.cracks);
    const auto& gc = p1.geometry;
    std::vector<int> touched;
    for (std::size_t e = 0; e < gc.size(); ++e)
        if (basis.kind[e].type != TipElementKind::plain) touched.push_back(static_cast<int>(e));
    std::vector<char> is_touched(gc.size(), 0);
    for (int e : touched) is_touched[e] = 1;
    // Touching pairs: two more points per direction than the P1 rules (graded rules converge more slowly:
    // n = 5 / 7 / 9 gave front-average K_I errors of 0.96 / 0.52 / 0.42 % on the 294-triangle penny crack).
    const TipRules rules(surface.options.quadrature.singular_order + 2);
    const PairQuadrature quad(surface.options.quadrature);
    const TipColumns columns(surface, basis, is_touched, rules, quad, *out);
    for (const auto& grp : colour_subset(gc, touched))
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grp.size(), 1), [&](const tbb::blocked_range<std::size_t>& rg) {
            for (std::size_t gi = rg.begin(); gi != rg.end(); ++gi) columns(grp[gi]);
        });
    out->tip_pairs_computed = tip_pair_count(touched, is_touched, surface.geometry.size());
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
