#pragma once
// Running rows as `crackflow run` child processes: one attempt at a row (its folder, log and
// record), the local backend (at most N at once, progress line, Ctrl-C ends them all), and the
// sequential runner a scheduler task or a farm command uses.
#include "runtime/batch_manifest.hpp"
#include "runtime/batch_summary.hpp"

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

namespace cf::runtime::batch {

struct RowRunOptions {
    std::string exe;                 // the crackflow binary (absolute)
    std::filesystem::path out_dir;   // the batch's DIR (absolute)
    std::filesystem::path workdir;   // where rows run (relative mesh paths are read from here)
    bool fast = false;
    int threads = 0;                 // per row; 0: crackflow's default
};

// crackflow run PIPELINE --out DIR/<id> --set ... [--fast] [--threads N]
std::vector<std::string> run_argv(const Row& row, const RowRunOptions& options);

// The batch's signal (SIGINT, SIGTERM) once one arrived, else 0. install_batch_signal_handlers
// makes SIGINT and SIGTERM set it (and interrupt waits) instead of ending the process.
int batch_signal();
void install_batch_signal_handlers();
void restore_default_signal_handlers();

// Runs `rows` (indices into manifest.rows) with at most `jobs` at once, in manifest order. On
// SIGINT/SIGTERM stops starting rows, passes the signal to the running ones and waits for them
// (SIGKILL after `grace_seconds`). Returns the process exits seen, in order of completion.
struct LocalOutcome {
    int finished = 0, ok = 0, failed = 0;
    bool cancelled = false;
};
LocalOutcome run_local(const Manifest& manifest, const std::vector<std::size_t>& rows, int jobs,
                       const RowRunOptions& options, double grace_seconds = 10);

// Runs the rows one after the other, skipping complete ones (what one scheduler task or one farm
// command does). Returns 0 when every row is ok, 130/143 when cancelled, else 1.
int run_sequential(const Manifest& manifest, const std::vector<std::size_t>& rows, const RowRunOptions& options);

// One line of progress: "12/50 rows done (11 ok, 1 failed), 2 running, 1m03s".
std::string progress_line(int done, int total, int ok, int failed, int running, double seconds);

}  // namespace cf::runtime::batch
