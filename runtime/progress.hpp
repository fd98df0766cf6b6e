#pragma once
// Progress display for `crackflow run`: on a terminal one status line with a bar per running
// stage, redrawn in place; otherwise plain lines when a stage starts and finishes.
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
};

}  // namespace cf::runtime
