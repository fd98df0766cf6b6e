#include "nodes/segment/fracture_faces.hpp"

#include "nodes/segment/surface_fragments.hpp"

#include <cmath>
#include <stdexcept>

namespace cf {

void tag_fracture_faces(SurfaceMesh& m, const LevelSet& object, double depth) {
    if (!(depth > 0) || !std::isfinite(depth))
        throw std::invalid_argument("fracture-face depth must be a positive number of metres");
    std::vector<Vec3> centroids(m.num_triangles());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) centroids[t] = triangle_centroid(m, t);
    const std::vector<double> phi = sample_points(object, centroids);
    // Outside faces first, then inside ones, each in their old order: the writers start a group
    // (OBJ g / usemtl) wherever the region changes, so contiguous regions give one group each.
    std::vector<Tri> outside, inside;
    std::vector<std::array<Vec2, 3>> uv_out, uv_in;
    std::vector<std::array<Vec3, 3>> n_out, n_in;
    const bool uv = m.has_uv(), normals = m.has_normals();
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const bool deep = phi[t] < -depth;
        (deep ? inside : outside).push_back(m.triangles[t]);
        if (uv) (deep ? uv_in : uv_out).push_back(m.corner_uv[t]);
        if (normals) (deep ? n_in : n_out).push_back(m.corner_normal[t]);
    }
    m.region.assign(outside.size(), 0);
    m.region.resize(m.num_triangles(), 1);
    m.region_names = {kOutsideRegion, kInsideRegion};
    m.triangles = std::move(outside);
    m.triangles.insert(m.triangles.end(), inside.begin(), inside.end());
    if (uv) {
        m.corner_uv = std::move(uv_out);
        m.corner_uv.insert(m.corner_uv.end(), uv_in.begin(), uv_in.end());
    }
    if (normals) {
        m.corner_normal = std::move(n_out);
        m.corner_normal.insert(m.corner_normal.end(), n_in.begin(), n_in.end());
    }
}

double region_area(const SurfaceMesh& m, const std::string& name) {
    double a = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        if (m.region_name(m.region_of(t)) == name) a += triangle_area(m, t);
    return a;
}

}  // namespace cf
