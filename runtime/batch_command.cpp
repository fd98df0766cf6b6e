#include "runtime/batch_command.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/register_all.hpp"
#include "runtime/batch_plan.hpp"
#include "runtime/batch_runner.hpp"
#include "runtime/batch_summary.hpp"
#include "runtime/batch_validation.hpp"
#include "runtime/child_process.hpp"

#include <tbb/info.h>

#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

namespace cf::runtime {

namespace fs = std::filesystem;
using namespace batch;

namespace {

std::string this_executable() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("crackflow") : p.string();
}

bool read_and_report(const std::string& path, Manifest& m, bool validate, bool fast) {
    std::vector<Problem> problems;
    m = read_manifest(path, problems);
    if (validate) validate_manifest(m, node_registry(), fast, problems);
    for (const auto& p : problems) std::fprintf(stderr, "%s\n", format(p).c_str());
    if (!problems.empty())
        std::fprintf(stderr, "%s: %zu error%s; nothing was run\n", path.c_str(), problems.size(), problems.size() == 1 ? "" : "s");
    return problems.empty();
}

int collect_command(const fs::path& dir) {
    std::vector<RowResult> rows;
    try {
        rows = collect(dir);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "crackflow batch: error: %s\n", e.what());
        return 2;
    }
    const SummaryCounts n = count(rows);
    for (const auto& r : rows)
        if (r.status != "ok")
            std::fprintf(stderr, "  %s: %s%s%s%s\n", r.id.c_str(), r.status.c_str(), r.error.empty() ? "" : ": ",
                         r.error.c_str(), r.log.empty() ? "" : (" (log: " + r.log + ")").c_str());
    std::fprintf(stderr, "crackflow batch: %d of %d rows ok, %d failed; summary in %s and %s\n", n.ok, n.total, n.failed,
                 (dir / "summary.json").string().c_str(), (dir / "summary.csv").string().c_str());
    return batch_exit_code(rows);
}

}  // namespace

int batch_command(const BatchRequest& req) {
    if (!req.collect_dir.empty()) return collect_command(fs::absolute(req.collect_dir));
    if (req.manifest.empty() || (req.out_dir.empty() && !req.check_only)) {
        std::fprintf(stderr, "crackflow batch: error: give a MANIFEST and --out DIR (or --collect DIR)\n");
        return 2;
    }
    if (req.backend != "local" && req.backend != "slurm") {
        std::fprintf(stderr, "crackflow batch: error: unknown --backend '%s' (local or slurm)\n", req.backend.c_str());
        return 2;
    }
    const std::string manifest_path = fs::absolute(req.manifest).lexically_normal().string();
    RowRunOptions opt;
    opt.exe = this_executable();
    opt.out_dir = req.out_dir.empty() ? fs::path() : fs::absolute(req.out_dir).lexically_normal();
    opt.workdir = req.workdir.empty() ? fs::current_path() : fs::absolute(req.workdir);
    opt.fast = req.fast;
    opt.threads = req.threads;

    // What one scheduler task or one farm command does: run its rows, skipping complete ones. The
    // manifest was validated when the batch was submitted.
    if (!req.row.empty() || !req.task_file.empty()) {
        Manifest m;
        if (!read_and_report(manifest_path, m, false, req.fast)) return 2;
        std::vector<std::string> ids;
        if (!req.row.empty()) ids.push_back(req.row);
        else {
            std::ifstream in(req.task_file);
            std::string line;
            for (long k = 0; std::getline(in, line); ++k)
                if (k == req.task) {
                    std::istringstream words(line);
                    for (std::string id; words >> id;) ids.push_back(id);
                }
            if (ids.empty()) {
                std::fprintf(stderr, "crackflow batch: error: task %ld is not in %s\n", req.task, req.task_file.c_str());
                return 2;
            }
        }
        std::map<std::string, std::size_t> index;
        for (std::size_t i = 0; i < m.rows.size(); ++i) index[m.rows[i].id] = i;
        std::vector<std::size_t> rows;
        for (const auto& id : ids) {
            auto it = index.find(id);
            if (it == index.end()) {
                std::fprintf(stderr, "crackflow batch: error: %s has no row '%s' (was the manifest changed?)\n",
                             manifest_path.c_str(), id.c_str());
                return 2;
            }
            rows.push_back(it->second);
        }
        if (req.task_file.empty() && !fs::exists(row_list_file(opt.out_dir))) {
            std::vector<std::string> all;
            for (const auto& r : m.rows) all.push_back(r.id);
            write_row_list(opt.out_dir, all);
        }
        install_batch_signal_handlers();
        const int code = run_sequential(m, rows, opt);
        restore_default_signal_handlers();
        return code;
    }

    Manifest m;
    if (!read_and_report(manifest_path, m, true, req.fast)) return 2;
    if (req.check_only) {
        std::printf("%s: ok (%zu rows)\n", manifest_path.c_str(), m.rows.size());
        return 0;
    }
    if (req.jobs < 1) {
        std::fprintf(stderr, "crackflow batch: error: --jobs must be at least 1\n");
        return 2;
    }

    std::error_code ec;
    fs::create_directories(opt.out_dir, ec);
    if (ec) {
        std::fprintf(stderr, "crackflow batch: error: cannot create %s: %s\n", opt.out_dir.string().c_str(), ec.message().c_str());
        return 2;
    }
    std::vector<std::string> ids;
    for (const auto& r : m.rows) ids.push_back(r.id);
    write_row_list(opt.out_dir, ids);

    std::vector<bool> complete(m.rows.size());
    std::vector<std::size_t> pending;
    for (std::size_t i = 0; i < m.rows.size(); ++i) {
        complete[i] = row_completion(opt.out_dir / m.rows[i].id, m.rows[i], req.fast) == "ok";
        if (!complete[i]) pending.push_back(i);
    }
    if (m.rows.size() != pending.size())
        std::fprintf(stderr, "crackflow batch: %zu of %zu rows already complete (report.json status ok), skipped\n",
                     m.rows.size() - pending.size(), m.rows.size());

    if (!req.emit_commands.empty()) {
        std::ostringstream lines;
        for (std::size_t i : pending) {
            std::vector<std::string> cmd = {opt.exe, "batch", manifest_path, "--out", opt.out_dir.string(), "--row",
                                            m.rows[i].id, "--workdir", opt.workdir.string()};
            if (req.fast) cmd.push_back("--fast");
            if (req.threads > 0) cmd.insert(cmd.end(), {"--threads", std::to_string(req.threads)});
            lines << shell_command(cmd) << "\n";
        }
        if (req.emit_commands == "-") std::fputs(lines.str().c_str(), stdout);
        else {
            graph::write_atomically(req.emit_commands, [&](std::ostream& o) { o << lines.str(); });
            std::fprintf(stderr, "crackflow batch: %zu commands in %s; then: crackflow batch --collect %s\n", pending.size(),
                         req.emit_commands.c_str(), opt.out_dir.string().c_str());
        }
        return 0;
    }

    if (req.backend == "slurm") {
        SlurmOptions s = req.slurm;
        if (!req.slurm_config.empty()) {
            try {
                apply_slurm_config(req.slurm_config, req.slurm_given, s);
            } catch (const std::exception& e) {
                std::fprintf(stderr, "crackflow batch: error: %s\n", e.what());
                return 2;
            }
        }
        opt.threads = std::max(1, s.cpus_per_task);
        install_batch_signal_handlers();
        const int code = run_slurm(m, manifest_path, complete, opt, s);
        restore_default_signal_handlers();
        return code;
    }

    // Local: rows share the cores, so each gets its part unless --threads says otherwise.
    if (opt.threads <= 0) opt.threads = std::max(1, tbb::info::default_concurrency() / req.jobs);
    std::fprintf(stderr, "crackflow batch: %zu rows, %d at a time, %d thread%s each; outputs in %s/<id>\n", pending.size(),
                 req.jobs, opt.threads, opt.threads == 1 ? "" : "s", opt.out_dir.string().c_str());
    install_batch_signal_handlers();
    const LocalOutcome o = run_local(m, pending, req.jobs, opt);
    const int sig = batch_signal();
    restore_default_signal_handlers();
    const auto results = collect(opt.out_dir);
    const SummaryCounts n = count(results);
    for (const auto& r : results)
        if (r.status != "ok")
            std::fprintf(stderr, "  %s: %s%s%s (log: %s)\n", r.id.c_str(), r.status.c_str(), r.error.empty() ? "" : ": ",
                         r.error.c_str(), r.log.c_str());
    std::fprintf(stderr, "crackflow batch: %d of %d rows ok, %d failed; summary in %s\n", n.ok, n.total, n.failed,
                 (opt.out_dir / "summary.csv").string().c_str());
    if (o.cancelled) return sig == SIGTERM ? 143 : 130;
    return batch_exit_code(results);
}

}  // namespace cf::runtime
