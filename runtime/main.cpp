// crackflow: the command line. A thin main over the runtime library (cf. OpenVDB's vdb_tool).
#include "nodes/register_all.hpp"
#include "runtime/node_docs.hpp"
#include "runtime/run_command.hpp"
#include "runtime/verify_command.hpp"

#include <CLI/CLI.hpp>

#include <climits>
#include <cstdio>

int main(int argc, char** argv) {
    CLI::App app{"crackflow " CRACKFLOW_VERSION " - brittle fracture simulation for visual effects"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string(CRACKFLOW_VERSION));

    cf::runtime::RunRequest run;
    auto* run_cmd = app.add_subcommand("run", "run a pipeline");
    run_cmd->add_option("pipeline", run.pipeline, "pipeline YAML file")->required();
    run_cmd->add_option("--out", run.out_dir, "output directory (default: out/<pipeline name>)");
    run_cmd->add_option("--set", run.overrides, "override a parameter: NODE.PARAM=VALUE (repeatable)");
    run_cmd->add_option("--threads", run.threads, "worker threads (default: all cores; at most 4 per core)")->check(CLI::Range(1, INT_MAX));
    run_cmd->add_flag("--fast", run.fast, "apply the pipeline's 'fast:' overrides (reduced resolution, for tests)");

    std::vector<std::string> validate_files, validate_overrides;
    auto* validate_cmd = app.add_subcommand("validate", "check pipelines without running them; exit 2 if any is invalid");
    validate_cmd->add_option("pipelines", validate_files, "pipeline YAML files")->required();
    validate_cmd->add_option("--set", validate_overrides, "override a parameter: NODE.PARAM=VALUE (repeatable)");

    bool as_json = false, as_markdown = false;
    auto* nodes_cmd = app.add_subcommand("nodes", "list the node types");
    nodes_cmd->add_flag("--json", as_json, "as JSON");
    nodes_cmd->add_flag("--markdown", as_markdown, "as Markdown (docs/nodes.md)");

    std::string graph_file;
    auto* graph_cmd = app.add_subcommand("graph", "print a pipeline as a Graphviz dot graph");
    graph_cmd->add_option("pipeline", graph_file, "pipeline YAML file")->required();

    std::vector<std::string> cases;
    bool verify_json = false;
    auto* verify_cmd = app.add_subcommand("verify", "run the verification cases (closed-form checks)");
    verify_cmd->add_option("--case", cases, "run only this case (repeatable)");
    verify_cmd->add_flag("--json", verify_json, "print only JSON on stdout");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    try {
        if (*run_cmd) return cf::runtime::run_command(run);
        if (*validate_cmd) return cf::runtime::validate_command(validate_files, validate_overrides);
        if (*graph_cmd) return cf::runtime::graph_command(graph_file);
        if (*verify_cmd) return cf::runtime::verify_command(cases, verify_json);
        if (*nodes_cmd) {
            const auto& reg = cf::node_registry();
            std::fputs((as_json ? cf::runtime::nodes_json(reg)
                        : as_markdown ? cf::runtime::nodes_markdown(reg)
                                      : cf::runtime::nodes_text(reg)).c_str(), stdout);
            return 0;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "crackflow: error: %s\n", e.what());
        return 1;
    }
    return 2;
}
