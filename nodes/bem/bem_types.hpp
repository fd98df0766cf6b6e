#pragma once
// The operator state that flows between assemble.sgbem, solve.sgbem and later steps: immutable
// and shared. A new step copies the small handle and shares the surface blocks; crack blocks are
// copied on write when elements are appended (append_crack_elements).
#include "nodes/bem/operators.hpp"
#include "nodes/bem/solver.hpp"

#include <memory>

namespace cf::bem {

struct BemOperators {
    std::shared_ptr<const SurfaceOperators> surface;
    std::shared_ptr<const CrackOperators> cracks;  // null without cracks
};

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::BemOperators, "BemOperators");
