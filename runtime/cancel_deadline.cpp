#include "runtime/cancel_deadline.hpp"

namespace cf::runtime {

void NodeTally::node_started(const std::string& node, int iteration) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        running_[{node, iteration}] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }
    if (next_) next_->node_started(node, iteration);
}

void NodeTally::node_finished(const std::string& node, int iteration, double seconds) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const double t1 = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        running_.erase({node, iteration});
        graph::NodeStats& s = finished_[node];
        s.runs++;
        s.wall_seconds += seconds;
        if (s.runs <= graph::kMaxRecordedRuns) s.intervals.emplace_back(t1 - seconds, t1);
    }
    if (next_) next_->node_finished(node, iteration, seconds);
}

graph::ExecutionResult NodeTally::partial_result(const graph::Plan& plan) const {
    std::lock_guard<std::mutex> lock(mutex_);
    graph::ExecutionResult r;
    r.cancelled = true;
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    for (const graph::PlanNode& p : plan.nodes) {
        graph::NodeStats s;
        // A loop's "started" events are its iterations; it has no "finished" ones.
        if (auto it = finished_.find(p.name); it != finished_.end() && !p.is_loop()) s = it->second;
        s.name = p.name;
        s.type = p.is_loop() ? "loop" : p.type->name();
        r.stats.push_back(std::move(s));
    }
    return r;
}

std::vector<std::string> NodeTally::running() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::set<std::string> names;
    for (const auto& [key, t0] : running_) names.insert(key.first);
    return {names.begin(), names.end()};
}

CancelDeadline::CancelDeadline(const std::atomic<int>& signal, std::chrono::milliseconds grace,
                               std::function<void(int)> abandon)
    : signal_(signal), grace_(grace), abandon_(std::move(abandon)) {
    // A timer, not a worker: it computes nothing and only sleeps until the run returns (compute
    // runs on oneTBB's threads).
    thread_ = std::thread([this] { watch(); });
}

CancelDeadline::~CancelDeadline() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        done_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void CancelDeadline::watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    // A signal handler cannot notify a condition variable, so the signal is read every 20 ms.
    while (!done_ && signal_.load() == 0) wake_.wait_for(lock, std::chrono::milliseconds(20));
    if (done_) return;
    const int sig = signal_.load();
    if (wake_.wait_for(lock, grace_, [this] { return done_; })) return;
    // Still holding the lock: the run cannot return and write its own report meanwhile.
    abandon_(sig);
}

}  // namespace cf::runtime
