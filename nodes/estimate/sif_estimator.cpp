#include "nodes/estimate/sif_estimator.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/domain/triangle_closest_point.hpp"
#include "nodes/initiate/surface_stress.hpp"
#include "nodes/propagate/crack_front.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace cf::estimate {

namespace {

constexpr double kMinCos = 1.0 / 3.0;  // cos(theta*) >= 1/3: |theta*| below ~70.5 degrees (ch. 5.1)

// Front edge records in front order: per front, its edges (v0 < v1) with the triangle they bound.
struct FrontEdge {
    int v0, v1, tri, region;
};

std::vector<std::vector<FrontEdge>> front_edges(const SurfaceMesh& cracks) {
    std::map<std::pair<int, int>, std::vector<int>> edge_tris;
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = cracks.triangles[t][k], b = cracks.triangles[t][(k + 1) % 3];
            edge_tris[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
        }
    std::vector<std::vector<FrontEdge>> out;
    for (const propagate::CrackFront& f : propagate::extract_fronts(cracks)) {
        std::vector<FrontEdge> edges;
        const std::size_t n = f.nodes.size();
        for (std::size_t i = 0; i < f.num_edges(); ++i) {
            const int a = f.nodes[i], b = f.nodes[(i + 1) % n];
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            edges.push_back({key.first, key.second, edge_tris.at(key).front(), f.region});
        }
        out.push_back(std::move(edges));
    }
    return out;
}

// Closest surface triangle to p: index and distance.
std::pair<std::size_t, double> closest_surface_triangle(const bem::SurfaceOperators& s, const Vec3& p) {
    std::size_t best = 0;
    double dist = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < s.geometry.size(); ++a) {
        const auto& g = s.geometry[a];
        const double d = (p - closest_point_on_triangle(p, g.p[0], g.p[1], g.p[2]).point).norm();
        if (d < dist) {
            dist = d;
            best = a;
        }
    }
    return {best, dist};
}

void smooth_along(std::vector<Mat3>& sigma, bool closed, int passes) {
    const std::size_t n = sigma.size();
    if (n < 2) return;
    for (int p = 0; p < passes; ++p) {
        std::vector<Mat3> next(n);
        for (std::size_t i = 0; i < n; ++i) {
            Mat3 sum = sigma[i];
            double w = 1;
            if (i > 0 || closed) {
                sum += sigma[(i + n - 1) % n];
                w += 1;
            }
            if (i + 1 < n || closed) {
                sum += sigma[(i + 1) % n];
                w += 1;
            }
            next[i] = sum / w;  // renormalised: an end keeps its full weight
        }
        sigma.swap(next);
    }
}

}  // namespace

InteriorFrontMeans interior_front_means(const bem::SurfaceOperators& surface, const SurfaceMesh& cracks,
                                        const std::vector<bem::FrontEdgeSif>& sifs, double near_surface, double nu) {
    InteriorFrontMeans m;
    const CancelToken cancel = CancelToken::current();
    for (const auto& r : sifs) {
        cancel.poll();  // a pass over the surface per edge
        const Vec3 p = 0.5 * (cracks.vertices[r.v0] + cracks.vertices[r.v1]);
        const auto [tri, dist] = closest_surface_triangle(surface, p);
        if (dist < near_surface * surface.geometry[tri].diameter) continue;
        m.KI += r.KI;
        const propagate::Sifs K{r.KI, r.KII, r.KIII};
        m.kink_deg += propagate::kink_angle(propagate::mode_i_iii_sif(K, nu), r.KII) * 180 / M_PI;
        ++m.edges;
    }
    if (m.edges) {
        m.KI /= static_cast<double>(m.edges);
        m.kink_deg /= static_cast<double>(m.edges);
    }
    return m;
}

double eta_for_kink(double theta) {
    const double t = std::tan(0.5 * theta);
    return t / (2 * t * t - 1);  // eq. (5.2)
}

Vec3 basic_estimate(const Mat3& sigma, const Vec3& e1, const Vec3& e2, const Vec3& e3, double scale, double sqrt_pi_a) {
    const Vec3 q = sigma * e2;  // traction on the crack plane, eq. (5.1)
    const double f = scale * sqrt_pi_a;
    return {f * e2.dot(q), f * e1.dot(q), f * e3.dot(q)};
}

Vec3 aligned_estimate(const Mat3& sigma, const Vec3& e1, const Vec3& e2, const Vec3& e3, double nu, double scale,
                      double sqrt_pi_a, double fc, int* choice) {
    const Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (sigma + sigma.transpose()));
    const Vec3 l = es.eigenvalues();  // ascending
    const Mat3 v = es.eigenvectors();
    // cos(theta*) of direction k: the crack normal turned onto v_k within the (e2, e1) plane.
    auto cos_theta = [&](int k) {
        const Vec3 vk = v.col(k);
        const double a = vk.dot(e2), b = vk.dot(e1);
        const double r = std::hypot(a, b);
        return r > 0 ? std::abs(a) / r : 0.0;
    };
    int k = 2, which = 0;
    if (cos_theta(2) < kMinCos) {
        const bool compressive_first = l[0] < 0 && -l[0] / std::max(fc, 1e-300) > l[1];
        const int first = compressive_first ? 0 : 1, second = compressive_first ? 1 : 0;
        if (cos_theta(first) >= kMinCos) {
            k = first;
            which = compressive_first ? 2 : 1;
        } else {
            k = second;
            which = 3;
        }
    }
    if (choice) *choice = which;
    Vec3 dir = v.col(k);
    if (dir.dot(e2) < 0) dir = -dir;  // eigenvectors are defined up to sign: face the crack normal
    const double lambda = l[k];
    // theta*: the propagation direction sin(theta) e2 + cos(theta) e1 turns the normal e2 into
    // cos(theta) e2 - sin(theta) e1, which should be parallel to v projected into (e2, e1).
    const double a = dir.dot(e2), b = dir.dot(e1);
    const double theta = (std::hypot(a, b) > 0 && std::abs(a) < 0.9999 * std::hypot(a, b)) ? std::atan2(-b, a) : 0.0;
    const double eta = eta_for_kink(theta);
    const double s = scale * sqrt_pi_a / std::sqrt(1 + eta * eta);  // eq. (5.3)
    // Mode I / III split by the angle alpha between v and the front tangent, in the (e2, e3) plane (eq. 5.4).
    const double c3 = dir.dot(e3), r3 = std::hypot(a, c3);
    const double cos_alpha = r3 > 0 ? c3 / r3 : 0.0;
    const double KI = s * lambda * std::sqrt(1 - std::abs(cos_alpha));
    const double KII = s * lambda * eta;
    // Sign of K_III as the basic estimator gives it for sigma = lambda v v^T: e3^T sigma e2 = lambda (v.e2)(v.e3).
    const double KIII = s * lambda * (cos_alpha < 0 ? -1.0 : 1.0) * std::sqrt(std::abs(cos_alpha) * (1 - nu));
    return {KI, KII, KIII};
}

namespace {

// estimate_sifs' steps, in the order it calls them.

// Coarse crack areas, one face (eq. 5.1), per crack.
std::vector<double> crack_areas(const SurfaceMesh& cracks) {
    std::vector<double> area(static_cast<std::size_t>(cracks.num_regions()), 0.0);
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t) {
        const Tri& tr = cracks.triangles[t];
        area[cracks.region_of(t)] +=
            0.5 * (cracks.vertices[tr[1]] - cracks.vertices[tr[0]]).cross(cracks.vertices[tr[2]] - cracks.vertices[tr[0]]).norm();
    }
    return area;
}

// The stress at each front edge's midpoint, per front and edge, and which edges were evaluated.
struct FrontStresses {
    std::vector<std::vector<Mat3>> sigma;
    std::vector<std::vector<char>> evaluated;
};

// Stress at the midpoints of the edges that move (all without `moving`): near-surface points
// take the closest triangle's surface stress (eq. 4.6), the others the Somigliana stress without
// crack terms (eq. 2.23), evaluated together.
FrontStresses front_stresses(const bem::BemSolution& sol, const SurfaceMesh& cracks,
                             const std::vector<std::vector<FrontEdge>>& fronts, const SifEstimatorSettings& set,
                             const std::vector<char>* moving, SifEstimatorReport& rep) {
    const bem::SurfaceOperators& s = *sol.surface;
    const double nu = s.elastic.nu, E = 2 * s.elastic.mu * (1 + nu);
    std::vector<Vec3> points;
    std::vector<std::pair<std::size_t, std::size_t>> where;  // (front, edge) of each interior point
    FrontStresses out;
    out.sigma.resize(fronts.size());
    out.evaluated.resize(fronts.size());
    const bool all_move = !moving || moving->size() != cracks.num_vertices();
    // Polled per front edge (a pass over the surface each) and per Somigliana point (in
    // bem::interior_stress), so Ctrl-C stops the estimator within milliseconds.
    const CancelToken cancel = CancelToken::current();
    for (std::size_t f = 0; f < fronts.size(); ++f) {
        out.sigma[f].assign(fronts[f].size(), Mat3::Zero());
        out.evaluated[f].assign(fronts[f].size(), 0);
        for (std::size_t i = 0; i < fronts[f].size(); ++i) {
            cancel.poll();
            const FrontEdge& e = fronts[f][i];
            if (!all_move && !(*moving)[e.v0] && !(*moving)[e.v1]) {
                ++rep.skipped_edges;
                continue;
            }
            out.evaluated[f][i] = 1;
            const Vec3 p = 0.5 * (cracks.vertices[e.v0] + cracks.vertices[e.v1]);
            const auto [tri, dist] = closest_surface_triangle(s, p);
            if (dist < set.near_surface * s.geometry[tri].diameter) {
                const auto& g = s.geometry[tri];
                const std::array<Vec3, 3> u = {sol.displacement[g.nodes[0]], sol.displacement[g.nodes[1]],
                                               sol.displacement[g.nodes[2]]};
                out.sigma[f][i] = initiate::surface_stress(g.p, u, sol.traction[tri], E, nu);  // eq. (4.6)
                ++rep.surface_points;
            } else {
                points.push_back(p);
                where.emplace_back(f, i);
            }
        }
    }
    if (!points.empty()) {
        const std::vector<Mat3> st = bem::interior_stress(sol, points, false, set.quadrature);  // eq. (2.23), no crack term
        for (std::size_t k = 0; k < points.size(); ++k) out.sigma[where[k].first][where[k].second] = st[k];
    }
    rep.interior_points = points.size();
    return out;
}

// Edges not evaluated take the nearest evaluated edge's stress along the (closed) loop, the
// earlier one on ties. False when the front has no evaluated edge (it is stopped).
bool fill_unevaluated(std::vector<Mat3>& sigma, const std::vector<char>& evaluated) {
    const std::size_t m = sigma.size();
    bool any = false;
    for (char e : evaluated) any = any || e;
    if (!any) return false;
    for (std::size_t i = 0; i < m; ++i) {
        if (evaluated[i]) continue;
        for (std::size_t d = 1; d <= m; ++d) {
            if (evaluated[(i + m - d) % m]) { sigma[i] = sigma[(i + m - d) % m]; break; }
            if (evaluated[(i + d) % m]) { sigma[i] = sigma[(i + d) % m]; break; }
        }
    }
    return true;
}

// The SIFs of one front's edges from their (smoothed) stresses, by the chosen estimator.
void estimate_front(const SurfaceMesh& cracks, const std::vector<FrontEdge>& front, const std::vector<Mat3>& sigma,
                    double sqrt_pi_a, double nu, const SifEstimatorSettings& set, SifEstimatorReport& rep,
                    std::vector<bem::FrontEdgeSif>& out) {
    for (std::size_t i = 0; i < front.size(); ++i) {
        const FrontEdge& e = front[i];
        bem::FrontEdgeSif r;
        r.v0 = e.v0;
        r.v1 = e.v1;
        bem::front_edge_frame(cracks, e.tri, e.v0, e.v1, r.e1, r.e2, r.e3);
        Vec3 K;
        if (set.kind == EstimatorKind::basic) {
            K = basic_estimate(sigma[i], r.e1, r.e2, r.e3, set.scale, sqrt_pi_a);
        } else {
            int choice = 0;
            K = aligned_estimate(sigma[i], r.e1, r.e2, r.e3, nu, set.scale, sqrt_pi_a, set.compressive_factor, &choice);
            if (choice == 1) ++rep.second_choices;
            if (choice == 2) ++rep.compressive_choices;
            if (choice == 3) ++rep.third_choices;
        }
        r.KI = K[0];
        r.KII = K[1];
        r.KIII = K[2];
        out.push_back(r);
    }
}

}  // namespace

std::vector<bem::FrontEdgeSif> estimate_sifs(const bem::BemSolution& sol, const SurfaceMesh& cracks,
                                             const SifEstimatorSettings& set, SifEstimatorReport* report,
                                             const std::vector<char>* moving) {
    if (!sol.surface) throw std::invalid_argument("SIF estimator: the solution has no surface");
    if (cracks.num_triangles() == 0)
        throw std::invalid_argument("SIF estimator: there is no crack front yet (no crack sheet); connect it where cracks exist, "
                                    "or use sif.fronts, which waits for them");
    const double nu = sol.surface->elastic.nu;
    const std::vector<double> area = crack_areas(cracks);
    const auto fronts = front_edges(cracks);
    if (fronts.empty()) throw std::invalid_argument("SIF estimator: the crack sheets have no front");
    for (const auto& f : fronts) {
        const double A = area[f.front().region];
        if (!(A > 0))
            throw std::invalid_argument("SIF estimator: crack '" + cracks.region_name(f.front().region) +
                                        "' has zero area; its coarse sheet needs triangles of positive area");
    }
    SifEstimatorReport rep;
    FrontStresses st = front_stresses(sol, cracks, fronts, set, moving, rep);
    std::vector<bem::FrontEdgeSif> out;
    for (std::size_t f = 0; f < fronts.size(); ++f) {
        if (!fill_unevaluated(st.sigma[f], st.evaluated[f])) continue;  // a stopped front gets no record
        smooth_along(st.sigma[f], true, set.smoothing_passes);  // extract_fronts gives closed loops
        const double sqrt_pi_a = std::pow(M_PI * area[fronts[f].front().region], 0.25);
        estimate_front(cracks, fronts[f], st.sigma[f], sqrt_pi_a, nu, set, rep, out);
    }
    // Same order as displacement correlation: by edge (v0, v1).
    std::sort(out.begin(), out.end(), [](const bem::FrontEdgeSif& a, const bem::FrontEdgeSif& b) {
        return std::make_pair(a.v0, a.v1) < std::make_pair(b.v0, b.v1);
    });
    if (report) *report = rep;
    return out;
}

}  // namespace cf::estimate
