#pragma once
// Pipeline files: parsing YAML into a validated execution plan.
//
// Format (docs/pipelines.md):
//   nodes:
//     NAME: {type: stage.kind, params: {p: v}, inputs: {port: other.port}}
//     LOOP:
//       type: loop
//       params: {max_iterations: 10}
//       inputs: {VAR: other.port}          # loop variables with their initial values
//       body: {NAME: {...}, ...}           # nodes run once per iteration
//       next: {VAR: bodynode.port}         # the value of VAR for the next iteration
//       while: bodynode.port               # optional Bool: iterate while true
//   fast: {node.param: value}              # optional overrides for quick test runs
// A node `{type: use, use: FILE, params: {...}, inputs: {...}}` reads another pipeline file (a
// sub-pipeline with declared `parameters:`, `inputs:` and `outputs:`) in its place: its nodes are
// named NAME/INNER; NAME.OUTPUT reads a declared output (graph/subpipeline.cpp, docs/pipelines.md).
// Inside the body, LOOP.VAR is the current value and LOOP.iteration the index (Int, from 0).
// Outside, LOOP.each.VAR streams the value after every iteration and LOOP.final.VAR is the
// value after the last one.
#include "graph/diagnostics.hpp"
#include "graph/registry.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cf::graph {

enum class SourceKind {
    NodeOutput,     // an ordinary node's output port
    LoopVariable,   // LOOP.VAR inside the body (per iteration)
    LoopIteration,  // LOOP.iteration inside the body (per iteration)
    LoopEach,       // LOOP.each.VAR outside (per iteration, streamed)
    LoopFinal,      // LOOP.final.VAR outside (once)
};

struct PlanInput {
    std::string port;         // the consuming node's input port ("" for loop 'while')
    int source = -1;          // index into Plan::nodes
    std::string source_port;  // output port, or the loop variable name
    SourceKind kind = SourceKind::NodeOutput;
    TypeId type{std::type_index(typeid(void)), "none"};
};

struct PlanNode {
    std::string name;
    SourceLoc loc;
    const NodeType* type = nullptr;  // null for loops
    std::map<std::string, ParamValue> params;
    std::map<std::string, SourceLoc> param_locs;  // where each parameter given in the file (or --set) was
    std::vector<PlanInput> inputs;
    int body_of = -1;      // index of the loop whose body holds this node
    int streamed_by = -1;  // outside node that runs once per iteration of this loop (via each)

    // Loops only.
    bool is_loop() const { return type == nullptr; }
    long long max_iterations = 0;
    std::vector<std::string> loop_vars;                // names, in file order
    std::map<std::string, TypeId> loop_var_types;
    std::vector<PlanInput> loop_init, loop_next;        // one per variable, same order
    std::optional<PlanInput> loop_while;

    bool per_iteration() const { return body_of >= 0 || streamed_by >= 0; }
};

// A sub-pipeline as used (its nodes are in Plan::nodes as NAME/INNER).
struct PlanUse {
    std::string name;  // the use node ("outer/inner" when nested)
    std::string file;  // the used file, as resolved
    SourceLoc loc;     // where the use node is written
};

struct Plan {
    std::string file;
    std::vector<PlanUse> uses;
    const NodeRegistry* registry = nullptr;  // the registry it was loaded with (sub-pipelines use it too)
    std::vector<PlanNode> nodes;  // in a topological order of the non-loop-back edges
    int find(const std::string& name) const;
};

struct Override {
    std::string node, param, value;
    SourceLoc loc;
    // false (--set, batch manifests): the value of a text parameter (String, Choice) is taken as
    // it is, no quoting needed ('z_max: traction 0 0 1'); a value in quotes is read as YAML, so
    // '"a b"' is a b. Other parameters are read as YAML (1e9, [0, 0, 1], true).
    // true (fast: entries): the value is YAML text for every parameter.
    bool yaml = false;
};

// Parses "node.param=value" (from --set). Appends a diagnostic when malformed.
std::optional<Override> parse_override(const std::string& text, std::vector<Diagnostic>& diags);

struct LoadOptions {
    std::vector<Override> overrides;
    bool fast = false;  // apply the file's `fast:` overrides
    // An input file (ParamDecl::reads_file) found nowhere is an error listing the paths tried;
    // false (a batch manifest checked before its rows run, whose data may appear later): the path
    // beside the file is kept and the run itself reports it.
    bool require_input_files = true;
};

// Reads, validates and plans a pipeline. All problems are appended to `diags`; the plan is
// usable only when `diags` stays empty.
Plan load_pipeline_file(const std::string& path, const NodeRegistry& registry, const LoadOptions& options,
                        std::vector<Diagnostic>& diags);
Plan load_pipeline_text(const std::string& text, const std::string& file_name, const NodeRegistry& registry,
                        const LoadOptions& options, std::vector<Diagnostic>& diags);

// Graphviz dot of a plan (loops and sub-pipelines as clusters).
std::string to_dot(const Plan& plan);

// The plan as a pipeline file (graph/pipeline_print.cpp): sub-pipelines expanded (nodes named
// NAME/INNER), every override applied, input paths resolved, only the parameters a file or an
// override gave (the rest take their defaults). Loads again to the same plan.
std::string to_yaml(const Plan& plan);

}  // namespace cf::graph
