// The bound on Ctrl-C around calls that cannot be polled (runtime/cancel_deadline.hpp) and the
// abandoning of pending writes it relies on (graph/atomic_write.hpp).
#include "graph/atomic_write.hpp"
#include "runtime/cancel_deadline.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <future>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::size_t files_in(const std::filesystem::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

// A writer blocked in its callback when the run is abandoned: its temporary is removed at once, it
// may not rename afterwards (throws, nothing under the final name), and the abandoning thread may
// still write (the report). Abandoning is process-wide, so this test runs in a child process.
TEST(CancelDeadline, AbandonRemovesPendingTemporariesAndBlocksOtherWriters) {
    const auto dir = cf::testing::temp_dir("abandon-writes");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::promise<void> inside, release;
        std::shared_future<void> released = release.get_future().share();
        auto writer = std::async(std::launch::async, [&] {
            try {
                cf::graph::write_atomically(dir / "slow.bin", [&](std::ostream& o) {
                    o << std::string(1 << 20, 'x');
                    o.flush();
                    inside.set_value();
                    released.wait();
                });
            } catch (const std::exception& e) {
                return std::string(e.what());
            }
            return std::string("no error");
        });
        inside.get_future().wait();
        if (files_in(dir) != 1) _exit(10);  // the temporary
        if (cf::graph::abandon_pending_writes() != 1) _exit(11);
        if (files_in(dir) != 0) _exit(12);
        release.set_value();
        const std::string what = writer.get();
        if (what.find("slow.bin: the run was cancelled") == std::string::npos) _exit(13);
        if (std::filesystem::exists(dir / "slow.bin") || files_in(dir) != 0) _exit(14);
        // A writer starting later on another thread is refused before it creates anything.
        auto late = std::async(std::launch::async, [&] {
            try {
                cf::graph::write_atomically(dir / "late.txt", [](std::ostream& o) { o << "late"; });
            } catch (const std::exception&) {
                return false;
            }
            return true;
        });
        if (late.get() || files_in(dir) != 0) _exit(15);
        cf::graph::write_atomically(dir / "report.json", [](std::ostream& o) { o << "{}"; });
        if (!std::filesystem::exists(dir / "report.json") || files_in(dir) != 1) _exit(16);
        _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "step that failed: exit code 10-16 in the test's order";
}

// The deadline calls abandon `grace` after the signal if the run is still going, not before, and
// never when the run returns first or no signal comes.
TEST(CancelDeadline, AbandonsOnlyARunStillGoingAGraceAfterTheSignal) {
    std::atomic<int> signal{0};
    {
        std::promise<std::pair<int, double>> called;
        auto when = called.get_future();
        const auto t0 = Clock::now();
        {
            cf::runtime::CancelDeadline d(signal, 200ms, [&](int sig) {
                called.set_value({sig, std::chrono::duration<double>(Clock::now() - t0).count()});
            });
            std::this_thread::sleep_for(100ms);
            signal.store(SIGTERM);
            ASSERT_EQ(when.wait_for(5s), std::future_status::ready);
        }
        const auto [sig, seconds] = when.get();
        EXPECT_EQ(sig, SIGTERM);
        // 0.1 s before the signal + 0.2 s grace; the signal is read every 20 ms.
        EXPECT_GE(seconds, 0.3);
        EXPECT_LT(seconds, 0.3 + 0.5);  // scheduling margin on a loaded machine
    }
    signal.store(0);
    bool called = false;
    {
        cf::runtime::CancelDeadline d(signal, 200ms, [&](int) { called = true; });
        std::this_thread::sleep_for(50ms);
        signal.store(SIGINT);
        std::this_thread::sleep_for(50ms);
    }  // the run returned within the grace time
    EXPECT_FALSE(called);
    signal.store(0);
    {
        cf::runtime::CancelDeadline d(signal, 10ms, [&](int) { called = true; });
        std::this_thread::sleep_for(100ms);
    }
    EXPECT_FALSE(called);
}
