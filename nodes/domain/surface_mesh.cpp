#include "surface_mesh.hpp"

#include <Eigen/Geometry>  // cross()

#include <algorithm>
#include <limits>

namespace cf {

std::string SurfaceMesh::region_name(int id) const {
    if (id >= 0 && id < static_cast<int>(region_names.size()) && !region_names[id].empty())
        return region_names[id];
    return "region" + std::to_string(id);
}

int SurfaceMesh::num_regions() const {
    int n = static_cast<int>(region_names.size());
    for (int r : region) n = std::max(n, r + 1);
    if (n == 0 && !triangles.empty()) n = 1;
    return n;
}

Vec3 triangle_normal_unnormalised(const SurfaceMesh& m, std::size_t t) {
    const Tri& f = m.triangles[t];
    const Vec3& a = m.vertices[f[0]];
    return (m.vertices[f[1]] - a).cross(m.vertices[f[2]] - a);
}

Vec3 triangle_normal(const SurfaceMesh& m, std::size_t t) {
    Vec3 n = triangle_normal_unnormalised(m, t);
    double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double triangle_area(const SurfaceMesh& m, std::size_t t) {
    return 0.5 * triangle_normal_unnormalised(m, t).norm();
}

Vec3 triangle_centroid(const SurfaceMesh& m, std::size_t t) {
    const Tri& f = m.triangles[t];
    return (m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0;
}

double surface_area(const SurfaceMesh& m) {
    double a = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) a += triangle_area(m, t);
    return a;
}

double signed_volume(const SurfaceMesh& m) {
    double v = 0;
    for (const Tri& f : m.triangles)
        v += m.vertices[f[0]].dot(m.vertices[f[1]].cross(m.vertices[f[2]]));
    return v / 6.0;
}

Box3 bounding_box(const SurfaceMesh& m) {
    Box3 b{Vec3::Constant(std::numeric_limits<double>::infinity()),
           Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const Vec3& p : m.vertices) {
        b.min = b.min.cwiseMin(p);
        b.max = b.max.cwiseMax(p);
    }
    return b;
}

}  // namespace cf
