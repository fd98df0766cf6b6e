#pragma once
// Displacement and stress of an SGBEM solution at points inside the body: the representation
// formula (thesis eq. 2.20) and its stress (eq. 2.23), evaluated by nodes/bem/interior_evaluation,
// at user-given points or on a rectangular grid slice. SI units: metres, Pa.
#include "nodes/bem/solver.hpp"

#include <string>
#include <vector>

namespace cf::probes {

// A planar grid: points origin + i/(nu-1) u + j/(nv-1) v, i < nu, j < nv (row-major, i fastest).
struct GridSlice {
    Vec3 origin = Vec3::Zero(), u = Vec3::UnitX(), v = Vec3::UnitY();  // [m]
    int nu = 0, nv = 0;                                                  // points along u and v (>= 2 each)
    std::vector<Vec3> points() const;
};

struct ProbeSample {
    int index = 0;                // user point index, or grid point index i + nu j
    Vec3 x = Vec3::Zero();        // [m]
    Vec3 u = Vec3::Zero();        // displacement [m]
    Eigen::Matrix3d stress;       // Cauchy stress [Pa]
    Vec3 principal = Vec3::Zero();  // principal stresses sigma_1 >= sigma_2 >= sigma_3 [Pa]
};

// Principal values of a symmetric stress, largest first.
Vec3 principal_stresses(const Eigen::Matrix3d& s);

// Samples at user-given points. Throws std::invalid_argument naming the point (index and
// coordinates) when one lies outside the body or on its surface (generalised winding number of the
// solution's surface below 1/2, or closer to it than 1e-9 of the bounding-box diagonal) or on a crack sheet.
std::vector<ProbeSample> probe_points(const bem::BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks = true);

// Samples at the grid points that lie inside the body and off the crack sheets (others are left
// out: a slice through a curved body has corners outside it, one through a crack's plane points on
// it). Throws std::invalid_argument when no grid point is left.
std::vector<ProbeSample> probe_slice(const bem::BemSolution& sol, const GridSlice& slice, bool include_cracks = true);

}  // namespace cf::probes
