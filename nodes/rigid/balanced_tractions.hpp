#pragma once
// Balanced tractions (thesis ch. 7.2, eq. 7.5): the piecewise-constant traction field closest to
// the collision tractions q_i that exerts no net force and no net torque, so the pure Neumann
// problem (eq. 7.4) has an equilibrium solution. With S = [S_f; S_tau] (6 x 3M: S_f q = sum A_e q_e,
// S_tau q = sum A_e (c_e - c) x q_e, moments about the area centroid c rather than the origin, which
// keeps the 6 x 6 system well conditioned wherever the body is) and the weighted objective
// min q_c^T W q_c, W = I (the thesis) or diag(A_e) (area-weighted, optional):
//   q = q_i - q_c,  q_c = W^-1 S^T (S W^-1 S^T)^-1 S q_i,
// S W^-1 S^T built in one pass over the elements. SI units: Pa, m^2, m.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>
#include <vector>

namespace cf::rigid {

using Mat3 = Eigen::Matrix3d;

struct BalancedTractions {
    std::vector<Vec3> traction;          // q per element [Pa]
    Vec3 removed_force = Vec3::Zero();   // S_f q_i [N]
    Vec3 removed_torque = Vec3::Zero();  // S_tau q_i about the area centroid [N m]
};

// `traction` per triangle of `mesh`. Throws std::invalid_argument for a size mismatch, a degenerate
// mesh (zero area) or a mesh whose 6 x 6 system is singular (all elements on one line).
BalancedTractions balance_tractions(const SurfaceMesh& mesh, const std::vector<Vec3>& traction, bool area_weighted = false);

// Net force [N] and torque [N m] about the area centroid of per-element tractions.
void traction_resultants(const SurfaceMesh& mesh, const std::vector<Vec3>& traction, Vec3& force, Vec3& torque);

}  // namespace cf::rigid
