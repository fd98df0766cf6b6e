#pragma once
// Every node type crackflow ships, registered explicitly (no static-initialiser magic, so a
// static library never drops a node).
#include "graph/registry.hpp"

namespace cf {

// The registry with every node type; built once, thread-safe to read.
const graph::NodeRegistry& node_registry();

}  // namespace cf
