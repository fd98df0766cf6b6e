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
    // Throws std::logic_error on a duplicate or malformed name (must be dotted: stage.name).
    void add(NodeType type);
    const NodeType* find(std::string_view name) const;
    std::vector<const NodeType*> all() const;  // sorted by name
    std::vector<std::string> names() const;

private:
    std::map<std::string, NodeType, std::less<>> types_;
};

}  // namespace cf::graph
