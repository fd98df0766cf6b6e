// Fragment segmentation (ch. 6.3) is parallel (oneTBB); its result must not depend on the
// thread count: the same fragments in the same order with bit-identical grids and measures.
// This test compares the trees voxel by voxel, so it includes OpenVDB (one slow TU).
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/segment/fragments.hpp"
#include "tests/levelset/test_meshes.hpp"
#include "tests/segment/tree_difference.hpp"

#include <gtest/gtest.h>

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>


namespace cf {
namespace {

using testing::tree_difference;

TEST(SegmentationThreads, OneAndTwoThreadsGiveBitIdenticalFragments) {
    // A 1 m cube at r_f = 1 cm cut by two through cracks (4 pieces), with a penny crack deep
    // inside one piece: the leaves of its band (x, y in [0.16, 0.32) m, z in [-0.32, -0.16) m)
    // touch no other leaf, only interior tiles, so only the tile-aware search keeps it inside
    // that piece (ch. 6.3).
    const double r_f = 0.01;
    const LevelSet cube = level_set_from_mesh(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), r_f);
    const Vec3 penny(0.24, 0.24, -0.24);
    const CrackLevelSets cracks{r_f,
                                3,
                                {planar_disk_crack(Vec3(0.013, 0, 0), Vec3(1, 0.1, 0.05), 1, r_f),
                                 planar_disk_crack(Vec3(0, -0.021, 0), Vec3(0.05, 1, 0.1), 1, r_f),
                                 planar_disk_crack(penny, Vec3(0.3, 0.2, 1), 0.035, r_f)}};
    const LevelSet broken = broken_object(cube, cracks);
    auto run = [&](int threads, const SegmentOptions& opt) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        return find_fragments(broken, opt);
    };
    for (const SegmentOptions opt : {SegmentOptions{-1, true}, SegmentOptions{0, true}, SegmentOptions{0.5 * r_f, false}}) {
        SCOPED_TRACE("s = " + std::to_string(opt.threshold) + ", tiles " + std::to_string(opt.use_tiles));
        const Fragments one = run(1, opt), two = run(2, opt);
        ASSERT_EQ(one.fragments.size(), two.fragments.size());
        if (opt.use_tiles) {
            // Four pieces; the penny crack stays inside the (+x, +y) piece as a gap.
            ASSERT_EQ(one.fragments.size(), 4u);
            int holder = -1;
            for (std::size_t i = 0; i < one.fragments.size(); ++i)
                if (sample(one.fragments[i].grid, penny + Vec3(0.05, 0, 0)) < 0) holder = int(i);  // beside the penny
            ASSERT_GE(holder, 0);
            EXPECT_GT(sample(one.fragments[std::size_t(holder)].grid, penny), 0);
        } else {
            // Without tiles the penny crack's band is cut off from the surface bands: a fifth
            // component.
            EXPECT_EQ(one.fragments.size(), 5u);
        }
        for (std::size_t i = 0; i < one.fragments.size(); ++i) {
            const Fragment &a = one.fragments[i], &b = two.fragments[i];
            EXPECT_EQ(a.volume, b.volume) << "fragment " << i;
            EXPECT_EQ(a.centroid, b.centroid) << "fragment " << i;
            EXPECT_EQ(a.bbox.min, b.bbox.min) << "fragment " << i;
            EXPECT_EQ(a.bbox.max, b.bbox.max) << "fragment " << i;
            EXPECT_EQ(a.active_voxels, b.active_voxels) << "fragment " << i;
            EXPECT_EQ(tree_difference(grid_of(a.grid), grid_of(b.grid)), "") << "fragment " << i;
        }
    }
}

}  // namespace
}  // namespace cf
