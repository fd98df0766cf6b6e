#pragma once
// Posix child processes for the batch runners: start a command with its output appended to a log,
// reap it with its resource use, and run a short command capturing its output (sbatch, squeue).
#include <filesystem>
#include <string>
#include <sys/types.h>
#include <vector>

namespace cf::runtime {

// Starts argv[0] (a path, no shell) with stdout and stderr appended to `log` and stdin from
// /dev/null, in `workdir` (unchanged when empty). The child gets SIGTERM if this process dies, so
// a killed batch leaves no orphans. Throws std::runtime_error when fork fails.
pid_t spawn_logged(const std::vector<std::string>& argv, const std::filesystem::path& log,
                   const std::filesystem::path& workdir);

struct ChildExit {
    pid_t pid = 0;
    bool exited = false;     // else killed by `signal`
    int exit_code = -1;
    int signal = 0;
    long long peak_rss_bytes = 0;
};
// Reaps one finished child (pid -1: any). With `block` false returns pid 0 when none has finished.
// Returns pid -1 when there is no child left (or an error other than EINTR).
ChildExit reap_child(pid_t pid, bool block);

struct CommandOutput {
    int exit_code = -1;  // 127 when the program cannot be started
    std::string out, err;
};
// Runs a command to completion (no shell) and returns its output.
CommandOutput run_capture(const std::vector<std::string>& argv);

// "a 'b c'": one shell word per argument, quoted only where needed.
std::string shell_quote(const std::string& word);
std::string shell_command(const std::vector<std::string>& argv);

}  // namespace cf::runtime
