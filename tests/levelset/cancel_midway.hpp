#pragma once
// Runs `work` with a cancel token whose flag another thread raises after `seconds`; true if the
// work ended in cf::Cancelled, false if it finished first (the caller then checks its result).
// For the tests that a polled algorithm stops cleanly wherever the flag lands.
#include "graph/cancel_token.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

namespace cf::testing {

inline bool cancelled_midway(double seconds, const std::function<void(const CancelToken&)>& work) {
    std::atomic<bool> flag{false};
    std::thread raiser([&] {
        std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
        flag.store(true);
    });
    bool threw = false;
    try {
        work(CancelToken(&flag));
    } catch (const Cancelled&) {
        threw = true;
    }
    raiser.join();
    return threw;
}

}  // namespace cf::testing
