#pragma once
// Surface stress of every BEM element from a solution (thesis ch. 4.3-4.4, eq. 4.4-4.6): ordinary
// surface elements from the nodal displacements and element tractions, crack elements from the
// displacements of their two faces. SI units (m, Pa).
#include "nodes/bem/solver.hpp"
#include "nodes/initiate/initiation.hpp"

#include <vector>

namespace cf::initiate {

// Young's modulus [Pa] of the constants the BEM was assembled with (E = 2 mu (1 + nu)).
double youngs_modulus(const bem::ElasticConstants& c);

// Per ordinary-surface element: eq. (4.6) from u_i of its nodes and its traction q_e; the
// normal is the outward element normal. Throws std::invalid_argument when the solution's
// arrays do not match its mesh.
std::vector<ElementStress> surface_element_stresses(const bem::BemSolution& sol);

// The two faces of a crack element (ch. 4.4, branching). With the sheet normal n pointing from
// the "-" to the "+" side and [u] = u+ - u-, the "+" face bounds the material on the +n side,
// so its outward normal is -n, and it moves by u+ = u_c + [u]/2; the "-" face has outward
// normal +n and moves by u- = u_c - [u]/2. Crack faces are traction-free: q = 0 in eq. (4.6).
struct CrackFaceStress {
    ElementStress plus, minus;
};

// `average_displacement` is u_c per crack vertex (bem::crack_average_displacement). Throws
// std::invalid_argument when the solution has no cracks or the sizes disagree.
std::vector<CrackFaceStress> crack_face_stresses(const bem::BemSolution& sol, const std::vector<Vec3>& average_displacement);

// How far a stress exceeds the strength S at its centroid: max(sigma_max - S, -sigma_min - f_c S)
// [Pa] (condition (a) of ch. 4.4; positive when a crack may start).
double strength_excess(const ElementStress& e, const ScalarField& strength);

}  // namespace cf::initiate
