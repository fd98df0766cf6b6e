#pragma once
// The BEM verification cases of docs/verification.md (sections "Operator identities",
// "Elastostatic solutions" 1-3 and "Fracture mechanics" 5), run by `crackflow verify` and ctest.
#include "nodes/bem/solver.hpp"
#include "nodes/domain/verification_case.hpp"

#include <vector>

namespace cf::bem {

// Penny crack of radius 1 (rings concentric rings, 6 rings^2 triangles) at the centre of the cube
// [-5, 5]^3 (m x m squares per face) under remote tension 1 along its normal (E = 1, nu = 0.3).
struct PennyRun {
    std::shared_ptr<const BemSolution> solution;
    double max_opening_error = 0;  // relative, nodes with r < 0.8
    double centre_opening_error = 0;
    double mean_KI_error = 0;      // front average, relative
    double max_node_KI_error = 0;  // per front node (mean of its two edges), relative
    std::size_t crack_triangles = 0;
};
PennyRun run_penny_crack(int rings, int cube_m, double grade = 1.0);

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
