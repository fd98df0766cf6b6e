#pragma once
// Runs a validated plan as a oneTBB flow graph. Each pipeline node is one serial
// function_node; independent branches run concurrently. A loop is a controller node: it
// sends each iteration's variables into its body, receives the next values back, streams
// every iteration's values to LOOP.each consumers (which therefore overlap with the next
// iteration) and the last ones to LOOP.final consumers.
#include "graph/node_context.hpp"
#include "graph/pipeline.hpp"

#include <map>
#include <string>
#include <vector>

namespace cf::graph {

// Runs of one node whose intervals and per-iteration counts are kept (see NodeStats).
constexpr int kMaxRecordedRuns = 10000;

struct NodeStats {
    std::string name;
    std::string type;  // "loop" for loops
    int runs = 0;
    double wall_seconds = 0;       // summed over runs
    long long peak_rss_bytes = 0;  // process peak resident set after this node's last run
    std::map<std::string, double> counts;                      // of the last run
    std::vector<std::map<std::string, double>> iteration_counts;  // per run, for per-iteration nodes (first kMaxRecordedRuns)
    std::vector<std::pair<double, double>> intervals;          // [start, end] of each run (first kMaxRecordedRuns)
};

struct ExecutionResult {
    bool ok = false;
    bool cancelled = false;    // stopped by the cancel flag (Ctrl-C), not by a failure
    std::string failed_node;   // the first node that failed
    std::string error;         // its message, "node 'x' (type): message"
    double wall_seconds = 0;
    std::vector<NodeStats> stats;  // plan order
    // Last value of every output port: outputs[node][port].
    std::map<std::string, std::map<std::string, Value>> outputs;
};

struct ExecutionObserver {
    virtual ~ExecutionObserver() = default;
    virtual void node_started(const std::string& node, int iteration) {}
    virtual void node_finished(const std::string& node, int iteration, double seconds) {}
};

ExecutionResult execute(const Plan& plan, const RunOptions& options, ExecutionObserver* observer = nullptr);

}  // namespace cf::graph
