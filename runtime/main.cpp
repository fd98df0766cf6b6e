// crackflow: the command line. A thin main over the runtime library (cf. OpenVDB's vdb_tool).
#include "nodes/register_all.hpp"
#include "runtime/batch_command.hpp"
#include "runtime/huge_pages.hpp"
#include "runtime/node_docs.hpp"
#include "runtime/run_command.hpp"
#include "runtime/verify_command.hpp"

#include <CLI/CLI.hpp>

#include <climits>
#include <csignal>
#include <cstdio>

int main(int argc, char** argv) {
    // Before the run's large allocations (runtime/huge_pages.hpp says why).
    cf::runtime::settle_huge_pages();
    // Under a file-size limit (ulimit -f) a write past it would kill the process with SIGXFSZ and
    // leave a temporary behind; ignored, the write fails with EFBIG, which the atomic writers report
    // with the file's name, and the run ends with exit 1 and its report.
    std::signal(SIGXFSZ, SIG_IGN);
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
    run_cmd->add_flag("--print-pipeline", run.print_pipeline,
                      "print the pipeline as it would run (sub-pipelines expanded, --fast and --set applied, input "
                      "paths resolved) as YAML on stdout, and stop");
    run_cmd->add_flag("--allow-absolute-paths", run.allow_absolute_paths,
                      "let output parameters name absolute paths outside --out (refused by default)");
    run_cmd->add_flag("--profile", run.profile,
                      "print the seconds per node type and the run's critical path at the end (also in report.json)");

    std::vector<std::string> validate_files, validate_overrides;
    auto* validate_cmd = app.add_subcommand("validate", "check pipelines without running them; exit 2 if any is invalid");
    validate_cmd->add_option("pipelines", validate_files, "pipeline YAML files")->required();
    validate_cmd->add_option("--set", validate_overrides, "override a parameter: NODE.PARAM=VALUE (repeatable)");
    bool validate_absolute = false;
    validate_cmd->add_flag("--allow-absolute-paths", validate_absolute, "accept absolute output paths (as run does with it)");

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

    cf::runtime::BatchRequest batch;
    auto* batch_cmd = app.add_subcommand("batch", "run a manifest of pipeline runs (CSV/YAML rows) locally, as Slurm job arrays, "
                                                  "or as commands for another farm manager (docs/batch.md)");
    batch_cmd->add_option("manifest", batch.manifest, "manifest file (.csv or .yaml): id, pipeline and NODE.PARAM columns");
    batch_cmd->add_option("--out", batch.out_dir, "output directory: one folder per row, DIR/<id>");
    batch_cmd->add_option("--backend", batch.backend, "local (default) or slurm")->check(CLI::IsMember({"local", "slurm"}));
    batch_cmd->add_option("--jobs,-j", batch.jobs, "local: rows run at once (default 1)")->check(CLI::Range(1, 4096));
    batch_cmd->add_option("--threads", batch.threads, "threads per row (default: local: cores / jobs; slurm: --cpus-per-task)")
        ->check(CLI::Range(1, 4096));
    batch_cmd->add_flag("--fast", batch.fast, "run every row with its pipeline's fast: overrides");
    batch_cmd->add_flag("--check", batch.check_only, "validate the manifest (every row against its pipeline) and stop");
    batch_cmd->add_option("--emit-commands", batch.emit_commands,
                          "write one shell command per row not yet complete to FILE ('-': stdout) for another farm manager");
    batch_cmd->add_option("--collect", batch.collect_dir, "summarise the batch in DIR: DIR/summary.json and DIR/summary.csv");
    batch_cmd->add_option("--partition", batch.slurm.partition, "slurm: partition");
    batch_cmd->add_option("--time", batch.slurm.time, "slurm: time limit per task (sbatch --time, e.g. 2:00:00)");
    batch_cmd->add_option("--mem", batch.slurm.mem, "slurm: memory per task (sbatch --mem, e.g. 8G)");
    batch_cmd->add_option("--cpus-per-task", batch.slurm.cpus_per_task, "slurm: CPUs per task, also each row's --threads (default 1)")
        ->check(CLI::Range(1, 4096));
    batch_cmd->add_option("--max-parallel", batch.slurm.max_parallel, "slurm: tasks running at once (--array=...%P; default: no limit)")
        ->check(CLI::Range(1, 1000000));
    batch_cmd->add_option("--rows-per-task", batch.slurm.rows_per_task,
                          "slurm: rows per array task (default: enough that ~1 s of task overhead stays below 5 % of the work)")
        ->check(CLI::Range(1, 1000000));
    batch_cmd->add_option("--row-seconds", batch.slurm.row_seconds,
                          "slurm: estimated seconds per row for choosing rows per task before any row ran (default 60)")
        ->check(CLI::PositiveNumber);
    batch_cmd->add_option("--max-array-size", batch.slurm.max_array_size,
                          "slurm: split arrays at this size (default: the cluster's MaxArraySize, else 1001)")
        ->check(CLI::Range(1L, 100000000L));
    batch_cmd->add_option("--sbatch-option", batch.slurm.sbatch_options, "slurm: pass an option to sbatch as it is (repeatable), "
                                                                         "e.g. --sbatch-option=--account=vfx");
    batch_cmd->add_flag("--wait", batch.slurm.wait, "slurm: wait for the array jobs, then write the summary");
    batch_cmd->add_option("--row", batch.row, "run only this row (what an emitted command does)");
    batch_cmd->add_option("--task-file", batch.task_file, "internal (Slurm job script): the rows of each task")->group("");
    batch_cmd->add_option("--task", batch.task, "internal (Slurm job script): run the rows of this task")->group("");
    batch_cmd->add_option("--workdir", batch.workdir, "working directory of the rows (default: the current one)");
    batch_cmd->add_option("--slurm-config", batch.slurm_config,
                          "slurm: a YAML file of the options above without '--' (partition: short, mem: 4G, ...); "
                          "the command line wins");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    try {
        if (*run_cmd) return cf::runtime::run_command(run);
        if (*validate_cmd) return cf::runtime::validate_command(validate_files, validate_overrides, validate_absolute);
        if (*graph_cmd) return cf::runtime::graph_command(graph_file);
        if (*batch_cmd) {
            for (const char* name : {"partition", "time", "mem", "cpus-per-task", "max-parallel", "rows-per-task",
                                     "row-seconds", "max-array-size"})
                if (batch_cmd->count(std::string("--") + name) > 0) batch.slurm_given.push_back(name);
            if (batch_cmd->count("--sbatch-option") > 0) batch.slurm_given.push_back("sbatch-options");
            return cf::runtime::batch_command(batch);
        }
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
