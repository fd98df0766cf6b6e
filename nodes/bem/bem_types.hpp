#pragma once
// The operator state that flows between assemble.sgbem, solve.sgbem and later steps: immutable
// and shared. A new step copies the small handle and shares the surface blocks; crack blocks are
// copied on write when elements are appended (append_crack_elements).
#include "nodes/bem/estimated_growth.hpp"
#include "nodes/bem/operators.hpp"
#include "nodes/bem/solver.hpp"

#include <memory>

namespace cf::bem {

struct BemOperators {
    std::shared_ptr<const SurfaceOperators> surface;
    std::shared_ptr<const CrackOperators> cracks;  // null without cracks; the frozen part once growth is estimated
    CrackMethod method = CrackMethod::full;        // chosen on the first assembly, kept by every later one
    long long switch_elements = 0;                 // hybrid: elements (surface + crack) above which growth is estimated
    std::shared_ptr<const EstimatedGrowth> estimated;  // null while every crack opening is a BEM unknown
    // Square-root crack-front elements (assemble.sgbem front_elements: square_root): the crack blocks of
    // `cracks` with every pair touching the current front re-integrated (tip_elements.hpp); null with
    // linear front elements or once growth is estimated. `cracks` stays the append-only P1 base.
    std::shared_ptr<const CrackOperators> tip;
    bool tip_elements = false;                     // chosen on the first assembly, kept by every later one
    // The crack blocks a solve uses.
    const std::shared_ptr<const CrackOperators>& solve_cracks() const { return tip ? tip : cracks; }
};

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::BemOperators, "BemOperators");
