#pragma once
// Checks that a triangle list is a closed, manifold, consistently and outward-oriented surface
// (what the SGBEM needs of an object boundary), optionally repairing the orientation. Works on
// any triangle list; when the triangles came from a file, `where` names each one's origin so
// every message points at a line.
#include "nodes/import/mesh_soup.hpp"

#include <string>
#include <vector>

namespace cf {

struct SurfaceCheckResult {
    std::size_t flipped_triangles = 0;  // re-oriented (only with reorient)
    std::size_t components = 0;         // connected shells
};

// Throws MeshFileError for, in this order: a non-manifold edge (shared by > 2 triangles), an
// open boundary (edges used once), a non-manifold vertex (surface sheets touching at a point),
// inconsistent orientation (an edge traversed the same way by both its triangles; with
// `reorient` each connected shell is made consistent by breadth-first search from its first
// triangle instead), a non-orientable shell, a shell enclosing zero volume, and a shell facing
// the wrong way (with `reorient` it is flipped instead). "Facing the right way" means positive
// signed volume for a shell nested inside an even number of other shells (solid parts) and
// negative for an odd number (cavities); nesting is found with the generalised winding number.
// Triangles must already be non-degenerate with distinct corners.
SurfaceCheckResult check_closed_surface(const std::vector<Vec3>& vertices, std::vector<Tri>& triangles,
                                        const std::string& file, const std::vector<FileLocation>& where,
                                        bool reorient);

}  // namespace cf
