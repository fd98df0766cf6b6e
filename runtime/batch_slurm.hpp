#pragma once
// The Slurm backend: one job script, the tasks file (row ids per task), submission as job arrays
// split at MaxArraySize, and waiting for them. The script text and the packing are plain
// functions; sbatch, scontrol and squeue are run as commands (the SLURM_CONF of the environment
// applies).
#include "runtime/batch_manifest.hpp"
#include "runtime/batch_runner.hpp"

#include <string>
#include <vector>

namespace cf::runtime::batch {

struct SlurmOptions {
    std::string partition, time, mem;  // sbatch --partition, --time, --mem; empty: the cluster's default
    int cpus_per_task = 1;             // also each row's --threads
    int max_parallel = 0;              // tasks running at once (--array=...%P); 0: no limit
    int rows_per_task = 0;             // 0: chosen from the row duration (rows_per_task())
    double row_seconds = 60;           // estimated seconds per row, when no row has run yet
    double task_overhead_seconds = 1;  // measured on a one-node cluster: ~0.7 s (docs/performance.md)
    long max_array_size = 0;           // 0: from `scontrol show config`, else 1001
    std::vector<std::string> sbatch_options;  // passed as they are, e.g. --account=vfx
    bool wait = false;
};

// Reads a cluster's defaults from a YAML file (docs/batch.md):
//   partition: short
//   time: "0:30:00"
//   mem: 4G
//   cpus-per-task: 2
//   max-parallel: 50
//   rows-per-task: 4
//   sbatch-options: [--account=vfx]
// Keys named in `given` (set on the command line) keep the command line's value. Throws
// std::runtime_error naming the file, line and key on an unknown key or a bad value.
void apply_slurm_config(const std::string& file, const std::vector<std::string>& given, SlurmOptions& options);

struct JobScript {
    std::string exe, manifest, out_dir, workdir, tasks_file, log_dir, job_name;
    bool fast = false;
    SlurmOptions slurm;
};
// The sbatch script: directives, then one call of `crackflow batch --task` for the array index
// plus the offset given as the script's first argument.
std::string job_script(const JobScript& s);

// Submits the rows not yet complete and, with `wait`, waits for them and writes the summary.
// Returns the batch exit code (0 all ok, 1 rows failed, 2 submission refused, 130 interrupted).
int run_slurm(const Manifest& manifest, const std::string& manifest_path, const std::vector<bool>& complete,
              const RowRunOptions& rows, const SlurmOptions& options);

}  // namespace cf::runtime::batch
