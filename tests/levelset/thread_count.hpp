#pragma once
// Level sets computed under a given thread limit, and the check that two are the same voxel for
// voxel (the determinism tests of the object level set's two band methods).
#include "nodes/levelset/level_set.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

namespace cf::testing {

template <class Make>
auto with_threads(int threads, Make&& make) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return make();
}

inline void expect_same_grid(const LevelSet& a, const LevelSet& b) {
    const GridDifference d = compare_grids(a, b);
    EXPECT_EQ(d.active_only_in_a + d.active_only_in_b + d.sign_differs, 0u);
    EXPECT_EQ(d.max_abs_difference, 0.0);
}

}  // namespace cf::testing
