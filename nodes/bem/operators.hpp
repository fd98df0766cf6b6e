#pragma once
// Dense Galerkin blocks of the Lame SGBEM (eq. 2.25/2.26, 2.38), assembled in parallel with
// oneTBB. Results are bit-identical for any thread count: elements are coloured so that no two
// elements of one colour share a node; colours run one after another, elements of a colour in
// parallel, and each element-pair contribution is added by exactly one task in a fixed order.
// Symmetric blocks are computed from the upper triangle of element pairs only (D = H + H^T),
// which makes them exactly symmetric.
#include "graph/machine_memory.hpp"
#include "nodes/bem/element_geometry.hpp"
#include "nodes/bem/local_blocks.hpp"
#include "nodes/bem/pair_integrals.hpp"
#include "nodes/bem/rigid_motion_rows.hpp"
#include "nodes/domain/material.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace cf::bem {

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;

struct AssemblyOptions {
    QuadratureSettings quadrature;
    bool single_layer = true;             // V is needed only when some region is Dirichlet
    // K's rows reproduce the rigid translations exactly (rigid_motion_rows.hpp). Off only to see the
    // raw quadrature (the oracle comparisons and the rigid_body_kernel verification case).
    bool rigid_motion_rows = true;
    double memory_budget_bytes = default_memory_budget_bytes();  // refuse dense allocations above this
};

// Blocks over the ordinary surface Gamma. Unknown numbering: element a, component j -> 3a+j;
// node i, component j -> 3i+j.
struct SurfaceOperators {
    SurfaceMesh mesh;
    ElasticConstants elastic;
    AssemblyOptions options;
    std::vector<ElementGeometry> geometry;
    Matrix V;  // 3M x 3M  (empty if !options.single_layer)
    Matrix K;  // 3M x 3N  P0 test x P1 trial
    Matrix D;  // 3N x 3N
    std::int64_t pairs_computed = 0;  // element-pair integrals evaluated
    RigidMotionRows rigid_motion;     // K's rigid-motion residual before its correction, and whether it was made
};

// Crack sheets Sigma (open triangle sheets; one SurfaceMesh, its regions are the cracks) and the
// blocks W = K[Gamma elements, Sigma nodes], X = D[Gamma nodes, Sigma nodes] and
// Y = D[Sigma nodes, Sigma nodes] (eq. 2.38) over ALL crack nodes (front nodes included; the
// solver keeps only interior nodes). Append-only: adding elements computes only new pairs.
struct CrackOperators {
    SurfaceMesh cracks;
    std::vector<ElementGeometry> geometry;
    Matrix W;   // 3M_Gamma x 3N_Sigma
    Matrix X;   // 3N_Gamma x 3N_Sigma
    Matrix HY;  // upper part: Y = HY + HY^T
    std::int64_t pairs_computed = 0;        // over the whole history of appends
    std::int64_t pairs_computed_last = 0;   // in the last append
    // Square-root crack-front elements (tip_elements.hpp): the blocks above are those of the
    // square-root basis, every node with a basis function is an unknown, and basis_integral holds
    // int psi_a over each element (local order) for face loads. False: plain P1 (front COD 0).
    bool tip_elements = false;
    std::vector<std::array<double, 3>> basis_integral;
    std::int64_t tip_pairs_computed = 0;    // element pairs integrated with the square-root basis
    std::int64_t tip_pairs_reused = 0;      // their corrections taken from the step before
    std::int64_t tip_pairs_in_append = 0;   // of the computed ones, those integrated with the append's P1 blocks (AppendedPairs)
    std::shared_ptr<const struct TipCache> tip_cache;  // tip_elements.cpp
    Matrix Y() const { return HY + HY.transpose(); }
};

// Bytes the dense blocks of a surface with the given counts need (peak during assembly).
double surface_operator_bytes(std::size_t triangles, std::size_t vertices, bool single_layer);
double crack_operator_bytes(std::size_t surface_triangles, std::size_t surface_vertices, std::size_t crack_vertices);
// A dense allocation refused before it was made (more than the memory budget allows).
struct MemoryBudgetExceeded : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};
// Throws MemoryBudgetExceeded with both numbers and the way out when bytes > budget.
void check_memory_budget(double bytes, double budget, const std::string& what);

// Assembles V, K, D on a closed surface. Throws std::invalid_argument for degenerate triangles
// or an over-budget size (before allocating).
std::shared_ptr<const SurfaceOperators> assemble_surface_operators(const SurfaceMesh& mesh, const Material& material,
                                                                   const AssemblyOptions& options);

// Receives the P1 blocks of every pair an append integrates (append_crack_elements' element tasks:
// task b calls it for b's pairs only, in a fixed order), so that work which needs exactly those blocks
// (the square-root corrections, tip_elements.hpp) does not integrate them a second time.
class AppendedPairs {
public:
    virtual ~AppendedPairs() = default;
    // Before the tasks: the crack elements (the new ones from `first_new` on).
    virtual void begin(const std::vector<ElementGeometry>& crack_geometry, std::size_t first_new) = 0;
    // Surface element a against new crack element b, for a = 0, 1, ... in order.
    virtual void surface_pair(int b, int a, const PairBlocks& p1) = 0;
    // Crack elements a <= b, b new, for a = 0, 1, ..., b in order.
    virtual void crack_pair(int a, int b, const PairBlocks& p1) = 0;
};

// Returns crack blocks for `cracks`, reusing `previous` (may be null). `cracks` must extend
// previous->cracks: same leading vertices and triangles, new ones appended. Throws
// std::invalid_argument when it does not, when a crack triangle is degenerate, or when a crack
// triangle intersects the ordinary surface.
// `memory_budget_bytes` < 0: the surface's (the budget of the assembly that made it); a loop's
// assembly passes its own. `observer` (may be null) sees the P1 blocks of every new pair.
std::shared_ptr<const CrackOperators> append_crack_elements(const SurfaceOperators& surface,
                                                            const std::shared_ptr<const CrackOperators>& previous,
                                                            const SurfaceMesh& cracks, double memory_budget_bytes = -1,
                                                            AppendedPairs* observer = nullptr);

// P0 x P1 mass matrix M01[a, (a, alpha)] = |T_a|/3 I applied to a nodal vector (3N -> 3M) and its transpose.
Vector mass_times_nodal(const SurfaceOperators& s, const Vector& nodal);
Vector mass_transpose_times_elemental(const SurfaceOperators& s, const Vector& elemental);

// Greedy element colouring: no two elements of one colour share a vertex. Returns colour lists.
std::vector<std::vector<int>> colour_elements(const std::vector<ElementGeometry>& g, std::size_t first, std::size_t last);

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::SurfaceOperators, "BemSurfaceOperators");
