#pragma once
// Progress display for `crackflow run`: on a terminal one status line with a bar per running
// stage, redrawn in place; otherwise plain lines when a stage starts and finishes. Lines about
// loop iterations after the first are rate-limited to one a second.
#include "graph/executor.hpp"

#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>

namespace cf::runtime {

class ProgressDisplay : public graph::ExecutionObserver {
public:
    explicit ProgressDisplay(std::FILE* out, bool interactive);
    void node_started(const std::string& node, int iteration) override;
    void node_finished(const std::string& node, int iteration, double seconds) override;
    void progress(const std::string& node, double fraction);
    void finish();  // clears the status line

private:
    void redraw();
    std::string label(const std::string& node, int iteration) const;
    std::FILE* out_;
    bool interactive_;
    std::mutex mutex_;
    std::map<std::string, double> running_;  // label -> fraction
    std::map<std::string, std::string> label_of_;  // node -> current label
    std::map<std::string, int> last_quarter_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_draw_{};
    // Lines about loop iterations after the first are printed at most once a second (a loop of a
    // million short iterations printed four lines each); the ones left out are counted and said.
    bool loop_line_shown(int iteration);
    std::string skipped_note();
    std::chrono::steady_clock::time_point last_loop_line_{};
    long long skipped_lines_ = 0;
};

}  // namespace cf::runtime
