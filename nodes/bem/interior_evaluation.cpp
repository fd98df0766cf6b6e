#include "nodes/bem/interior_evaluation.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/bem/quadrature.hpp"
#include "nodes/domain/isa_clones.hpp"
#include "nodes/domain/triangle_closest_point.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cf::bem {

namespace {

Vec3 at(const std::array<Vec3, 3>& p, const Vec3& bary) { return bary[0] * p[0] + bary[1] * p[1] + bary[2] * p[2]; }

// What one triangle contributes: +U* t (traction, P0) and sign * T^T u (P1 nodal values u_beta),
// sign = -1 on Gamma (eq. 2.20) and +1 on crack sheets with u = [u] (sgbem-math §2 "Cracks").
struct Source {
    const ElementGeometry* g = nullptr;
    Vec3 t = Vec3::Zero();
    std::array<Vec3, 3> u{};
    double sign = -1;
    bool has_traction = false;
};

struct Kernel {
    double c;      // 1 / (16 pi mu (1-nu)), Kelvin constant
    double kappa;  // 1 / (8 pi (1-nu))
    double nu;
    explicit Kernel(const ElasticConstants& e)
        : c(1 / (16 * M_PI * e.mu * (1 - e.nu))), kappa(1 / (8 * M_PI * (1 - e.nu))), nu(e.nu) {}
};

struct Accumulator {
    Vec3 u = Vec3::Zero();
    Mat3 G = Mat3::Zero();  // G(j, l) = du_j / dx_l
};

// What an evaluation accumulates: the displacement or its gradient. Each has its own sums, so
// leaving the other out does not change its bits (the stress needs only the gradient).
enum class Want { u, gradient };

// Adds w * integrand at y (d = x - y) for the source s, at barycentric point `bary` of s.
template <Want want>
void add_point(const Kernel& k, const Source& s, const Vec3& d, const Vec3& bary, double w, Accumulator& acc) {
    constexpr bool gradient = want == Want::gradient;
    const double r2 = d.squaredNorm(), r = std::sqrt(r2), r3 = r2 * r, r5 = r3 * r2;
    const double a = 1 - 2 * k.nu;
    const Vec3& n = s.g->normal;
    const Vec3 uy = bary[0] * s.u[0] + bary[1] * s.u[1] + bary[2] * s.u[2];
    const double dn = d.dot(n), du = d.dot(uy), nu_ = n.dot(uy);
    if constexpr (!gradient) {
        // Double layer T(x,y)^T u(y) (sgbem-math §1 written with d = x - y).
        const Vec3 Tu = k.kappa * (a * (n * du + uy * dn - nu_ * d) / r3 + 3 * dn * du * d / r5);
        acc.u += (w * s.sign) * Tu;
    } else {
        const double r7 = r5 * r2;
        Mat3 B = a * ((n * uy.transpose() + uy * n.transpose() - nu_ * Mat3::Identity()) / r3 -
                      3 * (n * du + uy * dn - nu_ * d) * d.transpose() / r5);
        B += 3 * ((d * (n * du + uy * dn).transpose() + dn * du * Mat3::Identity()) / r5 - 5 * dn * du * d * d.transpose() / r7);
        acc.G += (w * s.sign * k.kappa) * B;
    }
    if (s.has_traction) {
        const Vec3& t = s.t;
        const double dt = d.dot(t);
        if constexpr (!gradient) {
            acc.u += (w * k.c) * ((3 - 4 * k.nu) * t / r + d * dt / r3);
        } else {
            Mat3 A = -(3 - 4 * k.nu) * t * d.transpose() + dt * Mat3::Identity() + d * t.transpose() -
                     3 * dt / r2 * d * d.transpose();
            acc.G += (w * k.c / r3) * A;
        }
    }
}

// The gradient terms of add_point<Want::gradient> for a rule's points, four at a time: each point's
// scalars (distance powers, dot products) as add_point computes them, then the 3x3 coefficients of
// both kernels for four points per vector operation, each coefficient by the same IEEE operations in
// the same order as add_point's Eigen expressions (coefficient-wise; outer products are products of
// coefficients, the identity's off-diagonal zeros included), then added to the sums point by point in
// the rule's order. The results are add_point's to the bit; the 27 divisions per point, which bound
// the stress evaluation, run four wide (Lanes4; neither clone uses FMA, nodes/domain/isa_clones.hpp).

CF_AVX2_CLONE
void add_gradient_points(const Kernel& k, const Source& s, const Vec3& x, const std::array<Vec3, 3>& B, double area,
                         const TriangleRule& rule, Accumulator& acc) {
    const double a = 1 - 2 * k.nu;
    const double c1 = -(3 - 4 * k.nu);
    const Vec3& n = s.g->normal;
    const std::size_t count = rule.size();
    for (std::size_t first = 0; first < count; first += 4) {
        const std::size_t lanes = std::min<std::size_t>(4, count - first);
        // Per point: the scalars add_point computes, in its expressions (lanes past the rule's end
        // repeat its last point and are not added).
        Lanes4 d[3], uy[3], dn, du, nuu, r2, r3, r5, r7, dt;
        double w[4];
        for (int l = 0; l < 4; ++l) {
            const std::size_t i = first + std::min<std::size_t>(std::size_t(l), lanes - 1);
            const double st = rule.s[i], tt = rule.t[i];
            const Vec3 bary = (1 - st - tt) * B[0] + st * B[1] + tt * B[2];
            const Vec3 dl = x - at(s.g->p, bary);
            w[l] = rule.w[i] * 2 * area;
            const double r2l = dl.squaredNorm(), rl = std::sqrt(r2l), r3l = r2l * rl, r5l = r3l * r2l;
            const Vec3 uyl = bary[0] * s.u[0] + bary[1] * s.u[1] + bary[2] * s.u[2];
            for (int c = 0; c < 3; ++c) {
                d[c][l] = dl[c];
                uy[c][l] = uyl[c];
            }
            dn[l] = dl.dot(n);
            du[l] = dl.dot(uyl);
            nuu[l] = n.dot(uyl);
            r2[l] = r2l;
            r3[l] = r3l;
            r5[l] = r5l;
            r7[l] = r5l * r2l;
            dt[l] = s.has_traction ? dl.dot(s.t) : 0.0;
        }
        // Double layer: B = a ((n uy^T + uy n^T - nu_ I) / r3 - 3 v d^T / r5)
        //                 + 3 ((d q^T + dn du I) / r5 - 5 dn du d d^T / r7),  v = n du + uy dn - nu_ d, q = n du + uy dn.
        Lanes4 v3[3], q[3], Bc[9], Ac[9];
        const Lanes4 dndu = dn * du, five = (5 * dn) * du;
        for (int i = 0; i < 3; ++i) {
            q[i] = n[i] * du + uy[i] * dn;
            v3[i] = 3 * (q[i] - nuu * d[i]);
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const double I = i == j ? 1.0 : 0.0;
                const Lanes4 t1 = (n[i] * uy[j] + uy[i] * n[j]) - nuu * I;
                const Lanes4 first_part = a * (t1 / r3 - (v3[i] * d[j]) / r5);
                const Lanes4 q1 = (d[i] * q[j] + dndu * I) / r5;
                const Lanes4 q2 = ((five * d[i]) * d[j]) / r7;
                Bc[3 * i + j] = first_part + 3 * (q1 - q2);
            }
        if (s.has_traction) {
            // Single layer: A = -(3 - 4 nu) t d^T + dt I + d t^T - 3 dt / r2 d d^T.
            const Lanes4 f = (3 * dt) / r2;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    const double I = i == j ? 1.0 : 0.0;
                    Ac[3 * i + j] = (((c1 * s.t[i]) * d[j] + dt * I) + d[i] * s.t[j]) - (f * d[i]) * d[j];
                }
        }
        for (std::size_t l = 0; l < lanes; ++l) {
            const double fb = w[l] * s.sign * k.kappa;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) acc.G(i, j) += fb * Bc[3 * i + j][l];
            if (s.has_traction) {
                const double fa = w[l] * k.c / r3[l];
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j) acc.G(i, j) += fa * Ac[3 * i + j][l];
            }
        }
    }
}

struct Rules {
    TriangleRule six = symmetric_triangle_rule_6();
    TriangleRule g4 = collapsed_gauss_triangle_rule(4);
    TriangleRule g6 = collapsed_gauss_triangle_rule(6);
};
const Rules& rules() {
    static const Rules r;
    return r;
}

// Integrates over the sub-triangle of s with barycentric corners B[0..2] (area `area`), subdividing
// while it is near x (header comment).
template <Want want>
void integrate(const Kernel& k, const Source& s, const Vec3& x, const std::array<Vec3, 3>& B, double area, int depth,
               const InteriorQuadrature& q, Accumulator& acc) {
    const std::array<Vec3, 3> P = {at(s.g->p, B[0]), at(s.g->p, B[1]), at(s.g->p, B[2])};
    const double diam = std::max({(P[1] - P[0]).norm(), (P[2] - P[0]).norm(), (P[2] - P[1]).norm()});
    const Vec3 cb = closest_point_on_triangle(x, P[0], P[1], P[2]).barycentric;
    const double dist = (x - at(P, cb)).norm();
    const double ratio = dist / diam;
    if (ratio < q.leaf_ratio && depth < q.max_depth) {
        const Vec3 m01 = 0.5 * (B[0] + B[1]), m12 = 0.5 * (B[1] + B[2]), m02 = 0.5 * (B[0] + B[2]);
        const double qa = 0.25 * area;
        integrate<want>(k, s, x, {B[0], m01, m02}, qa, depth + 1, q, acc);
        integrate<want>(k, s, x, {m01, B[1], m12}, qa, depth + 1, q, acc);
        integrate<want>(k, s, x, {m02, m12, B[2]}, qa, depth + 1, q, acc);
        integrate<want>(k, s, x, {m12, m02, m01}, qa, depth + 1, q, acc);
        return;
    }
    const TriangleRule& rule = ratio >= 8 ? rules().six : ratio >= 4 ? rules().g4 : rules().g6;
    if constexpr (want == Want::gradient) {
        if (q.four_points_at_a_time) {
            add_gradient_points(k, s, x, B, area, rule, acc);
            return;
        }
    }
    for (std::size_t i = 0; i < rule.size(); ++i) {
        const double st = rule.s[i], tt = rule.t[i];
        const Vec3 bary = (1 - st - tt) * B[0] + st * B[1] + tt * B[2];
        add_point<want>(k, s, x - at(s.g->p, bary), bary, rule.w[i] * 2 * area, acc);
    }
}

struct Sources {
    std::vector<Source> gamma, sigma;
};

Sources collect(const BemSolution& sol, bool include_cracks) {
    Sources out;
    const SurfaceOperators& o = *sol.surface;
    for (std::size_t e = 0; e < o.geometry.size(); ++e) {
        Source s;
        s.g = &o.geometry[e];
        s.t = sol.traction[e];
        s.has_traction = true;
        for (int b = 0; b < 3; ++b) s.u[b] = sol.displacement[s.g->nodes[b]];
        s.sign = -1;
        out.gamma.push_back(s);
    }
    if (include_cracks && sol.cracks) {
        for (std::size_t e = 0; e < sol.cracks->geometry.size(); ++e) {
            Source s;
            s.g = &sol.cracks->geometry[e];
            for (int b = 0; b < 3; ++b) s.u[b] = sol.crack_opening[s.g->nodes[b]];
            s.sign = +1;
            out.sigma.push_back(s);
        }
    }
    return out;
}

// Nearest triangle of a source list: (index, barycentric closest point, distance).
struct Nearest {
    std::size_t index = 0;
    Vec3 bary = Vec3::Zero();
    double dist = std::numeric_limits<double>::infinity();
};
Nearest nearest(const std::vector<Source>& list, const Vec3& x) {
    Nearest best;
    for (std::size_t e = 0; e < list.size(); ++e) {
        const auto& p = list[e].g->p;
        const Vec3 b = closest_point_on_triangle(x, p[0], p[1], p[2]).barycentric;
        const double d = (x - at(p, b)).norm();
        if (d < best.dist) best = {e, b, d};
    }
    return best;
}

std::string point_text(const Vec3& x) {
    std::ostringstream os;
    os.precision(9);
    os << "(" << x.x() << ", " << x.y() << ", " << x.z() << ")";
    return os.str();
}

double on_surface_tolerance(const BemSolution& sol) { return 1e-9 * bounding_box(sol.surface->mesh).extent().norm(); }

template <Want want>
Accumulator evaluate(const Kernel& k, const Sources& src, const Vec3& x, const InteriorQuadrature& q) {
    Accumulator acc;
    for (const auto* list : {&src.gamma, &src.sigma})
        for (const Source& s : *list) {
            const std::array<Vec3, 3> B = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
            integrate<want>(k, s, x, B, s.g->area, 0, q, acc);
        }
    return acc;
}

void check_sizes(const BemSolution& sol) {
    if (!sol.surface || sol.displacement.size() != sol.surface->mesh.num_vertices() ||
        sol.traction.size() != sol.surface->geometry.size())
        throw std::invalid_argument("interior evaluation: the solution's displacement/traction arrays do not match its surface mesh");
    if (sol.cracks && sol.crack_opening.size() != sol.cracks->cracks.num_vertices())
        throw std::invalid_argument("interior evaluation: the solution's crack opening does not match its crack mesh");
}

}  // namespace

std::vector<Vec3> interior_displacement(const BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks,
                                        const InteriorQuadrature& q) {
    check_sizes(sol);
    const Sources src = collect(sol, include_cracks);
    const Kernel k(sol.surface->elastic);
    const double tol = on_surface_tolerance(sol);
    const CancelToken cancel = CancelToken::current();  // polled per point: one point costs one pass over the sources
    for (const Vec3& x : points) {
        cancel.poll();
        if (nearest(src.sigma, x).dist <= tol)
            throw std::invalid_argument("interior displacement: point " + point_text(x) +
                                        " lies on a crack sheet, where the displacement jumps; evaluate at a point "
                                        "off the sheet or use crack_average_displacement");
    }
    std::vector<Vec3> out(points.size(), Vec3::Zero());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            cancel.poll();
            const Nearest nb = nearest(src.gamma, points[i]);
            if (nb.dist <= tol) {  // boundary trace: the P1 interpolant
                const Source& s = src.gamma[nb.index];
                out[i] = nb.bary[0] * s.u[0] + nb.bary[1] * s.u[1] + nb.bary[2] * s.u[2];
            } else {
                out[i] = evaluate<Want::u>(k, src, points[i], q).u;
            }
        }
    });
    return out;
}

std::vector<Mat3> interior_displacement_gradient(const BemSolution& sol, const std::vector<Vec3>& points,
                                                 bool include_cracks, const InteriorQuadrature& q) {
    check_sizes(sol);
    const Sources src = collect(sol, include_cracks);
    const Kernel k(sol.surface->elastic);
    const double tol = on_surface_tolerance(sol);
    const CancelToken cancel = CancelToken::current();  // polled per point, as above
    // Every point checked (in parallel: a pass over all sources each), the first bad one reported.
    std::vector<char> where(points.size(), 0);  // 1 on the surface, 2 on a crack sheet
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            cancel.poll();
            if (nearest(src.gamma, points[i]).dist <= tol) where[i] = 1;
            else if (nearest(src.sigma, points[i]).dist <= tol) where[i] = 2;
        }
    });
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (where[i] == 1)
            throw std::invalid_argument("interior stress: point " + point_text(points[i]) +
                                        " lies on the surface, where the stress kernels are singular; use a point inside");
        if (where[i] == 2)
            throw std::invalid_argument("interior stress: point " + point_text(points[i]) +
                                        " lies on a crack sheet, where the stress kernels are singular; use a point off it");
    }
    std::vector<Mat3> out(points.size(), Mat3::Zero());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            cancel.poll();
            out[i] = evaluate<Want::gradient>(k, src, points[i], q).G;
        }
    });
    return out;
}

std::vector<Mat3> interior_stress(const BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks,
                                  const InteriorQuadrature& q) {
    std::vector<Mat3> G = interior_displacement_gradient(sol, points, include_cracks, q);
    const double mu = sol.surface->elastic.mu, nu = sol.surface->elastic.nu;
    const double lambda = 2 * mu * nu / (1 - 2 * nu);
    for (Mat3& g : G) g = (lambda * g.trace() * Mat3::Identity() + mu * (g + g.transpose())).eval();
    return G;
}

std::vector<Vec3> crack_average_displacement(const BemSolution& sol, const InteriorQuadrature& q) {
    if (!sol.cracks) return {};
    return interior_displacement(sol, sol.cracks->cracks.vertices, false, q);
}

}  // namespace cf::bem
