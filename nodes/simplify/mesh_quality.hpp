#pragma once
// Element quality of a closed triangle mesh, the two measures simplify.remesh guarantees bounds on
// (issue 13: a needle folded onto its neighbour gives the BEM tractions of 1e8 Pa under a rigid
// motion): the smallest interior angle of any triangle, and the smallest dihedral angle between
// two triangles sharing an edge, measured so that a flat surface is 180 degrees and a triangle
// folded back onto its neighbour is 0 (180 minus the angle between the two face normals; the same
// for convex and concave edges). Plain C++, no CGAL.
#include "nodes/domain/surface_mesh.hpp"

#include <cstddef>
#include <string>

namespace cf {

struct MeshQuality {
    double min_angle_deg = 180;     // smallest triangle angle; 0 for a zero-area triangle
    double min_dihedral_deg = 180;  // smallest dihedral over edges with exactly two triangles
    std::size_t worst_triangle = 0;  // where min_angle_deg is attained
    Vec3 worst_angle_at = Vec3::Zero();     // that triangle's centroid [m]
    Vec3 worst_dihedral_at = Vec3::Zero();  // midpoint of the edge of min_dihedral_deg [m]
    std::size_t angles_below = 0;     // triangles with an angle below the bound asked for
    std::size_t dihedrals_below = 0;  // edges with a dihedral below the bound asked for
};

// Smallest angle of triangle (a, b, c) [degrees]; 0 for coincident points.
double min_triangle_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c);
// Dihedral [degrees] between triangles with (not necessarily unit) normals n1 and n2 sharing an
// edge: 180 minus the angle between the normals; 0 when either normal is zero.
double dihedral_deg(const Vec3& n1, const Vec3& n2);

// Measures every triangle and every two-triangle edge; counts those below the given bounds.
MeshQuality measure_quality(const SurfaceMesh& mesh, double angle_bound_deg = 0, double dihedral_bound_deg = 0);

// One line: "min angle 16.2 deg (triangle 17 at (x, y, z) m), min dihedral 41.0 deg (edge at ...)".
std::string describe(const MeshQuality& q);

}  // namespace cf
