#include "nodes/probes/probe_points.hpp"

#include "graph/cancel_token.hpp"
#include "graph/diagnostics.hpp"
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/initiate/surface_queries.hpp"

#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <stdexcept>

namespace cf::probes {

std::vector<Vec3> GridSlice::points() const {
    std::vector<Vec3> p;
    if (nu < 2 || nv < 2) throw std::invalid_argument("a grid slice needs at least 2 points along each axis");
    p.reserve(std::size_t(nu) * nv);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) p.push_back(origin + (double(i) / (nu - 1)) * u + (double(j) / (nv - 1)) * v);
    return p;
}

Vec3 principal_stresses(const Eigen::Matrix3d& s) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (s + s.transpose()), Eigen::EigenvaluesOnly);
    const Vec3 e = es.eigenvalues();  // ascending
    return Vec3(e[2], e[1], e[0]);
}

namespace {

std::string point_text(const Vec3& p) {
    return "(" + graph::format_number(p.x()) + ", " + graph::format_number(p.y()) + ", " + graph::format_number(p.z()) + ")";
}

// Inside strictly: winding number above 1/2 and not within the surface tolerance the interior
// evaluation uses (there it would return the boundary trace and refuse the stress).
bool strictly_inside(const SurfaceMesh& surface, double tolerance, const Vec3& p) {
    return initiate::winding_number(surface, p) > 0.5 && initiate::distance_to_mesh(surface, p) > tolerance;
}

std::vector<ProbeSample> evaluate(const bem::BemSolution& sol, const std::vector<Vec3>& pts, const std::vector<int>& index,
                                  bool include_cracks) {
    std::vector<Vec3> u;
    std::vector<Eigen::Matrix3d> s;
    try {
        u = bem::interior_displacement(sol, pts, include_cracks);
        s = bem::interior_stress(sol, pts, include_cracks);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("a probe point cannot be evaluated: ") + e.what() +
                                    "; move it off the crack sheets");
    }
    std::vector<ProbeSample> out(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
        out[k].index = index[k];
        out[k].x = pts[k];
        out[k].u = u[k];
        out[k].stress = 0.5 * (s[k] + s[k].transpose());
        out[k].principal = principal_stresses(out[k].stress);
    }
    return out;
}

double surface_tolerance(const SurfaceMesh& m) { return 1e-9 * bounding_box(m).extent().norm(); }

}  // namespace

std::vector<ProbeSample> probe_points(const bem::BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks) {
    const SurfaceMesh& surface = sol.surface->mesh;
    const double tol = surface_tolerance(surface);
    std::vector<int> index;
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (!points[k].allFinite()) throw std::invalid_argument("probe point " + std::to_string(k) + " is not finite");
        if (!strictly_inside(surface, tol, points[k])) {
            const Box3 b = bounding_box(surface);
            throw std::invalid_argument("probe point " + std::to_string(k) + " " + point_text(points[k]) +
                                        " [m] is not inside the object (its surface spans " + point_text(b.min) + " to " +
                                        point_text(b.max) + "); move it inside");
        }
        index.push_back(static_cast<int>(k));
    }
    return evaluate(sol, points, index, include_cracks);
}

std::vector<ProbeSample> probe_slice(const bem::BemSolution& sol, const GridSlice& slice, bool include_cracks) {
    const SurfaceMesh& surface = sol.surface->mesh;
    const double tol = surface_tolerance(surface);
    const std::vector<Vec3> all = slice.points();
    const SurfaceMesh* cracks = include_cracks ? bem::current_crack_mesh(sol) : nullptr;
    // Each test is a pass over the surface (winding number, distance): for a large slice that is
    // seconds, so it runs in parallel and polls for Ctrl-C; the kept points stay in grid order.
    std::vector<char> keep(all.size(), 0);
    const CancelToken cancel = CancelToken::current();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, all.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
        cancel.poll();
        for (std::size_t k = r.begin(); k != r.end(); ++k)
            // A grid point on a crack sheet (a slice through a crack's plane) has two displacements: left out.
            keep[k] = strictly_inside(surface, tol, all[k]) &&
                      !(cracks && cracks->num_triangles() > 0 && initiate::distance_to_mesh(*cracks, all[k]) <= tol);
    });
    std::vector<Vec3> inside;
    std::vector<int> index;
    for (std::size_t k = 0; k < all.size(); ++k)
        if (keep[k]) {
            inside.push_back(all[k]);
            index.push_back(static_cast<int>(k));
        }
    if (inside.empty())
        throw std::invalid_argument("no point of the grid slice lies inside the object; check its origin and axes (m)");
    return evaluate(sol, inside, index, include_cracks);
}

}  // namespace cf::probes
