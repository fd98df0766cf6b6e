#include "runtime/batch_runner.hpp"

#include "graph/atomic_write.hpp"
#include "runtime/batch_plan.hpp"
#include "runtime/child_process.hpp"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <thread>
#include <unistd.h>

namespace cf::runtime::batch {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

std::atomic<int> g_signal{0};
extern "C" void on_batch_signal(int sig) { g_signal.store(sig); }

std::string utc_now() {
    char when[32];
    std::time_t now = std::time(nullptr);
    std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    return when;
}

std::string hostname() {
    char h[256] = {};
    gethostname(h, sizeof h - 1);
    return h;
}

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

void write_record(const fs::path& row_dir, const RowRecord& r) {
    graph::write_atomically(row_dir / kRowRecord, [&](std::ostream& o) { o << row_record_json(r); });
}

// A new attempt at a row: outputs of an earlier attempt are removed (a shorter run must not leave
// files of a longer one behind); the log keeps every attempt.
RowRecord begin_attempt(const Row& row, const RowRunOptions& options) {
    const fs::path dir = options.out_dir / row.id;
    RowRecord previous;
    const bool had = read_row_record(dir / kRowRecord, previous);
    std::error_code ec;
    if (fs::is_directory(dir, ec))
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.path().filename() != kRowLog) fs::remove_all(e.path(), ec);
    fs::create_directories(dir);
    RowRecord r;
    r.id = row.id;
    r.state = "running";
    r.host = hostname();
    r.started_utc = utc_now();
    r.job_id = env("SLURM_JOB_ID");
    r.array_job_id = env("SLURM_ARRAY_JOB_ID");
    r.array_task_id = env("SLURM_ARRAY_TASK_ID");
    r.attempt = had ? previous.attempt + 1 : 1;
    std::ofstream log(dir / kRowLog, std::ios::app);
    log << "== crackflow batch: row '" << row.id << "', attempt " << r.attempt << ", " << r.started_utc << " on " << r.host;
    if (!r.array_job_id.empty()) log << ", Slurm array job " << r.array_job_id << " task " << r.array_task_id;
    log << "\n== " << shell_command(run_argv(row, options)) << "\n";
    log.close();
    write_record(dir, r);
    return r;
}

void end_attempt(const fs::path& row_dir, RowRecord& r, const ChildExit& e, double seconds) {
    r.state = e.exited ? "exited" : "signalled";
    r.exit_code = e.exited ? e.exit_code : -1;
    r.signal = e.signal;
    r.seconds = seconds;
    r.peak_rss_bytes = e.peak_rss_bytes;
    std::ofstream log(row_dir / kRowLog, std::ios::app);
    if (e.exited) log << "== exit code " << e.exit_code;
    else log << "== killed by signal " << e.signal << " (" << strsignal(e.signal) << ")";
    log << " after " << seconds << " s\n";
    log.close();
    write_record(row_dir, r);
}

bool is_ok(const ChildExit& e) { return e.exited && e.exit_code == 0; }

}  // namespace

std::vector<std::string> run_argv(const Row& row, const RowRunOptions& options) {
    std::vector<std::string> a = {options.exe, "run", row.pipeline, "--out", (options.out_dir / row.id).string()};
    for (const auto& s : set_arguments(row)) a.insert(a.end(), {"--set", s});
    if (options.fast) a.push_back("--fast");
    if (options.threads > 0) a.insert(a.end(), {"--threads", std::to_string(options.threads)});
    return a;
}

int batch_signal() { return g_signal.load(); }

void install_batch_signal_handlers() {
    g_signal.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_batch_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;  // no SA_RESTART: a blocking wait returns at once
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

void restore_default_signal_handlers() {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
}

std::string progress_line(int done, int total, int ok, int failed, int running, double seconds) {
    const long s = static_cast<long>(seconds);
    char t[32];
    if (s >= 3600) std::snprintf(t, sizeof t, "%ldh%02ldm%02lds", s / 3600, s / 60 % 60, s % 60);
    else if (s >= 60) std::snprintf(t, sizeof t, "%ldm%02lds", s / 60, s % 60);
    else std::snprintf(t, sizeof t, "%lds", s);
    return std::to_string(done) + "/" + std::to_string(total) + " rows done (" + std::to_string(ok) + " ok, " +
           std::to_string(failed) + " failed), " + std::to_string(running) + " running, " + t;
}

LocalOutcome run_local(const Manifest& manifest, const std::vector<std::size_t>& rows, int jobs,
                       const RowRunOptions& options, double grace_seconds) {
    struct Running {
        std::size_t row;
        RowRecord record;
        Clock::time_point start;
    };
    std::map<pid_t, Running> running;
    LocalOutcome out;
    const bool tty = isatty(fileno(stderr)) != 0;
    const auto t0 = Clock::now();
    std::string last;
    auto show = [&](bool final) {
        const std::string line = "crackflow batch: " + progress_line(out.finished, static_cast<int>(rows.size()), out.ok,
                                                                     out.failed, static_cast<int>(running.size()),
                                                                     std::chrono::duration<double>(Clock::now() - t0).count());
        // On a terminal the line is redrawn every second; in a log, one line per change.
        if (tty) std::fprintf(stderr, "\r%s\033[K%s", line.c_str(), final ? "\n" : "");
        else if (line.substr(0, line.rfind(',')) != last.substr(0, last.rfind(',')))
            std::fprintf(stderr, "%s\n", line.c_str());
        last = line;
    };
    std::size_t next = 0;
    int forwarded = 0;
    Clock::time_point forwarded_at;
    bool killed = false;
    auto last_shown = Clock::now();
    while (next < rows.size() || !running.empty()) {
        const int sig = batch_signal();
        if (sig && !forwarded) {
            // Stop: no new rows; the running ones get the same signal and end as a cancelled run
            // (report written, exit 130/143); SIGKILL if they do not within the grace time.
            out.cancelled = true;
            forwarded = sig;
            forwarded_at = Clock::now();
            for (const auto& [pid, r] : running) kill(pid, sig);
        }
        if (forwarded && !killed && std::chrono::duration<double>(Clock::now() - forwarded_at).count() > grace_seconds) {
            for (const auto& [pid, r] : running) kill(pid, SIGKILL);
            killed = true;
        }
        while (!forwarded && next < rows.size() && static_cast<int>(running.size()) < jobs) {
            const Row& row = manifest.rows[rows[next++]];
            RowRecord rec = begin_attempt(row, options);
            const pid_t pid = spawn_logged(run_argv(row, options), options.out_dir / row.id / kRowLog, options.workdir);
            running.emplace(pid, Running{rows[next - 1], rec, Clock::now()});
            show(false);
        }
        if (running.empty() && (forwarded || next >= rows.size())) break;
        const ChildExit e = reap_child(-1, false);
        if (e.pid > 0) {
            auto it = running.find(e.pid);
            if (it == running.end()) continue;
            Running r = it->second;
            running.erase(it);
            const Row& row = manifest.rows[r.row];
            end_attempt(options.out_dir / row.id, r.record, e,
                        std::chrono::duration<double>(Clock::now() - r.start).count());
            ++out.finished;
            if (is_ok(e)) ++out.ok;
            else ++out.failed;
            show(false);
            continue;
        }
        if (e.pid < 0 && running.empty()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (tty && Clock::now() - last_shown > std::chrono::seconds(1)) show(false), last_shown = Clock::now();
    }
    show(true);
    return out;
}

int run_sequential(const Manifest& manifest, const std::vector<std::size_t>& rows, const RowRunOptions& options) {
    int failed = 0;
    for (std::size_t i : rows) {
        if (batch_signal()) break;
        const Row& row = manifest.rows[i];
        const fs::path dir = options.out_dir / row.id;
        if (row_completion(dir, row, options.fast) == "ok") {
            std::fprintf(stderr, "crackflow batch: row '%s' is complete (%s/report.json), skipped\n", row.id.c_str(),
                         dir.string().c_str());
            continue;
        }
        RowRecord rec = begin_attempt(row, options);
        const auto start = Clock::now();
        const pid_t pid = spawn_logged(run_argv(row, options), dir / kRowLog, options.workdir);
        std::fprintf(stderr, "crackflow batch: row '%s' started (log: %s)\n", row.id.c_str(), (dir / kRowLog).string().c_str());
        ChildExit e;
        int forwarded = 0;
        for (;;) {
            e = reap_child(pid, true);
            if (e.pid == pid || e.pid < 0) break;
            // Interrupted: Slurm's time limit or scancel (SIGTERM), or Ctrl-C. The run cancels itself cleanly.
            if (const int sig = batch_signal(); sig && !forwarded) kill(pid, sig), forwarded = sig;
        }
        end_attempt(dir, rec, e, std::chrono::duration<double>(Clock::now() - start).count());
        std::fprintf(stderr, "crackflow batch: row '%s' %s\n", row.id.c_str(),
                     is_ok(e) ? "ok" : e.exited ? ("failed, exit code " + std::to_string(e.exit_code)).c_str()
                                                : ("killed by signal " + std::to_string(e.signal)).c_str());
        if (!is_ok(e)) ++failed;
    }
    if (const int sig = batch_signal()) return sig == SIGTERM ? 143 : 130;
    return failed ? 1 : 0;
}

}  // namespace cf::runtime::batch
