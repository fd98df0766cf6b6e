#pragma once
// Boundary regions of a fine mesh (e.g. face groups read by import.mesh) carried over to a coarse
// mesh remeshed from its level set (simplify.remesh): each coarse triangle takes the region of the
// fine triangle closest to its centroid, the centroid deciding as it does for regions.halfspace
// (nodes/regions/README.md). Kept apart from the remesher so that rewriting one leaves the other.
#include "nodes/domain/surface_mesh.hpp"

#include <string>
#include <vector>

namespace cf {

struct CarriedRegions {
    SurfaceMesh mesh;                       // the coarse mesh with the fine mesh's region ids and names
    std::vector<std::string> empty_regions;  // fine regions (with triangles) that no coarse triangle took
};

// Throws std::invalid_argument when `fine` has no triangles.
CarriedRegions carry_regions(const SurfaceMesh& coarse, const SurfaceMesh& fine);

}  // namespace cf
