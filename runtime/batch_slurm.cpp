#include "runtime/batch_slurm.hpp"

#include "graph/atomic_write.hpp"
#include "graph/diagnostics.hpp"
#include "runtime/batch_plan.hpp"
#include "runtime/batch_summary.hpp"
#include "runtime/child_process.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <stdexcept>
#include <thread>
#include <yaml-cpp/yaml.h>
#include <unistd.h>

namespace cf::runtime::batch {

namespace fs = std::filesystem;

std::string job_script(const JobScript& s) {
    const SlurmOptions& o = s.slurm;
    std::string t = "#!/bin/sh\n";
    t += "# crackflow batch " + s.manifest + " --out " + s.out_dir + " (written by crackflow batch --backend slurm)\n";
    t += "#SBATCH --job-name=" + s.job_name + "\n";
    t += "#SBATCH --output=" + s.log_dir + "/task_%A_%a.log\n";
    t += "#SBATCH --open-mode=append\n";  // a resubmitted index appends to its log
    t += "#SBATCH --chdir=" + s.workdir + "\n";
    t += "#SBATCH --nodes=1\n#SBATCH --ntasks=1\n";
    t += "#SBATCH --cpus-per-task=" + std::to_string(std::max(1, o.cpus_per_task)) + "\n";
    if (!o.mem.empty()) t += "#SBATCH --mem=" + o.mem + "\n";
    if (!o.time.empty()) t += "#SBATCH --time=" + o.time + "\n";
    if (!o.partition.empty()) t += "#SBATCH --partition=" + o.partition + "\n";
    t += "# Task number = array index + this array's offset ($1): arrays are split at MaxArraySize.\n";
    std::vector<std::string> cmd = {s.exe, "batch", s.manifest, "--out", s.out_dir, "--task-file", s.tasks_file};
    if (s.fast) cmd.push_back("--fast");
    cmd.insert(cmd.end(), {"--threads", std::to_string(std::max(1, o.cpus_per_task))});
    t += "exec " + shell_command(cmd) + " --task \"$(( ${1:-0} + SLURM_ARRAY_TASK_ID ))\"\n";
    return t;
}

void apply_slurm_config(const std::string& file, const std::vector<std::string>& given, SlurmOptions& o) {
    YAML::Node root;
    try {
        root = YAML::LoadFile(file);
    } catch (const YAML::BadFile&) {
        throw std::runtime_error(file + ": cannot open the Slurm configuration file");
    } catch (const YAML::ParserException& e) {
        throw std::runtime_error(file + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                                 ": YAML syntax error: " + e.msg);
    }
    if (root.IsNull()) return;
    if (!root.IsMap()) throw std::runtime_error(file + ": a Slurm configuration is a mapping, e.g. 'partition: short'");
    const std::vector<std::string> keys = {"partition", "time", "mem", "cpus-per-task", "max-parallel", "rows-per-task",
                                           "row-seconds", "max-array-size", "sbatch-options"};
    for (auto it = root.begin(); it != root.end(); ++it) {
        const std::string key = it->first.Scalar();
        const YAML::Mark m = it->first.Mark();
        const std::string where = file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
        if (std::find(keys.begin(), keys.end(), key) == keys.end())
            throw std::runtime_error(where + ": unknown key '" + key + "' (" + graph::did_you_mean(key, keys) + ")");
        if (std::find(given.begin(), given.end(), key) != given.end()) continue;  // the command line wins
        try {
            const YAML::Node v = it->second;
            if (key == "partition") o.partition = v.as<std::string>();
            else if (key == "time") o.time = v.as<std::string>();
            else if (key == "mem") o.mem = v.as<std::string>();
            else if (key == "cpus-per-task") o.cpus_per_task = v.as<int>();
            else if (key == "max-parallel") o.max_parallel = v.as<int>();
            else if (key == "rows-per-task") o.rows_per_task = v.as<int>();
            else if (key == "row-seconds") o.row_seconds = v.as<double>();
            else if (key == "max-array-size") o.max_array_size = v.as<long>();
            else if (key == "sbatch-options") o.sbatch_options = v.as<std::vector<std::string>>();
        } catch (const YAML::Exception&) {
            throw std::runtime_error(where + ": the value of '" + key + "' is not " +
                                     (key == "sbatch-options" ? "a list of texts" : key == "partition" || key == "time" || key == "mem"
                                                                                       ? "a text"
                                                                                       : "a number"));
        }
        if ((key == "cpus-per-task" && o.cpus_per_task < 1) || (key == "max-parallel" && o.max_parallel < 1) ||
            (key == "rows-per-task" && o.rows_per_task < 1) || (key == "row-seconds" && !(o.row_seconds > 0)) ||
            (key == "max-array-size" && o.max_array_size < 1))
            throw std::runtime_error(where + ": '" + key + "' must be positive");
    }
}

namespace {

std::string utc_stamp() {
    char when[32];
    std::time_t now = std::time(nullptr);
    std::strftime(when, sizeof when, "%Y%m%dT%H%M%SZ", std::gmtime(&now));
    return when;
}

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
    return s;
}

// Median seconds of the rows that already ran to completion (their records), or -1.
double measured_row_seconds(const Manifest& m, const fs::path& out_dir, const std::vector<bool>& complete) {
    std::vector<double> s;
    for (std::size_t i = 0; i < m.rows.size(); ++i) {
        RowRecord r;
        if (complete[i] && read_row_record(out_dir / m.rows[i].id / kRowRecord, r) && r.seconds > 0) s.push_back(r.seconds);
    }
    if (s.empty()) return -1;
    std::sort(s.begin(), s.end());
    return s[s.size() / 2];
}

// Until none of the jobs is pending or running. Returns false when interrupted.
bool wait_for_jobs(const std::vector<std::string>& jobs) {
    std::string ids;
    for (const auto& j : jobs) ids += (ids.empty() ? "" : ",") + j;
    std::string last;
    for (;;) {
        if (batch_signal()) return false;
        const CommandOutput q = run_capture({"squeue", "-h", "-j", ids, "-o", "%i %T"});
        // A job that has left the controller's memory is "invalid": finished long ago.
        if (q.exit_code != 0 && q.err.find("Invalid job id") == std::string::npos) {
            std::fprintf(stderr, "crackflow batch: squeue failed (%s); still waiting\n", trim(q.err).c_str());
        } else {
            int pending = 0, running = 0;
            std::size_t pos = 0;
            while (pos < q.out.size()) {
                const auto nl = q.out.find('\n', pos);
                const std::string line = q.out.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
                if (line.find("PENDING") != std::string::npos) ++pending;
                else if (!trim(line).empty()) ++running;
                pos = nl == std::string::npos ? q.out.size() : nl + 1;
            }
            if (q.exit_code == 0 && pending + running == 0) return true;
            if (q.exit_code != 0) return true;
            const std::string now = std::to_string(pending) + " pending, " + std::to_string(running) + " running";
            if (now != last) std::fprintf(stderr, "crackflow batch: Slurm tasks: %s\n", now.c_str());
            last = now;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
}

}  // namespace

int run_slurm(const Manifest& manifest, const std::string& manifest_path, const std::vector<bool>& complete,
              const RowRunOptions& rows, const SlurmOptions& options) {
    int r = options.rows_per_task;
    if (r <= 0) {
        const double measured = measured_row_seconds(manifest, rows.out_dir, complete);
        r = rows_per_task(measured > 0 ? measured : options.row_seconds, options.task_overhead_seconds);
    }
    const auto tasks = pack_rows(manifest.rows.size(), r);
    const auto pending = tasks_with_pending_rows(tasks, complete);
    if (pending.empty()) {
        std::fprintf(stderr, "crackflow batch: all %zu rows are complete; nothing to submit\n", manifest.rows.size());
        const auto results = collect(rows.out_dir);
        return count(results).failed ? 1 : 0;
    }
    long max_array = options.max_array_size;
    if (max_array <= 0) {
        const CommandOutput c = run_capture({"scontrol", "show", "config"});
        if (c.exit_code == 127) {
            std::fprintf(stderr, "crackflow batch: error: cannot run scontrol: is Slurm's client (slurm-client) installed?\n");
            return 2;
        }
        if (c.exit_code != 0) {
            std::fprintf(stderr, "crackflow batch: error: scontrol show config failed: %s\n  hint: is this a Slurm submit host "
                                 "(SLURM_CONF, or slurm.conf in /etc/slurm)? --max-array-size skips this query\n",
                         trim(c.err).c_str());
            return 2;
        }
        max_array = parse_max_array_size(c.out);
    }
    const auto chunks = split_into_arrays(pending, max_array, options.max_parallel);

    const fs::path sub = rows.out_dir / ".batch" / "slurm" / (utc_stamp() + "-" + std::to_string(getpid()));
    fs::create_directories(sub);
    const fs::path tasks_file = sub / "tasks.txt", script = sub / "job.sh";
    graph::write_atomically(tasks_file, [&](std::ostream& o) {
        for (const auto& t : tasks) {
            for (std::size_t k = 0; k < t.size(); ++k) o << (k ? " " : "") << manifest.rows[t[k]].id;
            o << "\n";
        }
    });
    JobScript js;
    js.exe = rows.exe;
    js.manifest = manifest_path;
    js.out_dir = rows.out_dir.string();
    js.workdir = rows.workdir.string();
    js.tasks_file = tasks_file.string();
    js.log_dir = sub.string();
    js.job_name = "crackflow-" + rows.out_dir.filename().string();
    js.fast = rows.fast;
    js.slurm = options;
    graph::write_atomically(script, [&](std::ostream& o) { o << job_script(js); });
    fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add);

    std::size_t pending_rows = 0;
    for (bool c : complete) pending_rows += c ? 0 : 1;
    std::fprintf(stderr, "crackflow batch: %zu of %zu rows to run, %d per task: %zu task%s in %zu array job%s (MaxArraySize %ld)\n",
                 pending_rows, manifest.rows.size(), r, pending.size(), pending.size() == 1 ? "" : "s", chunks.size(),
                 chunks.size() == 1 ? "" : "s", max_array);
    std::vector<std::string> jobs;
    for (const auto& c : chunks) {
        std::vector<std::string> cmd = {"sbatch", "--parsable", "--array=" + c.array_spec};
        cmd.insert(cmd.end(), options.sbatch_options.begin(), options.sbatch_options.end());
        cmd.insert(cmd.end(), {script.string(), std::to_string(c.offset)});
        const CommandOutput o = run_capture(cmd);
        if (o.exit_code != 0) {
            std::fprintf(stderr, "crackflow batch: error: %s failed (exit %d): %s\n", shell_command(cmd).c_str(), o.exit_code,
                         o.exit_code == 127 ? "sbatch not found: is Slurm's client (slurm-client) installed?" : trim(o.err).c_str());
            if (!jobs.empty()) {
                std::string ids;
                for (const auto& j : jobs) ids += " " + j;
                std::fprintf(stderr, "crackflow batch: array jobs already submitted:%s (scancel them, or let them run)\n", ids.c_str());
            }
            return 2;
        }
        const std::string id = trim(o.out).substr(0, trim(o.out).find(';'));
        jobs.push_back(id);
        std::fprintf(stderr, "crackflow batch: submitted array job %s: tasks %s (array indices %s, offset %ld)\n", id.c_str(),
                     index_ranges([&] {
                         std::vector<long> t;
                         for (long i : c.indices) t.push_back(i + c.offset);
                         return t;
                     }()).c_str(),
                     c.array_spec.c_str(), c.offset);
    }
    graph::write_atomically(sub / "jobs.txt", [&](std::ostream& o) {
        for (const auto& j : jobs) o << j << "\n";
    });
    std::fprintf(stderr, "crackflow batch: job script %s, task logs %s/task_<job>_<index>.log\n", script.string().c_str(),
                 sub.string().c_str());
    if (!options.wait) {
        std::fprintf(stderr, "crackflow batch: when the jobs are done: crackflow batch --collect %s\n",
                     rows.out_dir.string().c_str());
        return 0;
    }
    if (!wait_for_jobs(jobs)) {
        std::vector<std::string> cancel = {"scancel"};
        cancel.insert(cancel.end(), jobs.begin(), jobs.end());
        run_capture(cancel);
        std::fprintf(stderr, "crackflow batch: interrupted; cancelled the array jobs (scancel)\n");
        return batch_signal() == SIGTERM ? 143 : 130;
    }
    const auto results = collect(rows.out_dir);
    const SummaryCounts n = count(results);
    std::fprintf(stderr, "crackflow batch: %d of %d rows ok, %d failed; summary in %s\n", n.ok, n.total, n.failed,
                 (rows.out_dir / "summary.csv").string().c_str());
    return batch_exit_code(results);
}

}  // namespace cf::runtime::batch
