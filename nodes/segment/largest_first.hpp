#pragma once
// Runs body(i) for i in [0, n) on the arena's threads, largest first by size(i), each free thread
// taking the next: a split index range can hand the two largest items (the halves of a cut object,
// often neighbours in index order) to one thread in turn while the other finishes the small ones.
// Ties keep index order. Once a body throws, no thread starts another item; the exception leaves
// this call after the others have finished theirs. Only the order of the work differs from a plain
// loop, so callers whose items write their own results get the same output whatever the thread count.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

namespace cf {

template <class Size, class Body>
void for_each_largest_first(std::size_t n, Size size, Body body) {
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return size(a) > size(b); });
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    const std::size_t workers = std::min<std::size_t>(n, std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
    tbb::parallel_for(std::size_t(0), workers, [&](std::size_t) {
        for (std::size_t k = next++; k < n && !failed; k = next++) try {
                body(order[k]);
            } catch (...) {
                failed = true;
                throw;
            }
    });
}

}  // namespace cf
