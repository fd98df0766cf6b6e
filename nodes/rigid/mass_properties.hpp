#pragma once
// Mass properties of a rigid body from its closed, outward-oriented triangle mesh (thesis ch. 7.3:
// a fragment's mass, centre of mass and inertia, computed exactly from the mesh rather than from a
// bounding box). Exact polyhedral integrals: the solid is the signed sum of the tetrahedra (p, a, b, c)
// of every triangle (a, b, c) with a reference point p; a tetrahedron's second moment is
// V/20 (sum of v v^T over its vertices + s s^T, s the sum of the vertices), relative to p.
// SI units: m, kg/m^3, kg, kg m^2.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>

namespace cf::rigid {

using Mat3 = Eigen::Matrix3d;

struct MassProperties {
    double volume = 0;                   // [m^3]
    double mass = 0;                     // [kg]
    Vec3 centre = Vec3::Zero();          // centre of mass [m]
    Mat3 inertia = Mat3::Zero();         // inertia tensor about the centre of mass, world axes [kg m^2]
    Mat3 principal_axes = Mat3::Identity();  // columns: unit principal axes (right-handed)
    Vec3 principal_moments = Vec3::Zero();   // ascending [kg m^2]
};

// Throws std::invalid_argument for a non-positive density or a mesh whose signed volume is not
// positive (open, or facing inward).
MassProperties mass_properties(const SurfaceMesh& mesh, double density);

}  // namespace cf::rigid
