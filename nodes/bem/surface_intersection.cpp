#include "nodes/bem/surface_intersection.hpp"

#include "graph/cancel_token.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cf::bem {

bool segment_meets_triangle(const Vec3& p, const Vec3& q, const ElementGeometry& t) {
    const double tol = 1e-10 * t.diameter;
    const double dp = (p - t.p[0]).dot(t.normal), dq = (q - t.p[0]).dot(t.normal);
    if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) return false;
    Vec3 x;
    if (std::abs(dp - dq) <= tol) {
        // Segment (nearly) in the plane: count it when an end point or the midpoint is inside.
        for (const Vec3& c : {p, q, Vec3(0.5 * (p + q))}) {
            bool inside = true;
            for (int k = 0; k < 3 && inside; ++k) {
                const Vec3 e = t.p[(k + 1) % 3] - t.p[k];
                inside = t.normal.dot(e.cross(c - t.p[k])) >= -tol * e.norm();
            }
            if (inside && std::abs((c - t.p[0]).dot(t.normal)) <= tol) return true;
        }
        return false;
    }
    x = p + (dp / (dp - dq)) * (q - p);
    for (int k = 0; k < 3; ++k) {
        const Vec3 e = t.p[(k + 1) % 3] - t.p[k];
        if (t.normal.dot(e.cross(x - t.p[k])) < -tol * e.norm()) return false;
    }
    return true;
}

bool triangles_intersect(const ElementGeometry& a, const ElementGeometry& b) {
    if ((a.centroid - b.centroid).norm() > a.diameter + b.diameter) return false;
    for (int k = 0; k < 3; ++k) {
        if (segment_meets_triangle(a.p[k], a.p[(k + 1) % 3], b)) return true;
        if (segment_meets_triangle(b.p[k], b.p[(k + 1) % 3], a)) return true;
    }
    return false;
}

void check_crack_clear_of_surface(const std::vector<ElementGeometry>& surface, const std::vector<ElementGeometry>& crack,
                                  std::size_t first, const SurfaceMesh& cracks) {
    const CancelToken cancel = CancelToken::current();  // per crack triangle: one pass over the surface
    for (std::size_t c = first; c < crack.size(); ++c) {
        cancel.poll();
        for (std::size_t s = 0; s < surface.size(); ++s)
            if (triangles_intersect(crack[c], surface[s]))
                throw std::invalid_argument("crack '" + cracks.region_name(cracks.region_of(c)) + "' triangle " +
                                            std::to_string(c) + " touches or crosses surface triangle " + std::to_string(s) +
                                            "; cracks must lie strictly inside the body (shrink or move the crack)");
    }
}

}  // namespace cf::bem
