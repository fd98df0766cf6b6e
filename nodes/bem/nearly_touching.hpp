#pragma once
// Why a BEM surface's blocks can fail to be positive definite although the mesh is closed and
// oriented: two triangles that share no vertex but lie much closer than their size (a fold of a
// remeshed organic shape, a thin slot). Their integrals are taken as separated pairs with regular
// rules (quadrature.hpp), which lose accuracy as the gap shrinks against the triangles; far enough
// off, the dense blocks stop being positive definite. Used to say where, when a factorisation fails.
#include "nodes/bem/element_geometry.hpp"

#include <string>
#include <vector>

namespace cf::bem {

struct NearlyTouchingPair {
    bool found = false;        // some pair of triangles without a common vertex exists
    int a = -1, b = -1;        // triangle indices
    double gap = 0;            // their distance [m]
    double size = 0;           // the longer of their longest edges [m]
    Vec3 where = Vec3::Zero(); // midway between their closest points [m]
    double ratio() const { return size > 0 ? gap / size : 0; }
};

// Distance between two triangles [m] (0 when they meet) and the midpoint of its closest points
// (also the fragment cracks' clearance test, nodes/propagate/fragment_cracks.cpp).
double triangle_distance(const ElementGeometry& a, const ElementGeometry& b, Vec3* midpoint = nullptr);

// The pair of triangles without a common vertex with the smallest gap / size.
NearlyTouchingPair nearly_touching_pair(const std::vector<ElementGeometry>& g);

// A sentence for an error message: the pair, its gap and size, and what to do; empty when no pair
// comes closer than `ratio_limit` times its size.
std::string describe_nearly_touching(const std::vector<ElementGeometry>& g, double ratio_limit = 0.25);

// A sentence for an error message about the element whose row of the double layer misses the rigid
// translations most (rigid_motion_rows.hpp: `residual`, dimensionless): where it is, by how much, and
// the sharpest fold between it and a triangle sharing an edge with it (the touching pairs' rules lose
// accuracy across sharp folds and on slivers). Empty when the residual is below `residual_limit`
// (well-shaped closed surfaces stay near 1e-4).
std::string describe_worst_row(const std::vector<ElementGeometry>& g, int element, double residual,
                               double residual_limit = 1e-3);

}  // namespace cf::bem
