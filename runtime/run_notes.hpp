#pragma once
// What a finished run's counts suggest its author change: a run can end "finished" with fewer
// fragments than the loads would make, and the reason is in a count nobody reads. These notes
// are printed after the run and kept in report.json (summary.notes).
#include "graph/executor.hpp"

#include <string>
#include <vector>

namespace cf::runtime {

// One note per finding, each naming the node, the parameter (with where it was set) and the fix.
// - initiate.cracks: its last run found surface elements over the strength, more than r_c from
//   every crack front, that max_cracks held back (the run's cracks were capped, not exhausted).
// - a loop with a `while` that ran max_iterations times and stopped with the condition still true
//   (a fracture loop: the cracks had not come to rest; its last propagate.fronts counts are named).
std::vector<std::string> run_notes(const graph::Plan& plan, const graph::ExecutionResult& result);

}  // namespace cf::runtime
