#include "graph/loop_type.hpp"

namespace cf::graph {

NodeType loop_node_type() {
    NodeType t(kLoopTypeName,
               "Runs the nodes of its `body:` once per iteration (the fracture time loop, a scene's frames). Each "
               "input is a loop variable with its initial value; `next: {VAR: bodynode.port}` gives its value for "
               "the next iteration (from a body node, same type); the optional `while: bodynode.port` (Bool) "
               "stops the loop when false. Inside the body read LOOP.VAR and LOOP.iteration; outside, "
               "LOOP.each.VAR (after every iteration, streamed) or LOOP.final.VAR (after the last). Loops do not nest.");
    t.executor_construct();
    t.input<AnyValue>("VAR", "initial value of the loop variable VAR; one input per variable, named in the pipeline "
                             "(e.g. `inputs: {state: start.state}`)");
    t.output<AnyValue>("VAR", "inside the body: the variable's value in the current iteration");
    t.output<long long>("iteration", "inside the body: the index of the current iteration, from 0");
    t.output<AnyValue>("each.VAR", "outside the loop: the variable after every iteration (a consumer runs once per "
                                   "iteration)");
    t.output<AnyValue>("final.VAR", "outside the loop: the variable after the last iteration");
    t.param_int(kMaxIterationsParam, 100, "the most iterations the loop runs").range(1, 1e9);
    return t;
}

}  // namespace cf::graph
