#pragma once
// Crack growth that is not part of the BEM system (thesis ch. 5.2, 5.3). Once a fracture run
// estimates instead of solving (method estimator, or hybrid past its element threshold), the crack
// elements already in the system stay there, factorised, as if they were ordinary surfaces whose
// right-hand side never changes; every later crack element carries an opening estimated by
// inverted displacement correlation (eq. 5.5-5.6), and its influence on the ordinary surface,
// f <- f - B du, is integrated element by element: B and Y are never assembled, and the memory
// kept is the crack mesh plus two vectors of the surface's size.
#include "graph/value.hpp"
#include "nodes/bem/operators.hpp"

#include <memory>
#include <vector>

namespace cf::bem {

// Openings estimated for crack nodes that left a crack front (eq. 5.5-5.6), per vertex of the
// crack mesh; written by the fracture loop (propagate.fronts), read by assemble.sgbem.
struct CrackOpeningEstimate {
    std::vector<Vec3> opening;  // [u] = u+ - u- [m], zero where unknown
    std::vector<char> known;    // per crack vertex: estimated
    // Per crack vertex: a front node whose markers still move (a node of a new front, or a node
    // of a front edge with an active marker). The SIF estimator evaluates the stress only there,
    // as the thesis' code does (ch. 5.3: the cost is linear in the moving front). Empty: all move.
    std::vector<char> front_active;
};

// Which crack unknowns the BEM system carries (thesis ch. 5, fig. 40).
enum class CrackMethod {
    full,       // every crack element's opening is a BEM unknown (ch. 4.2)
    estimator,  // the cracks present at the start are solved once; all growth is estimated
    hybrid,     // full until the mesh exceeds switch_elements, then as estimator
};
const char* method_name(CrackMethod m);

struct EstimatedGrowth {
    SurfaceMesh cracks;                   // the current crack sheets: frozen prefix + estimated elements
    std::size_t frozen_triangles = 0;     // prefix solved in the BEM system (CrackOperators::cracks)
    std::size_t frozen_vertices = 0;
    std::vector<char> frozen_unknown;     // per frozen vertex: an opening unknown of the system (interior node)
    std::vector<Vec3> opening;            // per crack vertex: the estimated opening [m] (zero where none)
    std::vector<char> estimated;          // per crack vertex: has an estimated opening
    std::vector<char> front_active;       // per crack vertex, from the last update (empty: every front moves)
    std::vector<unsigned char> integrated;  // per crack triangle: bit k = node k's opening is in k_opening/d_opening
    Vector k_opening;  // 3 M_Gamma: sum of K-type blocks times estimated openings = W(:, est) du
    Vector d_opening;  // 3 N_Gamma: the same with D-type blocks = X(:, est) du
    int switch_step = 0;                  // BEM step (loop iteration + 1; 0 before the loop) of the switch
    std::size_t pairs_last = 0;           // (surface element, crack element) pairs integrated in the last update
    std::size_t nodes_last = 0;           // crack nodes whose opening joined in the last update
};

// The growth state after this step. `previous` null: the switch happens now, with the frozen
// prefix of `frozen_triangles` triangles and `frozen_vertices` vertices. Every (crack element,
// node) pair whose node has a known opening that is not a frozen unknown and that was not
// integrated before is integrated against every surface element with the assembly's own pair
// quadrature, so k_opening and d_opening equal W du and X du of the assembled blocks.
// Throws std::invalid_argument when `cracks` does not extend the previous mesh, when an opening
// estimate does not match the mesh, or when a new element is degenerate or touches the surface.
std::shared_ptr<const EstimatedGrowth> update_estimated_growth(const SurfaceOperators& surface,
                                                               const std::shared_ptr<const EstimatedGrowth>& previous,
                                                               const SurfaceMesh& cracks, std::size_t frozen_triangles,
                                                               std::size_t frozen_vertices, const CrackOpeningEstimate& openings,
                                                               int step);

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::CrackOpeningEstimate, "CrackOpeningEstimate");
