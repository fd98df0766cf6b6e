#pragma once
// Triangulation of a planar crack region for the BEM (thesis ch. 4.4, App. A item 12): CGAL's 2D
// constrained Delaunay triangulation refined by Delaunay_mesher_2 with a size criterion.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>
#include <vector>

namespace cf::initiate {

using Vec2 = Eigen::Vector2d;

// Meshes the simple polygon `boundary` (2D, counter-clockwise or clockwise, not closed by a
// repeated point) with triangles whose longest edge is at most `max_edge` [m] and whose angles
// are above ~20 degrees (boundary segments may be split, never moved).
// `interior_point` (strictly inside the polygon) becomes a vertex, so the mesh has an interior
// node. Vertices are mapped to 3D as origin + x t1 + y t2; triangles are oriented with normal
// t1 x t2. One region named `name`. Throws std::invalid_argument for fewer than 3 points or a
// non-positive max_edge.
SurfaceMesh mesh_planar_region(const std::vector<Vec2>& boundary, const Vec2& interior_point, double max_edge,
                               const Vec3& origin, const Vec3& t1, const Vec3& t2, const std::string& name);

}  // namespace cf::initiate
