#pragma once
// Where a finished run's time went (issue 17): seconds per node type and the run's critical path,
// the chain of node runs that bounded its wall time. Printed by `crackflow run --profile`; the
// path is also in report.json (summary.critical_path).
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"

#include <string>
#include <vector>

namespace cf::runtime {

// One node's runs on the critical path (consecutive in the path, e.g. a loop body node's
// iterations gathered under its name in the order the node first appears).
struct CriticalNode {
    std::string node, type;
    int runs = 0;
    double seconds = 0;  // summed wall time of those runs
};

struct RunProfile {
    double wall_seconds = 0;
    double node_seconds = 0;           // wall time of all node runs summed (> wall where they overlapped)
    std::vector<std::pair<std::string, double>> stage_seconds;  // per node type, largest first
    std::vector<CriticalNode> critical_path;  // in time order
    double critical_seconds = 0;       // node time on the path; wall - this: waiting, scheduling
};

// The path is found backwards from the run that ended last: each run's predecessor is the latest
// run, ended before it started, of a node it takes an input from (a loop stands for the nodes of
// its initial, next and while values). Runs beyond the first kMaxRecordedRuns of a node are not seen.
RunProfile run_profile(const graph::Plan& plan, const graph::ExecutionResult& result);

// The profile as text for people: the split per node type and the path.
std::string profile_text(const RunProfile& p);

}  // namespace cf::runtime
