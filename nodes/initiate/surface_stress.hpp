#pragma once
// Per-element surface stress from nodal displacements and the element traction (thesis ch. 4.3,
// eq. 4.4-4.6), and principal stresses. SI units: metres, Pa.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>
#include <array>

namespace cf::initiate {

using Mat3 = Eigen::Matrix3d;

// 3D stress of one triangle (a, b, c) [m] with nodal displacements u [m], constant traction q [Pa]
// (sigma n1 = q, n1 = unit normal (b-a)x(c-a)), Young's modulus E [Pa] and Poisson's ratio nu.
// In-plane stress by a linear-triangle FEM step, eq. (4.4)-(4.5), in the plane-stress form the
// text derives (E* = E/(1-nu^2), i.e. lambda* = E nu/(1-nu^2) in S) on the triangle's own
// co-rotated 2D frame; Poisson correction q_i = q_i* + n1 (q.n_i) + n_i (q.n1) nu/(1-nu) and
// dyadic sum eq. (4.6). The result is symmetric and reproduces q on the normal.
// Throws std::invalid_argument for a degenerate triangle.
Mat3 surface_stress(const std::array<Vec3, 3>& corners, const std::array<Vec3, 3>& displacement, const Vec3& traction,
                    double E, double nu);

// Signed principal stresses, ascending (min, mid, max) [Pa], with unit directions as columns.
struct PrincipalStress {
    Vec3 values;
    Mat3 directions;
    double max() const { return values[2]; }
    double min() const { return values[0]; }
    Vec3 max_direction() const { return directions.col(2); }
    Vec3 min_direction() const { return directions.col(0); }
};
PrincipalStress principal_stresses(const Mat3& sigma);

}  // namespace cf::initiate
