#pragma once
// Cancellation for plain C++ algorithms, independent of the graph: an algorithm that may run
// for more than about 0.1 s takes a CancelToken and calls poll() in its loops, so Ctrl-C or
// SIGTERM stops a run within a fraction of a second wherever it is. poll() is two relaxed atomic
// loads: cheap enough for every element of an assembly loop. A default token never cancels.
//
// Algorithms take the token as a last parameter defaulting to CancelToken::current(): the token of
// the node running on the calling thread (the executor opens a CancelScope around every node), so
// node adapters and the algorithms they call in turn need not pass it along, and tests or other
// callers may pass their own. Read it on the calling thread and capture it by value into parallel
// bodies (a worker thread's current token is that of whatever node it is nested in, or none).
#include <atomic>
#include <stdexcept>

namespace cf {

// Thrown by poll() (and by graph nodes) when the run was cancelled: Ctrl-C, SIGTERM, or a failure
// elsewhere in the graph. The executor treats it as a stop, not as this node's error.
struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("cancelled") {}
};

class CancelToken {
public:
    CancelToken() = default;
    explicit CancelToken(const std::atomic<bool>* flag, const std::atomic<bool>* outer = nullptr)
        : flag_(flag), outer_(outer) {}
    bool requested() const {
        return (flag_ && flag_->load(std::memory_order_relaxed)) || (outer_ && outer_->load(std::memory_order_relaxed));
    }
    void poll() const {
        if (requested()) throw Cancelled();
    }
    // The token of the node running on this thread (none outside a run).
    static CancelToken current() { return slot(); }

private:
    friend class CancelScope;
    static CancelToken& slot() {
        static thread_local CancelToken token;
        return token;
    }
    const std::atomic<bool>* flag_ = nullptr;
    const std::atomic<bool>* outer_ = nullptr;
};

// Makes `token` this thread's current token until the scope ends (then the previous one again).
class CancelScope {
public:
    explicit CancelScope(CancelToken token) : previous_(CancelToken::slot()) { CancelToken::slot() = token; }
    ~CancelScope() { CancelToken::slot() = previous_; }
    CancelScope(const CancelScope&) = delete;
    CancelScope& operator=(const CancelScope&) = delete;

private:
    CancelToken previous_;
};

}  // namespace cf
