#pragma once
// The BEM verification cases of docs/verification.md (sections "Operator identities",
// "Elastostatic solutions" 1-3 and "Fracture mechanics" 5), run by `crackflow verify` and ctest.
#include "nodes/bem/solver.hpp"
#include "nodes/domain/verification_case.hpp"

#include <vector>

namespace cf::bem {

// Penny crack of radius 1 (rings concentric rings, 6 rings^2 triangles) at the centre of the cube
// [-side/2, side/2]^3 (m x m squares per face) under remote tension 1 along its normal (E = 1, nu = 0.3).
struct PennyRun {
    std::shared_ptr<const BemSolution> solution;
    double max_opening_error = 0;  // relative, nodes with r < 0.8
    double centre_opening_error = 0;
    double mean_KI_error = 0;      // front average, relative
    double max_node_KI_error = 0;  // per front node (mean of its two edges), relative
    std::size_t crack_triangles = 0;
};
// tip_elements: square-root crack-front elements and K from their coefficients; else plain P1 and
// displacement correlation.
// The finite cube raises the opening over the infinite body's: centre COD +0.8 % at side 10 (the
// default, the thesis-era cases), +0.1 % at side 20, +0.02 % at side 40 (square-root front elements, 216 triangles).
PennyRun run_penny_crack(int rings, int cube_m, double grade = 1.0, bool tip_elements = false, double side = 10.0);

// Elliptical crack, semi-axes a = 1 (x) and b = aspect (y): the penny mesh of `rings` rings scaled in y,
// square-root front elements, in the cube [-side/2, side/2]^3 (4 x 4 squares per face), remote tension 1
// (E = 1, nu = 0.3). Errors of K_I against Irwin's solution at the front edges' midpoints.
struct EllipseRun {
    double mean_ratio_error = 0;  // |mean of K / K_Irwin - 1|
    double max_node_error = 0;    // per front node (mean of its two edges' ratios)
    double k_ratio = 0;           // K_max / K_min along the front (Irwin: sqrt(a / b))
    std::size_t crack_triangles = 0;
};
EllipseRun run_elliptical_crack(int rings, double aspect, double side);

// Penny crack a = 1 as in run_penny_crack (4 x 4 squares per cube face): the work of the remote load
// 1/2 sigma int [u_n] dA and its closed form 8 (1 - nu^2) sigma^2 a^3 / (3 E).
struct EnergyRun {
    double energy = 0, exact = 0;
    std::size_t crack_triangles = 0;
};
EnergyRun run_penny_energy(int rings, bool tip_elements, double side);

// Solid sphere R = 1 (icosphere level: 20 * 4^level triangles) under radial traction 1 with the TRUE
// normal at each element centroid (t = c/|c|), pure Neumann; exact u = 0.4 x (E = 1, nu = 0.3).
// Returns the relative L2 error of the nodal displacement (an O(h^2) geometry error) and h.
struct SphereRun {
    double h = 0;  // longest edge [m]
    double error = 0;
    std::size_t triangles = 0;
};
SphereRun run_sphere_true_normals(int level);

}  // namespace cf::bem

namespace cf {
void add_bem_verification_cases(std::vector<VerificationCase>& cases);
}
