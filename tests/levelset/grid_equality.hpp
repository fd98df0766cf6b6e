#pragma once
// Two OpenVDB level sets compared bit for bit: every active voxel of one is active in the other
// with the same float, and every tile of the reference (interior and exterior) holds the same value
// in the other. For the tests that a rewritten OpenVDB call reproduces the tool it replaces.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <cstddef>

namespace cf::testing {

inline void expect_bit_identical(const openvdb::FloatGrid& ours, const openvdb::FloatGrid& ref) {
    EXPECT_EQ(ours.activeVoxelCount(), ref.activeVoxelCount());
    EXPECT_EQ(ours.tree().leafCount(), ref.tree().leafCount());
    EXPECT_EQ(ours.background(), ref.background());
    std::size_t differing = 0;
    auto acc = ref.getConstAccessor();
    for (auto it = ours.cbeginValueOn(); it; ++it)
        if (!acc.isValueOn(it.getCoord()) || acc.getValue(it.getCoord()) != *it) ++differing;
    EXPECT_EQ(differing, 0u);
    std::size_t tiles = 0, tiles_differing = 0;
    for (auto it = ref.cbeginValueAll(); it; ++it) {
        if (it.isVoxelValue()) continue;
        ++tiles;
        if (ours.tree().getValue(it.getCoord()) != *it) ++tiles_differing;
    }
    EXPECT_GT(tiles, 0u);
    EXPECT_EQ(tiles_differing, 0u);
}

}  // namespace cf::testing
