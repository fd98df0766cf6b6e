#pragma once
// The list of all node types. Registration is explicit (nodes/register_all.cpp), so static
// libraries never drop a node and the order of `crackflow nodes` is stable (sorted by name).
#include "graph/node_type.hpp"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace cf::graph {

struct Plan;
struct Diagnostic;
// A check across the nodes of a loaded plan that the graph itself cannot know (a stage's
// knowledge, e.g. which regions an upstream mesh will have): appends its problems to the
// diagnostics, so `validate` reports them with the rest. It may fill in parameters a node type
// declares for it (a check that can only be made at run time, handed to the node that can make it
// earliest).
using PlanCheck = std::function<void(Plan&, std::vector<Diagnostic>&)>;

class NodeRegistry {
public:
    // Holds the built-in `loop` (graph/loop_type.hpp) from the start: the pipeline loader reads
    // its parameters from the registry like any node type's.
    NodeRegistry();
    // Throws std::logic_error on a duplicate or malformed name (must be dotted: stage.name; only
    // executor constructs such as `loop` are not).
    void add(NodeType type);
    const NodeType* find(std::string_view name) const;
    std::vector<const NodeType*> all() const;  // sorted by name
    std::vector<std::string> names() const;
    // Run by the pipeline loader on every plan that passed its own checks.
    void add_plan_check(PlanCheck check) { checks_.push_back(std::move(check)); }
    const std::vector<PlanCheck>& plan_checks() const { return checks_; }

private:
    std::map<std::string, NodeType, std::less<>> types_;
    std::vector<PlanCheck> checks_;
};

}  // namespace cf::graph
