#pragma once
// Rigid translations reproduced exactly by the double layer's rows.
//
// On a closed surface a rigid translation r is an elastic state with zero traction, so the exact
// operator satisfies (1/2 I + K) r = 0 at every surface point (Gauss's solid-angle integral; in the
// Guenter form K's action on a constant is the Laplace double layer times I). The Galerkin rows of K meet it only up to the
// quadrature error of the element pairs around each test element, which is largest on touching
// pairs across sharp ridges. V^-1 amplifies it about a hundredfold: a rigidly translated Dirichlet
// patch on a remeshed scan then carries tractions of 1e-2 to 1 E |d| / L where the exact one is 0.
//
// The classical cure ("rigid body motion" evaluation of the singular terms, Rizzo & Shippy 1977;
// Cruse 1974) computes each row's rigid sums and puts their error on the row's own nodes. Here, per
// P0 test element a, the 3 x 3 residual of the translations is taken in equal thirds off the blocks
// K[a, vertices of a]. A smooth field's row error begins with its value at a times the same
// residual, so the correction removes that leading term for every field, not only for rigid ones;
// the tests and rigid_translation_remeshed check it on a uniform strain.
#include "nodes/bem/element_geometry.hpp"

#include <Eigen/Core>
#include <vector>

namespace cf::bem {

struct RigidMotionRows {
    bool applied = false;     // false: the mesh is not a closed oriented manifold, or K is far off
    double max_residual = 0;  // before: max over rows of |translation residual|_F / area (dimensionless;
                              // sqrt(3) for a surface that is inside out)
    int worst_element = -1;   // the row (P0 test element) where max_residual is reached
};

// Measures and (if the surface qualifies) removes the translation residual of every row of
// K (3M x 3N, P0 test x P1 trial). `closed_oriented`: the mesh is a closed, consistently oriented
// 2-manifold. Rows are corrected only when every row's translation residual is below
// `limit` (a quadrature error; an inside-out or open surface gives residuals of order 1).
RigidMotionRows impose_rigid_motion_rows(Eigen::MatrixXd& K, const std::vector<ElementGeometry>& geometry,
                                         bool closed_oriented, double limit = 0.05);

}  // namespace cf::bem
