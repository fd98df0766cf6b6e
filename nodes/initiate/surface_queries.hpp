#pragma once
// Geometric queries against triangle meshes that crack placement needs (thesis ch. 4.4, ch. 6:
// crack sheets must stay strictly inside the body and clear of other sheets). Brute force over
// the triangles: the meshes involved are coarse BEM meshes. SI units (metres).
#include "nodes/bem/element_geometry.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <vector>

namespace cf::initiate {

// Unsigned distance [m] from p to the nearest triangle of `mesh` (infinity for an empty mesh).
double distance_to_mesh(const SurfaceMesh& mesh, const Vec3& p);

// Generalised winding number of a closed, outward-oriented mesh at p (1 inside, 0 outside),
// from the solid angles of its triangles (Van Oosterom and Strackee). Robust to small gaps.
double winding_number(const SurfaceMesh& mesh, const Vec3& p);
inline bool inside_closed_mesh(const SurfaceMesh& mesh, const Vec3& p) { return winding_number(mesh, p) > 0.5; }

// Triangles that a new crack sheet must not touch (the ordinary surface, existing sheets).
// Throws std::invalid_argument naming `what` for a degenerate triangle.
class TriangleObstacles {
public:
    void add(const SurfaceMesh& mesh, const char* what);
    // Whether any triangle of `m` touches or crosses an obstacle triangle (closed triangles,
    // with the relative tolerance of bem::triangles_intersect).
    bool intersects(const SurfaceMesh& m) const;
    std::size_t size() const { return triangles_.size(); }

private:
    std::vector<bem::ElementGeometry> triangles_;
};

}  // namespace cf::initiate
