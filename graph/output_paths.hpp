#pragma once
// Output file names checked before a run: every parameter declared with writes_file() must name
// a file inside the run's output directory (no '..' out of it; no absolute path unless allowed),
// not the run's own report.json, and no two such parameters may name the same file (the later
// writer would silently replace the earlier one's output).
#include "graph/diagnostics.hpp"
#include "graph/pipeline.hpp"

#include <vector>

namespace cf::graph {

void check_output_paths(const Plan& plan, bool allow_absolute, std::vector<Diagnostic>& diags);

}  // namespace cf::graph
