// The surface mesher's cells (fragment_cells.hpp): the per-label search of the contact zone (a
// min-plus filter over leaf rows) against the per-voxel search over every ball offset it replaced,
// kept in FragmentCells as the reference. Tolerance zero: every cell must come out bit for bit the
// same, on pieces where up to eight fragments meet within a search ball (three through cracks
// crossing near one point, slivers between close parallel cracks) and for search balls that
// reach one and two leaves past the leaf searched.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/segment/fragment_cells.hpp"
#include "nodes/segment/fragments.hpp"
#include "tests/levelset/test_meshes.hpp"
#include "tests/segment/cracked_sphere.hpp"
#include "tests/segment/tree_difference.hpp"

#include <gtest/gtest.h>


namespace cf {
namespace {

// Every cell of `f` by both searches, for cell margins whose balls (margin + 2 voxels) stay within
// the neighbouring leaves (1, 2 voxels) and reach two leaves out (7.5: a 10-voxel ball).
void expect_same_cells(const Fragments& f) {
    for (const double margin : {1.0, 2.0, 7.5}) {
        SCOPED_TRACE("cell margin " + std::to_string(margin) + " voxels");
        const FragmentCells per_label(f, margin, NearestSearch::per_label);
        const FragmentCells per_voxel(f, margin, NearestSearch::per_voxel);
        for (std::size_t i = 0; i < f.fragments.size(); ++i) {
            SCOPED_TRACE("fragment " + std::to_string(i));
            const LevelSet expected = per_voxel.cell(i), actual = per_label.cell(i);
            EXPECT_EQ(testing::tree_difference(grid_of(expected), grid_of(actual)), "");
            // Not the object offset alone: the bisector of a gap shapes every cell.
            EXPECT_NE(testing::tree_difference(grid_of(expected), grid_of(f.object)), "");
        }
    }
}

TEST(FragmentCellsEquivalence, CubeCutIntoEighthsNearOneCorner) {
    // Three through cracks that cross near one point: eight fragments meet there, more than the
    // four nearest a zone voxel keeps, so the search must choose among them as the old one did.
    const double r_f = 0.02;
    const LevelSet cube = level_set_from_mesh(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), r_f);
    const CrackLevelSets cracks{r_f,
                                3,
                                {planar_disk_crack(Vec3(0.013, 0, 0), Vec3(1, 0.1, 0.05), 2, r_f),
                                 planar_disk_crack(Vec3(0, -0.021, 0), Vec3(0.05, 1, 0.1), 2, r_f),
                                 planar_disk_crack(Vec3(0, 0, 0.007), Vec3(0.1, -0.07, 1), 2, r_f)}};
    Fragments f = find_fragments(broken_object(cube, cracks));
    f.object = cube;
    ASSERT_EQ(f.fragments.size(), 8u);
    expect_same_cells(f);
}

TEST(FragmentCellsEquivalence, SphereWithRandomCracksAndSlivers) {
    // A sphere of radius 0.25 m at r_f = 1 cm: three random through cracks and three parallel
    // ones 2.5 r_f apart, whose slivers put several fragments into one leaf.
    const testing::CrackedSphere s = testing::cracked_sphere(0.25, 0.01, 3, 0.1, 0.05, 5);
    Fragments f = find_fragments(broken_object(s.sphere, s.cracks));
    f.object = s.sphere;
    ASSERT_GE(f.fragments.size(), 8u);
    expect_same_cells(f);
}

}  // namespace
}  // namespace cf
