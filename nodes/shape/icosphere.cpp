#include "nodes/shape/icosphere.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace cf {
namespace {

// The regular icosahedron on the unit sphere, faces counter-clockwise seen from outside.
SurfaceMesh unit_icosahedron() {
    const double t = (1 + std::sqrt(5.0)) / 2;
    SurfaceMesh m;
    m.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                  {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : m.vertices) p.normalize();
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    return m;
}

// Splits every triangle into four at its edge midpoints (shared between neighbours).
void split_in_four(SurfaceMesh& m, bool project_midpoints) {
    std::map<std::pair<int, int>, int> midpoint_of;
    auto midpoint = [&](int a, int b) {
        auto [it, inserted] = midpoint_of.emplace(std::minmax(a, b), static_cast<int>(m.vertices.size()));
        if (inserted) {
            Vec3 p = 0.5 * (m.vertices[a] + m.vertices[b]);
            if (project_midpoints) p.normalize();
            m.vertices.push_back(p);
        }
        return it->second;
    };
    std::vector<Tri> out;
    out.reserve(4 * m.triangles.size());
    for (const Tri& f : m.triangles) {
        const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
        out.push_back({f[0], ab, ca});
        out.push_back({ab, f[1], bc});
        out.push_back({ca, bc, f[2]});
        out.push_back({ab, bc, ca});
    }
    m.triangles = std::move(out);
}

}  // namespace

int icosphere_level_for(double target_triangles) {
    int best = 0;
    for (int k = 1; k <= max_icosphere_level; ++k)
        if (std::abs(static_cast<double>(icosphere_triangle_count(k)) - target_triangles) <
            std::abs(static_cast<double>(icosphere_triangle_count(best)) - target_triangles))
            best = k;
    return best;
}

SurfaceMesh make_icosphere(const SphereSpec& spec) {
    if (!(spec.radius > 0))
        throw std::invalid_argument("parameter 'radius' must be > 0 m, got " + graph::format_quantity(spec.radius, "m"));
    if (spec.level < 0 || spec.level > max_icosphere_level)
        throw std::invalid_argument("subdivision level must be in [0, " + std::to_string(max_icosphere_level) +
                                    "], got " + std::to_string(spec.level));
    SurfaceMesh m = unit_icosahedron();
    const bool per_level = spec.projection == SphereProjection::PerLevel;
    for (int k = 0; k < spec.level; ++k) split_in_four(m, per_level);
    for (Vec3& p : m.vertices) p = spec.centre + spec.radius * p.normalized();
    m.region.assign(m.triangles.size(), 0);
    m.region_names = {"surface"};
    return m;
}

}  // namespace cf
