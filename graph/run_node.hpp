#pragma once
// Runs one node outside any graph: fills defaults, checks parameters and inputs against the
// declaration, calls the run function, and checks that every output was set. The executor
// and the per-node test harness both use this, so a node behaves the same in both.
#include "graph/node_context.hpp"

#include <map>
#include <string>
#include <vector>

namespace cf::graph {

struct NodeResult {
    std::map<std::string, Value> outputs;
    std::map<std::string, double> counts;

    template <class T>
    const T& out(const std::string& port) const {
        auto it = outputs.find(port);
        if (it == outputs.end()) throw std::logic_error("no output '" + port + "'");
        return it->second.get<T>();
    }
};

// Defaults filled in; problems appended to `errors` as "parameter 'x': why".
std::map<std::string, ParamValue> resolve_params(const NodeType& type, const std::map<std::string, ParamValue>& given,
                                                 std::vector<std::string>& errors);

// Throws NodeError for bad parameters or inputs, or whatever the node throws.
NodeResult run_node(const NodeType& type, const std::map<std::string, ParamValue>& params,
                    const std::map<std::string, Value>& inputs, const RunOptions& options = {},
                    const std::string& node_name = "", int iteration = -1);

}  // namespace cf::graph
