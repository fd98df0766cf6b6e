#pragma once
// `crackflow nodes`: the node registry as text, Markdown (docs/nodes.md) or JSON.
#include "graph/registry.hpp"

#include <string>

namespace cf::runtime {

std::string nodes_markdown(const graph::NodeRegistry& registry);
std::string nodes_json(const graph::NodeRegistry& registry);
std::string nodes_text(const graph::NodeRegistry& registry);

}  // namespace cf::runtime
