#pragma once
// `crackflow run`, `validate` and `graph`: load a pipeline, report every problem at once, run it.
#include <string>
#include <vector>

namespace cf::runtime {

struct RunRequest {
    std::string pipeline;
    std::string out_dir;               // default: out/<pipeline name>
    std::vector<std::string> overrides;  // NODE.PARAM=VALUE
    int threads = 0;                   // 0: all cores
    bool fast = false;
    bool allow_absolute_paths = false;  // output parameters may name files outside --out
    bool print_pipeline = false;        // print the pipeline as it would run (graph::to_yaml) and stop
    bool profile = false;               // print the split per node type and the critical path at the end
};

// Exit codes: 0 ok, 1 a node failed, 2 invalid pipeline or arguments, 130 cancelled (Ctrl-C).
int run_command(const RunRequest& request);
int validate_command(const std::vector<std::string>& pipelines, const std::vector<std::string>& overrides,
                     bool allow_absolute_paths = false);
int graph_command(const std::string& pipeline);

}  // namespace cf::runtime
