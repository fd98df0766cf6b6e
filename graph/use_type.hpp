#pragma once
// The `use` node type: a sub-pipeline read in place of the node (graph/subpipeline.cpp). Declared
// in the registry like `loop` so that `crackflow nodes` and docs/nodes.md describe it; the loader
// expands it before planning, so no use node reaches the executor.
#include "graph/node_type.hpp"

namespace cf::graph {

NodeType use_node_type();

}  // namespace cf::graph
