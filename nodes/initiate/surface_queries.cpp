#include "nodes/initiate/surface_queries.hpp"

#include "nodes/bem/surface_intersection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cf::initiate {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

double distance_to_mesh(const SurfaceMesh& mesh, const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const Tri& t : mesh.triangles) {
        const Vec3 q = closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
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
