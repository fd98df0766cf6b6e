#pragma once
// `crackflow batch`: a manifest of runs on this machine (local), as Slurm job arrays, or as one
// command per line for another farm manager; --collect summarises a batch's folder.
#include "runtime/batch_slurm.hpp"

#include <string>

namespace cf::runtime {

struct BatchRequest {
    std::string manifest;
    std::string out_dir;
    std::string backend = "local";  // local | slurm
    int jobs = 1;                   // local: rows at once
    int threads = 0;                // per row; 0: local: cores / jobs, slurm: --cpus-per-task
    bool fast = false;
    bool check_only = false;        // validate the manifest, run nothing
    std::string emit_commands;      // file ("-": stdout) for one command per pending row
    std::string collect_dir;        // --collect DIR
    // Internal: what a scheduler task or a farm command runs.
    std::string row;                // --row ID
    std::string task_file;          // --task-file F --task K
    long task = -1;
    std::string workdir;            // --workdir (rows' working directory; default: the current one)
    batch::SlurmOptions slurm;
    std::string slurm_config;              // --slurm-config FILE (YAML)
    std::vector<std::string> slurm_given;  // the Slurm options given on the command line (they win)
};

// Exit codes: 0 every row ok; 1 some rows failed (rerun the same command to retry only those);
// 2 bad input (manifest, options, a refused submission): nothing ran, fix it first; 130/143
// cancelled (Ctrl-C, SIGTERM).
int batch_command(const BatchRequest& request);

}  // namespace cf::runtime
