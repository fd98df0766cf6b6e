#pragma once
// SGBEM solves (thesis ch. 2.3, 2.5, 4.2, 7.1).
// Mixed problems: A = [V_DD, -K_DN; K_DN^T, D_NN] (eq. 2.25), factorised once by block
// Cholesky (V_DD = L L^T, then the SPD complement D_NN + W^T W with W = L^-1 K_DN, formed as a
// symmetric rank update). Dense factorisations are DenseCholesky (parallel, deterministic).
// Pure Neumann: A = D_R = D^T D + gamma T^T T with the area-scaled regulariser of eq. (7.2)-(7.3)
// and gamma = (tr(D)/(3n))^2, right-hand side D^T f_N (eq. 7.4); loads must be balanced.
// Cracks (eq. 2.38, 4.2, 4.3): unknown w = -[u] at interior crack nodes, Schur complement
// S = Y - C A^-1 B factorised by Cholesky; when crack unknowns are appended the Cholesky factor
// is extended by the new rows instead of recomputed. s = A^-1 (f - B w).
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/dense_cholesky.hpp"
#include "nodes/bem/estimated_growth.hpp"
#include "nodes/bem/operators.hpp"

#include <Eigen/Cholesky>
#include <memory>
#include <vector>

namespace cf::bem {

// The factorised surface block A for one Dirichlet/Neumann partition.
struct SurfaceSystem {
    std::shared_ptr<const SurfaceOperators> ops;
    bool pure_neumann = false;
    std::vector<char> dirichlet;     // partition it was built for
    std::vector<int> d_elements;     // Dirichlet elements (traction unknowns)
    std::vector<int> n_nodes;        // nodes not in closure(Gamma_D) (displacement unknowns)
    // mixed
    DenseCholesky v_factor;          // V_DD = L L^T
    Matrix l_inv_k;                  // W = L^-1 K_DN
    DenseCholesky s_factor;          // D_NN + K_DN^T V_DD^-1 K_DN = D_NN + W^T W
    // pure Neumann
    Matrix T;                        // 6 x 3N regulariser rows (eq. 7.2, 7.3)
    double gamma = 0;
    DenseCholesky r_factor;          // D_R
    Eigen::Index size() const;       // number of unknowns in s
    Vector solve(const Vector& f) const;  // A^-1 f
};

// Cholesky factor of the crack Schur complement and what is needed to extend it.
struct CrackSchur {
    std::vector<int> dof_nodes;      // crack nodes carrying unknowns, in unknown order
    std::size_t crack_triangles = 0; // crack elements it was built from
    Matrix Z;                        // A^-1 B  (size(s) x 3 dofs)
    Matrix L;                        // lower Cholesky factor of S (symmetrised)
    // Square-root front elements: per unknown node (dof_nodes' order), the number of solves its basis
    // function has stood unchanged, counting this one (1: new or changed). The next step keeps the factor
    // on the leading run of nodes whose basis still stands, and orders the rest by this.
    std::vector<int> stood;
};

struct SolveOptions {
    double balance_tolerance = 1e-3;  // pure Neumann: max relative net force / torque of the loads
    bool extend_schur = true;         // false: always refactor the Schur complement (for benchmarks)
    // Dense matrices of the surface factor and the crack Schur complement are estimated before they
    // are allocated and refused above this (bytes); < 0: the budget the surface operators were
    // assembled with.
    double memory_budget_bytes = -1;
};

struct BemSolution {
    std::shared_ptr<const SurfaceOperators> surface;
    std::shared_ptr<const CrackOperators> cracks;     // may be null
    std::shared_ptr<const SurfaceSystem> system;
    std::shared_ptr<const CrackSchur> schur;          // null without crack unknowns
    std::vector<Vec3> displacement;                   // per surface node [m]
    std::vector<Vec3> traction;                       // per surface element [Pa]
    std::vector<Vec3> crack_opening;                  // per node of cracks->cracks, [u] = u+ - u- (0 at the front) [m]
    // With square-root front elements (cracks->tip_elements): per node of cracks->cracks, the front
    // nodes' square-root coefficients (the opening is sqrt(rho) times the P1 field of these at the
    // front and crack_opening elsewhere; tip_elements.hpp) [m]; 0 off the front. Empty without.
    std::vector<Vec3> front_coefficient;
    // Growth past the system (thesis ch. 5.2): the whole current crack mesh with estimated openings;
    // null while every crack opening is a BEM unknown. `cracks` above is then the frozen part.
    std::shared_ptr<const EstimatedGrowth> estimated;
    Vec3 residual_force = Vec3::Zero();               // net load [N] (pure Neumann)
    Vec3 residual_torque = Vec3::Zero();              // about the surface centroid [N m]
    bool reused_surface_factor = false;
    bool extended_schur = false;
    std::size_t schur_rows_added = 0;
};

// Per-node crack face loads: optional pressure p on both faces [Pa] per crack region.
struct CrackLoads {
    std::vector<double> pressure;  // per crack region id; empty means traction-free
};

// Interior crack nodes (not on a boundary edge of the sheet).
std::vector<char> crack_interior_nodes(const SurfaceMesh& cracks);

// Solves. `previous` (may be null) provides factorisations to reuse: the surface factor when
// operators and partition match, and the Schur factor when the crack mesh only grew.
// `surface_factor` (may be null): a surface factorisation made before (a rigid body's earlier
// fracture run, ch. 7.3), reused when `previous` gives none and its operators and partition match.
// `estimated` (may be null): growth outside the system (ch. 5.2); its openings enter the surface
// rows of the right-hand side as f <- f - B du (B du from EstimatedGrowth::k_opening, d_opening),
// the rows of the frozen crack unknowns keep their right-hand side, and with `previous` from the
// same system the stored factorisations are reused (one forward/back substitution).
std::shared_ptr<const BemSolution> solve_sgbem(const std::shared_ptr<const SurfaceOperators>& surface,
                                               const std::shared_ptr<const CrackOperators>& cracks,
                                               const ResolvedConditions& bc, const CrackLoads& loads,
                                               const BemSolution* previous, const SolveOptions& options = {},
                                               const std::shared_ptr<const EstimatedGrowth>& estimated = nullptr,
                                               const std::shared_ptr<const SurfaceSystem>& surface_factor = nullptr);

// The crack mesh of a solution: the estimated growth's when there is one, else the system's (null: none).
const SurfaceMesh* current_crack_mesh(const BemSolution& sol);
// Opening per vertex of current_crack_mesh: solved where the system has unknowns, estimated elsewhere.
std::vector<Vec3> current_crack_opening(const BemSolution& sol);

// Net force and torque (about the area centroid) of per-element tractions.
void load_resultants(const SurfaceOperators& s, const std::vector<Vec3>& traction, Vec3& force, Vec3& torque);

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::BemSolution, "BemSolution");
