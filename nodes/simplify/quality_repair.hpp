#pragma once
// Local repair of element shape on a closed triangle mesh (issue 13): every triangle angle at
// least `min_angle_deg` and every dihedral between neighbours (180 = flat) at least
// `min_dihedral_deg`. Plain C++, no CGAL.
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/simplify/mesh_quality.hpp"

#include <cstddef>
#include <functional>

namespace cf {

struct QualityBounds {
    double min_angle_deg = 15;
    double min_dihedral_deg = 30;
};

struct QualityRepair {
    std::size_t flips = 0;      // edge flips (count unchanged)
    std::size_t collapses = 0;  // edge collapses (2 triangles fewer each)
    std::size_t moves = 0;      // single vertices moved towards their neighbours' centroid
    std::size_t splits = 0;     // edges split at their projected midpoint (2 triangles more each)
    MeshQuality after;          // measured on the result, with the bounds' counts
};

// Point on the surface the mesh approximates nearest to p (e.g. a level set's iso-surface); empty:
// vertices keep the position an operation gives them.
using SurfaceProjection = std::function<Vec3(const Vec3&)>;

// Repeatedly takes each triangle with an angle below the bound or an edge with a dihedral below
// it and applies, of these candidates, the one that raises the worst normalised quality
// min(angle / bound, dihedral / bound) of the triangles it changes (and their neighbours' edges)
// the most, if any raises it:
//  - flipping an edge of the triangle, only where the two triangles are flat to within 20 degrees
//    (the surface does not move) or fold onto each other (the fold is the defect);
//  - collapsing an edge onto one end, the midpoint or its projection (link condition kept, no
//    surviving triangle's normal turned by more than 45 degrees);
//  - moving a vertex to its neighbours' centroid, projected (the same normal bound);
//  - with a projection, splitting an edge at its projected midpoint (where a thin part's rim is
//    sharper than the elements: the new vertex on the rounded rim opens the dihedral).
// Stops when no element violates a bound or no candidate helps (at most `max_passes` passes).
// The mesh must be closed, manifold and consistently oriented; it stays so. Unused vertices are
// dropped. `after` reports the bounds actually met: the caller decides whether that is enough.
QualityRepair improve_quality(SurfaceMesh& mesh, const QualityBounds& bounds, const SurfaceProjection& project = {},
                              int max_passes = 30);

}  // namespace cf
