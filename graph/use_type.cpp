#include "graph/use_type.hpp"

#include "graph/loop_type.hpp"

namespace cf::graph {

NodeType use_node_type() {
    NodeType t("use",
               "Reads another pipeline file, a sub-pipeline, in place of this node: `{type: use, use: FILE, params: "
               "{...}, inputs: {...}}`, FILE relative to the using file. The used file declares `parameters:` (each "
               "set on one or more of its nodes' parameters), `inputs:` (read inside as input.NAME) and `outputs:` "
               "(read outside as NODE.NAME). Its nodes join the pipeline as NODE/INNER (report.json, --set "
               "NODE/INNER.PARAM); --set NODE.PARAM sets a declared parameter. docs/pipelines.md, 'Sub-pipelines'.");
    t.executor_construct();
    t.input<AnyValue>("NAME", "a declared input of the used file, connected like any input (`inputs: {mesh: box.mesh}`)");
    t.output<AnyValue>("NAME", "a declared output of the used file (`fracture.fragments`)");
    return t;
}

}  // namespace cf::graph
