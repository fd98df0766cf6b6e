// Level-set CSG and pruning with cancellation polls (issue 16: Ctrl-C within 0.5 s inside the
// segmentation's CSG of the broken object, eq. (6.1), and the nested shells' CSG): uncancelled,
// the trees are OpenVDB's csgDifference / csgUnion / pruneLevelSet bit for bit; cancelled, the
// call throws Cancelled instead of returning a half-combined grid.
#include "nodes/levelset/level_set_grid.hpp"
#include "tests/levelset/cancel_midway.hpp"
#include "tests/levelset/grid_equality.hpp"

#include <gtest/gtest.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <thread>

namespace cf {
namespace {

using openvdb::FloatGrid;

FloatGrid::Ptr sphere(float radius, const openvdb::Vec3f& centre, float voxel) {
    return openvdb::tools::createLevelSetSphere<FloatGrid>(radius, centre, voxel, 3.0f);
}

// A crack-like sheet: the slab |n . x - c| <= 1.5 voxels, limited to the sphere of `radius`
// (as levelset.crack_planar builds a disc), in the same band width.
FloatGrid::Ptr slab(float radius, float voxel) {
    FloatGrid::Ptr disc = sphere(radius, {0.05f, 0.f, 0.f}, voxel);
    FloatGrid::Ptr g = FloatGrid::create(3.0f * voxel);
    g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    const openvdb::Vec3d n = openvdb::Vec3d(1, 0.3, 0.2).unit();
    auto acc = g->getAccessor();
    const int r = int(radius / voxel) + 4;
    for (int i = -r; i <= r; ++i)
        for (int j = -r; j <= r; ++j)
            for (int k = -r; k <= r; ++k) {
                const openvdb::Vec3d x = openvdb::Vec3d(i, j, k) * voxel;
                const double d = std::abs(n.dot(x - openvdb::Vec3d(0.05, 0, 0))) - 1.5 * voxel;
                const double v = std::max(d, double(disc->tree().getValue(openvdb::Coord(i, j, k))));
                if (std::abs(v) < 3.0 * voxel) acc.setValue(openvdb::Coord(i, j, k), float(v));
            }
    openvdb::tools::signedFloodFill(g->tree());
    return g;
}

TEST(PolledCsg, DifferenceAndUnionEqualOpenVdbsBitForBit) {
    ensure_openvdb_initialized();
    const std::atomic<bool> never{false};
    const CancelToken cancel(&never);
    const float voxel = 0.01f;
    const FloatGrid::Ptr object = sphere(0.5f, {0, 0, 0}, voxel);
    struct Case {
        const char* what;
        FloatGrid::Ptr b;
        bool difference;
    };
    const Case cases[] = {
        {"object minus a crack sheet through it", slab(0.45f, voxel), true},
        {"object minus an off-centre sphere (a bite and a cavity wall)", sphere(0.3f, {0.35f, 0.1f, 0}, voxel), true},
        {"object minus a sphere inside it (a cavity)", sphere(0.2f, {-0.1f, 0, 0}, voxel), true},
        {"object united with an overlapping sphere", sphere(0.3f, {0.55f, 0, 0.1f}, voxel), false},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        FloatGrid::Ptr ref = object->deepCopy(), ours = object->deepCopy();
        FloatGrid::Ptr b_ref = c.b->deepCopy(), b_ours = c.b->deepCopy();
        if (c.difference) {
            openvdb::tools::csgDifference(*ref, *b_ref);
            csg_difference_polled(*ours, *b_ours, cancel);
        } else {
            openvdb::tools::csgUnion(*ref, *b_ref);
            csg_union_polled(*ours, *b_ours, cancel);
        }
        testing::expect_bit_identical(*ours, *ref);
        // And the values are the CSG's, eq. (6.1): max(a, -b) / min(a, b) wherever the result's band is.
        auto a = object->getConstAccessor();
        auto b = c.b->getConstAccessor();
        std::size_t checked = 0, wrong = 0;
        for (auto it = ours->cbeginValueOn(); it; ++it) {
            const float va = a.getValue(it.getCoord()), vb = b.getValue(it.getCoord());
            const float want = c.difference ? std::max(va, -vb) : std::min(va, vb);
            ++checked;
            if (*it != want) ++wrong;
        }
        EXPECT_GT(checked, 10000u);
        EXPECT_EQ(wrong, 0u);
    }
}

TEST(PolledCsg, PruneEqualsPruneLevelSet) {
    ensure_openvdb_initialized();
    const std::atomic<bool> never{false};
    FloatGrid::Ptr g = sphere(0.5f, {0, 0, 0}, 0.01f);
    // Switch off half the band so that whole leaves become prunable.
    for (auto it = g->beginValueOn(); it; ++it)
        if (it.getCoord().x() > 3) it.setValueOff();
    FloatGrid::Ptr ref = g->deepCopy();
    openvdb::tools::pruneLevelSet(ref->tree());
    prune_level_set_polled(g->tree(), CancelToken(&never));
    EXPECT_LT(ref->tree().leafCount(), sphere(0.5f, {0, 0, 0}, 0.01f)->tree().leafCount());
    testing::expect_bit_identical(*g, *ref);
}

TEST(PolledCsg, DeepCopyEqualsDeepCopy) {
    ensure_openvdb_initialized();
    const std::atomic<bool> never{false};
    // The difference leaves inside tiles, outside tiles and leaves at several levels.
    FloatGrid::Ptr g = sphere(0.5f, {0, 0, 0}, 0.005f);
    FloatGrid::Ptr cavity = sphere(0.2f, {-0.1f, 0, 0}, 0.005f);
    openvdb::tools::csgDifference(*g, *cavity);
    g->setName("object");
    // Tiles at every level: 8^3 tiles in a lower node, 128^3 ones in an upper node and a 4096^3 one
    // in the root, active and inactive, and an inactive voxel with a value of its own.
    g->tree().addTile(1, openvdb::Coord(640, 0, 0), -0.25f, true);
    g->tree().addTile(1, openvdb::Coord(640, 8, 0), 0.25f, false);
    g->tree().addTile(2, openvdb::Coord(8192, 0, 0), -0.5f, true);
    g->tree().addTile(2, openvdb::Coord(8192, 128, 0), 0.5f, false);
    g->tree().addTile(3, openvdb::Coord(-16384, 0, 0), -1.0f, true);
    g->tree().setValueOff(openvdb::Coord(0, 0, 100), 0.125f);
    const FloatGrid::Ptr ref = g->deepCopy();
    const FloatGrid::Ptr ours = deep_copy_polled(*g, CancelToken(&never));
    testing::expect_bit_identical(*ours, *ref);
    // Every value, voxel or tile, on or off, in the same order, at the same level.
    std::size_t values = 0, differing = 0;
    auto a = ours->cbeginValueAll();
    for (auto b = ref->cbeginValueAll(); b; ++b, ++a, ++values)
        if (!a || a.getCoord() != b.getCoord() || a.getDepth() != b.getDepth() || *a != *b || a.isValueOn() != b.isValueOn())
            ++differing;
    EXPECT_FALSE(bool(a)) << "more values than deepCopy's";
    EXPECT_EQ(differing, 0u) << "of " << values;
    EXPECT_EQ(ours->tree().nodeCount(), ref->tree().nodeCount());
    EXPECT_EQ(ours->tree().nonLeafCount(), ref->tree().nonLeafCount());
    EXPECT_EQ(ours->tree().activeTileCount(), ref->tree().activeTileCount());
    EXPECT_EQ(ours->getName(), "object");
    EXPECT_EQ(ours->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(ours->transform(), ref->transform());
    EXPECT_NE(&ours->transform(), &g->transform());  // its own, as deepCopy's
    std::atomic<bool> raised{true};
    EXPECT_THROW(deep_copy_polled(*g, CancelToken(&raised)), Cancelled);
}

// Raised from another thread at several moments of a large difference, the flag ends the call in
// Cancelled, or, if the call finished first, in the whole result (also run under ASan/UBSan).
TEST(PolledCsg, ACancelledDifferenceThrowsCancelled) {
    ensure_openvdb_initialized();
    const float voxel = 0.002f;
    const FloatGrid::Ptr object = sphere(0.5f, {0, 0, 0}, voxel);
    const FloatGrid::Ptr bite = sphere(0.4f, {0.3f, 0.1f, 0}, voxel);
    std::atomic<bool> raised{true};
    {
        FloatGrid::Ptr a = object->deepCopy(), b = bite->deepCopy();
        EXPECT_THROW(csg_difference_polled(*a, *b, CancelToken(&raised)), Cancelled);
    }
    std::atomic<bool> lowered{false};
    FloatGrid::Ptr whole = object->deepCopy();
    {
        FloatGrid::Ptr b = bite->deepCopy();
        const auto t0 = std::chrono::steady_clock::now();
        csg_difference_polled(*whole, *b, CancelToken(&lowered));
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("uncancelled difference: %.3f s, %zu active voxels\n", seconds, std::size_t(whole->activeVoxelCount()));
        for (double f : {0.05, 0.2, 0.4, 0.6, 0.8}) {
            FloatGrid::Ptr a = object->deepCopy(), c = bite->deepCopy();
            const bool threw = testing::cancelled_midway(f * seconds, [&](const CancelToken& token) {
                csg_difference_polled(*a, *c, token);
                testing::expect_bit_identical(*a, *whole);  // finished first: the whole result
            });
            std::printf("flag at %.0f %% of the difference: %s\n", 100 * f, threw ? "cancelled" : "finished first");
        }
    }
}

}  // namespace
}  // namespace cf
