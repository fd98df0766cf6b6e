#pragma once
// The `loop` node type: the pipeline's iteration construct (like Blender's repeat zone), declared
// like every node type so that parameter validation, `crackflow nodes` and docs/nodes.md all come
// from this one declaration. The executor runs a loop itself (graph/executor.cpp), so the type has
// no run function; its ports are named by the pipeline (one per loop variable), so they are
// declared as patterns (VAR, each.VAR, final.VAR) of any type.
#include "graph/node_type.hpp"

namespace cf::graph {

// The type of a loop variable's ports: whatever value the variable is started with.
struct AnyValue {};

inline constexpr const char* kLoopTypeName = "loop";
inline constexpr const char* kMaxIterationsParam = "max_iterations";

NodeType loop_node_type();

}  // namespace cf::graph

CF_GRAPH_TYPE(cf::graph::AnyValue, "any");
