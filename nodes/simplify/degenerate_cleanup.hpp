#pragma once
// Removal of zero-area slivers from a closed manifold triangle mesh (ch. 6.1: the coarse BEM
// mesh must have no degenerate elements; QEM on large flat faces leaves vertices on the
// opposite edge, "caps", or next to another vertex, "needles"). Plain C++, no CGAL.
#include "nodes/domain/surface_mesh.hpp"

#include <cstddef>

namespace cf {

struct DegenerateCleanup {
    std::size_t flips = 0;      // caps fixed by flipping their longest edge (count unchanged)
    std::size_t collapses = 0;  // needles fixed by collapsing their shortest edge (2 triangles fewer)
    std::size_t left = 0;       // degenerate triangles no admissible flip or collapse could remove
};

// A triangle is a sliver when twice its area is at most `ratio` * (longest edge)^2 (the measure
// of check_topology, nodes/domain/mesh_topology.hpp). Each sliver is removed by
//  - a cap (its apex projects well inside the longest edge): flipping the longest edge; the two
//    new triangles cover the neighbour across that edge, so the surface does not move;
//  - a needle (apex close to an end of the longest edge), or a cap whose flip is not admissible:
//    collapsing its shortest edge onto one end point or the midpoint, whichever turns the
//    surrounding triangles' normals least.
// An operation is admissible only if it keeps the mesh manifold (link condition, no duplicate
// edge), creates no new sliver and turns no changed triangle's normal by more than 60 degrees,
// so every step lowers the sliver count and the pass terminates. Vertices left unused by
// collapses are dropped. The mesh must be closed, manifold and consistently oriented.
DegenerateCleanup remove_degenerate_triangles(SurfaceMesh& mesh, double ratio = 1e-6);

}  // namespace cf
