#include "graph/registry.hpp"

#include "graph/loop_type.hpp"
#include "graph/use_type.hpp"

#include <regex>
#include <stdexcept>

namespace cf::graph {

NodeRegistry::NodeRegistry() {
    add(loop_node_type());
    add(use_node_type());
}

void NodeRegistry::add(NodeType type) {
    static const std::regex dotted("[a-z][a-z0-9_]*(\\.[a-z][a-z0-9_]*)+");
    if (!type.is_executor_construct() && !std::regex_match(type.name(), dotted))
        throw std::logic_error("node type name '" + type.name() + "' must be dotted lower-case, stage first (e.g. shape.box)");
    if (!type.is_executor_construct() && !type.run_fn()) throw std::logic_error("node type " + type.name() + " has no run function");
    std::string n = type.name();
    if (!types_.emplace(n, std::move(type)).second) throw std::logic_error("node type " + n + " registered twice");
}

const NodeType* NodeRegistry::find(std::string_view name) const {
    auto it = types_.find(name);
    return it == types_.end() ? nullptr : &it->second;
}

std::vector<const NodeType*> NodeRegistry::all() const {
    std::vector<const NodeType*> r;
    for (const auto& [n, t] : types_) r.push_back(&t);
    return r;
}

std::vector<std::string> NodeRegistry::names() const {
    std::vector<std::string> r;
    for (const auto& [n, t] : types_) r.push_back(n);
    return r;
}

}  // namespace cf::graph
