#pragma once
// Per-iteration time table of every loop in a finished run (e.g. a fracture simulation's time
// split per BEM step: assemble, solve, SIFs, propagation, recording), printed after a run.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"

#include <string>

namespace cf::runtime {

// One table per loop: a row per iteration, a column per body node (wall seconds) plus one per
// '*_seconds' count a body node reports (its own split), and the row total. Empty without loops.
std::string loop_step_tables(const graph::Plan& plan, const graph::ExecutionResult& result);

}  // namespace cf::runtime
