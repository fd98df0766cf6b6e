#pragma once
// Running a shell command from a test (an independent reader: python3-vtk, the Khronos glTF
// validator) and reading what it printed.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace cf::testing {

// s in single quotes for /bin/sh, inner quotes escaped.
inline std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
}

struct CommandResult {
    int exit_code = -1;  // -1: could not start, or did not exit normally
    std::string output;  // stdout and stderr
};

inline CommandResult run_command(const std::string& command) {
    CommandResult r;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

}  // namespace cf::testing
