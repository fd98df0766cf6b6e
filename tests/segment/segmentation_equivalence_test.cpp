// The fragment search (ch. 6.3) on pieces and bit masks (issue 17) against the voxel-by-voxel
// search it replaced (tests/segment/voxel_segmentation.cpp): on procedural broken objects with
// through cracks, a crack deep inside (tile-aware search), slivers between close cracks (several
// pieces per leaf, fragments under the d-ring) and a thin curved tube, every option, both
// must give the same fragments in the same order, with bit-identical grids, volumes, centroids,
// boxes and voxel counts (tolerance zero: the new search must not change any result).
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/shape/torus.hpp"
#include "tests/levelset/test_meshes.hpp"
#include "tests/segment/cracked_sphere.hpp"
#include "tests/segment/tree_difference.hpp"
#include "tests/segment/voxel_segmentation.hpp"

#include <gtest/gtest.h>


namespace cf {
namespace {

void expect_same_measures(const Fragment& a, const Fragment& b) {
    EXPECT_EQ(a.volume, b.volume);
    EXPECT_EQ(a.centroid, b.centroid);
    EXPECT_EQ(a.bbox.min, b.bbox.min);
    EXPECT_EQ(a.bbox.max, b.bbox.max);
    EXPECT_EQ(a.active_voxels, b.active_voxels);
}

void expect_identical(const Fragments& expected, const Fragments& actual) {
    ASSERT_EQ(expected.fragments.size(), actual.fragments.size());
    for (std::size_t i = 0; i < expected.fragments.size(); ++i) {
        SCOPED_TRACE("fragment " + std::to_string(i));
        const Fragment &a = expected.fragments[i], &b = actual.fragments[i];
        expect_same_measures(a, b);
        EXPECT_EQ(testing::tree_difference(grid_of(a.grid), grid_of(b.grid)), "");
    }
}

// Both searches on `broken` with every option the node offers: s = r_f (the default), 0 and
// r_f / 2, with and without tiles. Returns the fragment counts (s = r_f, tiles; s = 0, no tiles).
std::pair<std::size_t, std::size_t> compare_all_options(const LevelSet& broken) {
    const double r_f = broken.voxel_size;
    std::pair<std::size_t, std::size_t> counts;
    for (const SegmentOptions opt : {SegmentOptions{-1, true}, SegmentOptions{0, true}, SegmentOptions{0.5 * r_f, true},
                                     SegmentOptions{-1, false}, SegmentOptions{0, false}}) {
        SCOPED_TRACE("s = " + std::to_string(opt.threshold) + " m, tiles " + std::to_string(opt.use_tiles));
        const Fragments expected = reference::find_fragments_voxelwise(broken, opt);
        const Fragments actual = find_fragments(broken, opt);
        expect_identical(expected, actual);
        if (opt.threshold < 0 && opt.use_tiles) counts.first = actual.fragments.size();
        if (opt.threshold == 0 && !opt.use_tiles) counts.second = actual.fragments.size();
    }
    return counts;
}

TEST(SegmentationEquivalence, CubeWithThroughCracksAndAPennyCrackInside) {
    // A 2 m cube at r_f = 2 cm: two through cracks (four pieces) and a penny crack deep inside
    // one piece, whose band touches only interior tiles.
    const double r_f = 0.02;
    const LevelSet cube = level_set_from_mesh(testmesh::box(Vec3::Constant(-1), Vec3::Constant(1)), r_f);
    const CrackLevelSets cracks{r_f,
                                3,
                                {planar_disk_crack(Vec3(0.026, 0, 0), Vec3(1, 0.1, 0.05), 2, r_f),
                                 planar_disk_crack(Vec3(0, -0.042, 0), Vec3(0.05, 1, 0.1), 2, r_f),
                                 planar_disk_crack(Vec3(0.48, 0.48, -0.48), Vec3(0.3, 0.2, 1), 0.07, r_f)}};
    const auto [with_tiles, without] = compare_all_options(broken_object(cube, cracks));
    EXPECT_EQ(with_tiles, 4u);  // the penny crack stays inside its piece
    EXPECT_GE(without, 5u);     // without tiles its band is a component of its own
}

TEST(SegmentationEquivalence, SphereCutByRandomCracksWithSlivers) {
    // A sphere of radius 0.4 m at r_f = 1 cm cut through by four random disk cracks and a bundle
    // of three parallel ones 2.5 r_f apart: slivers thinner than a leaf, so leaves hold several
    // pieces of different fragments and the d-ring of one fragment reaches into its neighbours.
    const testing::CrackedSphere s = testing::cracked_sphere(0.4, 0.01, 4, 0.2, 0.1, 17);
    const auto [with_tiles, without] = compare_all_options(broken_object(s.sphere, s.cracks));
    EXPECT_GE(with_tiles, 8u);  // 4 random cracks through a sphere and the slivers of the bundle
    EXPECT_GE(without, with_tiles);
}

TEST(SegmentationEquivalence, SpecksBelowTheMinimumVolumeAreMeasuredWithoutKeepingTheirGrids) {
    // SegmentOptions::min_volume frees a speck's grid as soon as it is measured (a run with a
    // thousand specks held them all at once). Everything else must be as without it: the same
    // fragments in the same order with the same measures, names and grids, and after
    // drop_small_fragments the same survivors and the same dropped count and volume, to the bit.
    const testing::CrackedSphere s = testing::cracked_sphere(0.4, 0.01, 4, 0.2, 0.1, 17);
    const LevelSet broken = broken_object(s.sphere, s.cracks);
    Fragments full = find_fragments(broken);
    const std::size_t n = full.fragments.size();
    ASSERT_GE(n, 4u);
    // A threshold between two distinct volumes near the middle: fragments on both sides of it.
    double min_volume = 0;
    for (std::size_t k = n / 2; k + 1 < n && min_volume == 0; ++k)
        if (full.fragments[k].volume > full.fragments[k + 1].volume)
            min_volume = 0.5 * (full.fragments[k].volume + full.fragments[k + 1].volume);
    ASSERT_GT(min_volume, 0);
    SegmentOptions lean_options;
    lean_options.min_volume = min_volume;
    Fragments lean = find_fragments(broken, lean_options);
    ASSERT_EQ(lean.fragments.size(), n);
    std::size_t specks = 0;
    for (std::size_t i = 0; i < n; ++i) {
        SCOPED_TRACE("fragment " + std::to_string(i));
        const Fragment &a = full.fragments[i], &b = lean.fragments[i];
        expect_same_measures(a, b);
        const bool speck = a.volume < min_volume;
        specks += speck;
        EXPECT_EQ(b.grid.empty(), speck);
        if (!speck && !b.grid.empty()) {
            EXPECT_EQ(grid_of(b.grid).getName(), grid_of(a.grid).getName());
            EXPECT_EQ(testing::tree_difference(grid_of(a.grid), grid_of(b.grid)), "");
        }
    }
    EXPECT_GE(specks, 1u);
    EXPECT_LT(specks, n);
    double removed_full = 0, removed_lean = 0;
    EXPECT_EQ(drop_small_fragments(full, min_volume, &removed_full), specks);
    EXPECT_EQ(drop_small_fragments(lean, min_volume, &removed_lean), specks);
    EXPECT_EQ(removed_full, removed_lean);
    expect_identical(full, lean);
}

TEST(SegmentationEquivalence, ThinTorusCutIntoArcs) {
    // A thin torus (tube radius 2.25 r_f, so few interior tiles and a curved band in every
    // leaf) cut by two cracks into two arcs.
    const double r_f = 0.004;
    TorusSpec t;
    t.major_radius = 0.1;
    t.minor_radius = 0.009;
    t.major_segments = 48;
    t.minor_segments = 12;
    const LevelSet ring = level_set_from_mesh(make_torus(t), r_f);
    const CrackLevelSets cracks{r_f,
                                3,
                                {planar_disk_crack(Vec3(0.1, 0, 0), Vec3(0, 1, 0.1), 0.03, r_f),
                                 planar_disk_crack(Vec3(-0.1, 0.01, 0), Vec3(0.2, 1, 0), 0.03, r_f)}};
    const auto [with_tiles, without] = compare_all_options(broken_object(ring, cracks));
    EXPECT_EQ(with_tiles, 2u);  // two arcs
    EXPECT_GE(without, 2u);
}

}  // namespace
}  // namespace cf
