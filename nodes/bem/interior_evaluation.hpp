#pragma once
// Post-processing of an SGBEM solution inside the body (thesis eq. 2.20, 2.23, ch. 6.4):
//   u(x) = int_Gamma U*(x,y) t(y) ds_y - int_Gamma T(x,y)^T u(y) ds_y + int_Sigma T(x,y)^T [u](y) ds_y
// (sgbem-math.md §0 and §2 "Cracks": the crack sheet adds +W_Sigma[u] with [u] = u+ - u- and the sheet
// normal n pointing from "-" to "+"), and sigma(x) = lambda tr(grad u) I + mu (grad u + grad u^T) with
// grad u from the x-derivatives of the same kernels (equivalent to the Kelvin stress kernels S1, S2 of
// eq. 2.24). Data: P1 displacement and P0 traction on Gamma, P1 opening on Sigma, as solved.
//
// Quadrature near the surface: every triangle is integrated by adaptive subdivision. A (sub)triangle
// whose distance to x is below `leaf_ratio` times its longest edge is split into four by its edge
// midpoints, up to `max_depth` levels; leaves use a rule chosen by distance/size: >= 8 -> 6-point
// (degree 4), >= 4 -> 4x4 collapsed Gauss, otherwise 6x6 collapsed Gauss. The cost near the surface
// grows like log(h / distance), and the relative error stays at about 1e-7 down to distances of
// h * 2^-max_depth (measured in tests/bem/interior_evaluation_test.cpp).
#include "nodes/bem/solver.hpp"

#include <vector>

namespace cf::bem {

struct InteriorQuadrature {
    double leaf_ratio = 1.5;  // subdivide while distance < leaf_ratio * longest edge
    int max_depth = 14;       // subdivision levels at most (2^-14 h is the closest resolved distance)
    // The gradient's kernel terms four rule points at a time (the same bits as one at a time, which
    // false selects: the reference the tests compare with).
    bool four_points_at_a_time = true;
};

// Displacement [m] at points strictly inside the body. `include_cracks` adds the crack term.
// A point closer to Gamma than 1e-9 of the bounding-box diagonal gets the boundary trace (the P1
// interpolant at its closest surface point); a point on a crack sheet (same tolerance) throws
// std::invalid_argument naming it, because the displacement jumps there.
std::vector<Vec3> interior_displacement(const BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks = true,
                                        const InteriorQuadrature& q = {});

// Displacement gradient G[j][l] = du_j/dx_l and stress [Pa] at interior points (eq. 2.23).
// Throws std::invalid_argument for a point on Gamma or on a crack sheet (the kernels are singular
// there; surface stress is eq. 4.6, a different evaluation).
std::vector<Mat3> interior_displacement_gradient(const BemSolution& sol, const std::vector<Vec3>& points,
                                                 bool include_cracks = true, const InteriorQuadrature& q = {});
std::vector<Mat3> interior_stress(const BemSolution& sol, const std::vector<Vec3>& points, bool include_cracks = true,
                                  const InteriorQuadrature& q = {});

// The crack's average displacement u_c at every crack vertex (thesis ch. 6.4): eq. (2.20)
// integrated over the ordinary surface only, excluding every crack. The faces then move by
// u+- = u_c +- [u]/2. Crack vertices on Gamma (surface-reaching cracks) get the boundary trace.
std::vector<Vec3> crack_average_displacement(const BemSolution& sol, const InteriorQuadrature& q = {});

}  // namespace cf::bem
