#pragma once
// Crack-opening estimator of thesis ch. 5.2: a crack node that a front leaves behind in a BEM
// step gets the opening that displacement correlation would read there, eq. (5.5)-(5.6), from the
// SIFs the front had at the start of the step and the distance d the front has moved past it.
// The constants are the inverse of sif.displacement_correlation's full-jump form, so correlating
// an estimated opening returns the SIFs it came from:
//   [u].n1 = 4 (1 - nu) sqrt(d) K_I  / (mu sqrt(2 pi)),   [u].n2 = 4 (1 - nu) sqrt(d) K_II / (mu sqrt(2 pi)),
//   [u].n3 = 4 sqrt(d) K_III / (mu sqrt(2 pi))
// (eq. 5.5 writes the one-face displacement, half the jump). SI units: Pa sqrt(m), m.
#include "nodes/bem/estimated_growth.hpp"
#include "nodes/propagate/crack_front.hpp"

namespace cf::propagate {

// Eq. (5.5)-(5.6) in the front frame (n1 normal, n2 forward, n3 = n1 x n2; K_III signed with n3).
Vec3 opening_from_sifs(const Sifs& K, const FrontFrame& frame, double d, double E, double nu);

// For every node of `old_front` (with node SIFs and frames) that is not a node of `new_front`:
// its opening with d = its distance to the new front's polyline, stored in `estimate` (resized to
// the crack mesh; a node keeps the first opening it was given). Returns the number of nodes set.
std::size_t estimate_openings_left_behind(const SurfaceMesh& cracks, const CrackFront& old_front, const CrackFront& new_front,
                                          double E, double nu, bem::CrackOpeningEstimate& estimate);

}  // namespace cf::propagate
