#pragma once
// The bound on Ctrl-C and SIGTERM. Nodes stop at their next poll of the cancel token
// (graph/cancel_token.hpp), but a few third-party calls cannot be polled or stopped midway
// (OpenVDB's volumeToMesh of one fragment, signedFloodFill; docs/architecture.md). If the run has
// not wound down within a grace time of the signal, it is abandoned: pending temporaries are
// removed, a report is written from what had finished, and the process exits with 128 + the
// signal without waiting for that call, whose result a cancelled run discards anyway.
#include "graph/executor.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <thread>

namespace cf::runtime {

// Forwards to another observer and keeps what a report needs if the run is abandoned: per node
// the finished runs, their summed wall time and intervals, and which nodes are running now.
class NodeTally : public graph::ExecutionObserver {
public:
    explicit NodeTally(graph::ExecutionObserver* next) : next_(next) {}
    void node_started(const std::string& node, int iteration) override;
    void node_finished(const std::string& node, int iteration, double seconds) override;
    // A cancelled result in plan order (counts empty: only finished runs and times are known).
    graph::ExecutionResult partial_result(const graph::Plan& plan) const;
    std::vector<std::string> running() const;

private:
    graph::ExecutionObserver* next_;
    mutable std::mutex mutex_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::map<std::string, graph::NodeStats> finished_;
    std::map<std::pair<std::string, int>, double> running_;  // (node, iteration) -> start [s]
};

// Watches for a signal while a run executes; `abandon(signal)` is called on the watching thread if
// the run is still going `grace` after the signal (it is expected not to return: it exits).
class CancelDeadline {
public:
    CancelDeadline(const std::atomic<int>& signal, std::chrono::milliseconds grace, std::function<void(int)> abandon);
    ~CancelDeadline();  // the run has returned: stop watching
    CancelDeadline(const CancelDeadline&) = delete;
    CancelDeadline& operator=(const CancelDeadline&) = delete;

private:
    void watch();
    const std::atomic<int>& signal_;
    const std::chrono::milliseconds grace_;
    std::function<void(int)> abandon_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool done_ = false;
    std::thread thread_;
};

}  // namespace cf::runtime
