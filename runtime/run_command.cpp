#include "runtime/run_command.hpp"
#include "runtime/run_profile.hpp"
#include "runtime/cancel_deadline.hpp"

#include "graph/atomic_write.hpp"
#include "graph/executor.hpp"
#include "graph/output_paths.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"
#include "runtime/progress.hpp"
#include "runtime/report.hpp"
#include "runtime/run_notes.hpp"
#include "runtime/step_table.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <unistd.h>

namespace cf::runtime {

namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};  // the signal that cancelled the run (SIGINT or SIGTERM)

// SIGINT (Ctrl-C) and SIGTERM (a scheduler or `kill`) both cancel the run cleanly: running nodes
// stop at their next check, temporaries are removed by the atomic writers, the report is written.
extern "C" void on_sigint(int sig) {
    g_signal.store(sig);
    g_interrupted.store(true);
}

bool load(const std::string& path, const std::vector<std::string>& overrides, bool fast, graph::Plan& plan,
          bool allow_absolute_paths = false) {
    std::vector<graph::Diagnostic> diags;
    graph::LoadOptions options;
    options.fast = fast;
    for (const auto& o : overrides)
        if (auto parsed = graph::parse_override(o, diags)) options.overrides.push_back(*parsed);
    plan = graph::load_pipeline_file(path, node_registry(), options, diags);
    if (diags.empty()) graph::check_output_paths(plan, allow_absolute_paths, diags);
    for (const auto& d : diags) std::fprintf(stderr, "%s\n", graph::format(d).c_str());
    if (!diags.empty())
        std::fprintf(stderr, "%s: %zu error%s\n", path.c_str(), diags.size(), diags.size() == 1 ? "" : "s");
    return diags.empty();
}

int cancelled_exit_code(int sig) { return sig == SIGTERM ? 143 : 130; }  // 128 + the signal, as shells report it

// report.json, atomically; false (with the error printed) if it could not be written.
bool write_report(const std::filesystem::path& report, const graph::Plan& plan, const graph::ExecutionResult& result,
                  const ReportContext& ctx) {
    try {
        graph::write_atomically(report, [&](std::ostream& o) { o << report_json(plan, result, ctx); });
        return true;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "crackflow run: error: %s\n", e.what());
        return false;
    }
}

// The cancel deadline passed with a node still inside a call that cannot be polled: the report from
// the runs that finished, then exit without waiting for that call (its pending writes are abandoned).
[[noreturn]] void abandon_run(const graph::Plan& plan, const NodeTally& tally, const ReportContext& ctx,
                              const std::filesystem::path& report, int sig) {
    graph::ExecutionResult partial = tally.partial_result(plan);
    std::string running;
    for (const auto& n : tally.running()) running += (running.empty() ? "'" : ", '") + n + "'";
    partial.error = "cancelled while " + (running.empty() ? std::string("a node") : "node " + running) +
                    " was inside a call that cannot be interrupted; the run was abandoned without its result";
    const int code = write_report(report, plan, partial, ctx) ? cancelled_exit_code(sig) : 1;
    std::fprintf(stderr, "crackflow run: cancelled after %.2f s (%s); partial report in %s\n", partial.wall_seconds,
                 partial.error.c_str(), report.string().c_str());
    std::fflush(stderr);
    std::fflush(stdout);
    std::_Exit(code);  // not exit(): the abandoned call still runs on a worker thread
}

}  // namespace

int validate_command(const std::vector<std::string>& pipelines, const std::vector<std::string>& overrides,
                     bool allow_absolute_paths) {
    int code = 0;
    for (const auto& p : pipelines) {
        graph::Plan plan, fast_plan;
        bool ok = load(p, overrides, false, plan, allow_absolute_paths);
        // The pipeline as `run --fast` (and the test suite) runs it: its fast: overrides are checked too.
        if (ok && !load(p, overrides, true, fast_plan, allow_absolute_paths)) {
            std::fprintf(stderr, "%s: the errors above come from its fast: section (as run --fast applies it)\n", p.c_str());
            ok = false;
        }
        if (ok) std::printf("%s: ok (%zu nodes)\n", p.c_str(), plan.nodes.size());
        else code = 2;
    }
    return code;
}

int graph_command(const std::string& pipeline) {
    graph::Plan plan;
    if (!load(pipeline, {}, false, plan)) return 2;
    std::fputs(graph::to_dot(plan).c_str(), stdout);
    return 0;
}

int run_command(const RunRequest& req) {
    graph::Plan plan;
    if (!load(req.pipeline, req.overrides, req.fast, plan, req.allow_absolute_paths)) return 2;
    if (req.print_pipeline) {
        std::fputs(graph::to_yaml(plan).c_str(), stdout);
        return 0;
    }
    std::filesystem::path out = req.out_dir.empty()
                                    ? std::filesystem::path("out") / std::filesystem::path(req.pipeline).stem()
                                    : std::filesystem::path(req.out_dir);
    std::error_code ec;
    std::filesystem::create_directories(out, ec);
    if (ec) {
        std::fprintf(stderr, "crackflow run: error: cannot create output directory %s: %s\n", out.string().c_str(),
                     ec.message().c_str());
        return 2;
    }
    // More workers than a few per core only cost memory (TBB sizes its arena by the limit: --threads 1e9
    // grew to 7.8 GB before failing).
    const int cores = tbb::info::default_concurrency();
    if (req.threads > 4 * cores) {
        std::fprintf(stderr, "crackflow run: error: --threads %d is more than 4 per core of this machine (%d cores); use at most %d\n",
                     req.threads, cores, 4 * cores);
        return 2;
    }
    const int threads = req.threads > 0 ? req.threads : cores;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

    ProgressDisplay progress(stderr, isatty(fileno(stderr)) != 0);
    g_interrupted.store(false);
    g_signal.store(0);
    auto previous = std::signal(SIGINT, on_sigint);
    auto previous_term = std::signal(SIGTERM, on_sigint);
    graph::RunOptions options;
    options.output_dir = out;
    options.fast = req.fast;
    options.cancel_flag = &g_interrupted;
    options.on_progress = [&](const std::string& node, double f) { progress.progress(node, f); };
    options.allow_absolute_paths = req.allow_absolute_paths;
    options.keep_outputs = false;  // the report needs the counts only; values are freed once consumed
    ReportContext ctx{req.pipeline, req.overrides, req.fast, threads, {}};  // notes: set after the run
    const auto report = out / "report.json";
    NodeTally tally(&progress);
    graph::ExecutionResult result;
    {
        // Ctrl-C within 0.5 s anywhere: nodes stop at their next poll; a run still inside a call
        // that cannot be polled 0.3 s after the signal is abandoned (runtime/cancel_deadline.hpp).
        const CancelDeadline deadline(g_signal, std::chrono::milliseconds(300), [&](int sig) {
            graph::abandon_pending_writes();
            progress.finish();
            abandon_run(plan, tally, ctx, report, sig);
        });
        result = graph::execute(plan, options, &tally);
    }
    std::signal(SIGINT, previous);
    std::signal(SIGTERM, previous_term);
    progress.finish();

    ctx.notes = run_notes(plan, result);
    if (!write_report(report, plan, result, ctx)) return 1;
    if (result.cancelled) {
        std::fprintf(stderr, "crackflow run: cancelled after %.2f s; partial report in %s\n", result.wall_seconds,
                     report.string().c_str());
        return cancelled_exit_code(g_signal.load());
    }
    if (!result.ok) {
        std::fprintf(stderr, "crackflow run: error: %s\n  (report: %s)\n", result.error.c_str(), report.string().c_str());
        return 1;
    }
    std::fputs(loop_step_tables(plan, result).c_str(), stderr);
    if (req.profile) std::fputs(profile_text(run_profile(plan, result)).c_str(), stderr);
    for (const std::string& n : ctx.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
    std::fprintf(stderr, "crackflow run: finished in %.2f s; outputs in %s (report: %s)\n", result.wall_seconds,
                 out.string().c_str(), report.string().c_str());
    return 0;
}

}  // namespace cf::runtime
