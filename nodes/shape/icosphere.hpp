#pragma once
// A sphere tessellated as a subdivided icosahedron: 20 * 4^k triangles, 10 * 4^k + 2 vertices,
// every vertex on the sphere (an inscribed polyhedron, so its volume and area are below
// 4/3 pi r^3 and 4 pi r^2 and converge to them as O(h^2)).
#include "nodes/domain/surface_mesh.hpp"

#include <cstddef>

namespace cf {

// Where new vertices are put on the sphere.
enum class SphereProjection {
    // Each level's edge midpoints go onto the sphere along the sphere's true normal through them
    // (radially) before the next level splits: triangles stay close to equilateral.
    PerLevel,
    // The flat icosahedron is split k times and only then every vertex is moved onto the sphere
    // along its true normal (a class I geodesic sphere): triangles near the original 12
    // vertices come out smaller than those at face centres.
    Once,
};

struct SphereSpec {
    double radius = 1;      // [m], > 0
    Vec3 centre{0, 0, 0};   // [m]
    int level = 2;          // subdivision level k in [0, max_icosphere_level]
    SphereProjection projection = SphereProjection::PerLevel;
};

constexpr int max_icosphere_level = 8;  // 1,310,720 triangles

constexpr std::size_t icosphere_triangle_count(int level) { return std::size_t{20} << (2 * level); }
// The level whose triangle count 20 * 4^k is nearest to target (ties go to the smaller mesh),
// limited to [0, max_icosphere_level].
int icosphere_level_for(double target_triangles);

// Single region "surface". Throws std::invalid_argument for radius <= 0 or a level out of range.
SurfaceMesh make_icosphere(const SphereSpec& spec);

}  // namespace cf
