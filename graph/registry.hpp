#pragma once
// The list of all node types. Registration is explicit (nodes/register_all.cpp), so static
// libraries never drop a node and the order of `crackflow nodes` is stable (sorted by name).
#include "graph/node_type.hpp"

#include <map>
#include <string>
#include <vector>

namespace cf::graph {

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

private:
    std::map<std::string, NodeType, std::less<>> types_;
};

}  // namespace cf::graph
