#include "runtime/child_process.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace cf::runtime {

namespace {
std::vector<char*> c_argv(const std::vector<std::string>& argv) {
    std::vector<char*> r;
    for (const auto& a : argv) r.push_back(const_cast<char*>(a.c_str()));
    r.push_back(nullptr);
    return r;
}
}  // namespace

pid_t spawn_logged(const std::vector<std::string>& argv, const std::filesystem::path& log,
                   const std::filesystem::path& workdir) {
    // Everything the child needs is prepared before fork: after it only async-signal-safe calls.
    auto args = c_argv(argv);
    const std::string log_path = log.string(), dir = workdir.string();
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error(std::string("cannot start a process: fork: ") + std::strerror(errno));
    if (pid > 0) return pid;
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before prctl
    // The batch's own handlers are not the child's: default dispositions, nothing blocked.
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    const int in = open("/dev/null", O_RDONLY);
    const int out = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (in < 0 || out < 0) _exit(127);
    dup2(in, 0);
    dup2(out, 1);
    dup2(out, 2);
    if (!dir.empty() && chdir(dir.c_str()) != 0) {
        const char msg[] = "crackflow batch: cannot change to the working directory\n";
        (void)!write(2, msg, sizeof msg - 1);
        _exit(127);
    }
    execv(args[0], args.data());
    const char msg[] = "crackflow batch: cannot execute the crackflow binary\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(127);
}

ChildExit reap_child(pid_t pid, bool block) {
    ChildExit r;
    for (;;) {
        int status = 0;
        rusage u{};
        const pid_t got = wait4(pid, &status, block ? 0 : WNOHANG, &u);
        if (got < 0 && errno == EINTR) {
            if (!block) return r;
            r.pid = 0;  // interrupted by a signal: let the caller look at its flags
            return r;
        }
        if (got <= 0) {
            r.pid = got;
            return r;
        }
        r.pid = got;
        r.peak_rss_bytes = static_cast<long long>(u.ru_maxrss) * 1024;
        if (WIFEXITED(status)) r.exited = true, r.exit_code = WEXITSTATUS(status);
        else if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
        else continue;  // stopped/continued: not an end
        return r;
    }
}

CommandOutput run_capture(const std::vector<std::string>& argv) {
    CommandOutput r;
    int out_pipe[2], err_pipe[2];
    if (pipe(out_pipe) != 0) return r;
    if (pipe(err_pipe) != 0) {
        close(out_pipe[0]), close(out_pipe[1]);
        return r;
    }
    auto args = c_argv(argv);
    const pid_t pid = fork();
    if (pid < 0) {
        for (int fd : {out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1]}) close(fd);
        return r;
    }
    if (pid == 0) {
        std::signal(SIGINT, SIG_DFL);
        std::signal(SIGTERM, SIG_DFL);
        const int in = open("/dev/null", O_RDONLY);
        if (in >= 0) dup2(in, 0);
        dup2(out_pipe[1], 1);
        dup2(err_pipe[1], 2);
        close(out_pipe[0]), close(err_pipe[0]);
        execvp(args[0], args.data());
        _exit(127);
    }
    close(out_pipe[1]), close(err_pipe[1]);
    pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
    int open_fds = 2;
    char buf[4096];
    while (open_fds > 0) {
        if (poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            break;
        }
        for (int k = 0; k < 2; ++k) {
            if (fds[k].fd < 0 || !(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            const ssize_t n = read(fds[k].fd, buf, sizeof buf);
            if (n > 0) (k == 0 ? r.out : r.err).append(buf, static_cast<std::size_t>(n));
            else if (n == 0 || errno != EINTR) {
                close(fds[k].fd);
                fds[k].fd = -1;
                --open_fds;
            }
        }
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

std::string shell_quote(const std::string& w) {
    if (!w.empty() && w.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-./=:,+@%") ==
                          std::string::npos)
        return w;
    std::string q = "'";
    for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

std::string shell_command(const std::vector<std::string>& argv) {
    std::string s;
    for (const auto& a : argv) s += (s.empty() ? "" : " ") + shell_quote(a);
    return s;
}

}  // namespace cf::runtime
