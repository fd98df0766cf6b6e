#include "nodes/initiate/surface_queries.hpp"

#include "nodes/bem/surface_intersection.hpp"
#include "nodes/domain/triangle_closest_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cf::initiate {

double distance_to_mesh(const SurfaceMesh& mesh, const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const Tri& t : mesh.triangles) {
        const Vec3 q = closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]).point;
        best = std::min(best, (p - q).norm());
    }
    return best;
}

double winding_number(const SurfaceMesh& mesh, const Vec3& p) {
    double total = 0;
    for (const Tri& t : mesh.triangles) {
        const Vec3 a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p, c = mesh.vertices[t[2]] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double num = a.dot(b.cross(c));
        const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2 * std::atan2(num, den);  // solid angle of the triangle seen from p
    }
    return total / (4 * M_PI);
}

void TriangleObstacles::add(const SurfaceMesh& mesh, const char* what) {
    const std::vector<bem::ElementGeometry> g = bem::element_geometries(mesh, what);
    triangles_.insert(triangles_.end(), g.begin(), g.end());
}

bool TriangleObstacles::intersects(const SurfaceMesh& m) const {
    if (m.triangles.empty() || triangles_.empty()) return false;
    for (const bem::ElementGeometry& x : bem::element_geometries(m, "new crack sheet"))
        for (const bem::ElementGeometry& y : triangles_)
            if (bem::triangles_intersect(x, y)) return true;
    return false;
}

}  // namespace cf::initiate
