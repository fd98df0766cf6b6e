// The object level set's mesh-to-volume conversion with a cancel token that is polled at every
// triangle-corner read (issue 16: Ctrl-C within 0.5 s inside the conversion of an imported mesh):
// uncancelled, its grid is OpenVDB's meshToLevelSet's bit for bit; cancelled, it stops with
// Cancelled instead of returning an incomplete grid.
#include "nodes/levelset/level_set_grid.hpp"
#include "nodes/shape/notched_bar.hpp"
#include "nodes/shape/torus.hpp"
#include "tests/levelset/cancel_midway.hpp"
#include "tests/levelset/grid_equality.hpp"
#include "tests/levelset/thread_count.hpp"

#include <gtest/gtest.h>
#include <openvdb/tools/MeshToVolume.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

namespace cf {
namespace {

// OpenVDB's own conversion, called as the object level set called it before issue 16.
openvdb::FloatGrid::Ptr reference_grid(const SurfaceMesh& mesh, double r_f, double half_width) {
    std::vector<openvdb::Vec3s> points;
    for (const Vec3& v : mesh.vertices) points.emplace_back(float(v.x()), float(v.y()), float(v.z()));
    std::vector<openvdb::Vec3I> tris;
    for (const Tri& t : mesh.triangles) tris.emplace_back(t[0], t[1], t[2]);
    auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, tris, float(half_width));
}

void expect_bit_identical_to_mesh_to_level_set(const SurfaceMesh& mesh, double r_f, const char* what) {
    SCOPED_TRACE(what);
    ensure_openvdb_initialized();
    const LevelSet ls = level_set_from_mesh(mesh, r_f);
    const openvdb::FloatGrid& ours = grid_of(ls);
    const openvdb::FloatGrid::Ptr ref = reference_grid(mesh, r_f, ls.half_width);
    EXPECT_GT(ref->activeVoxelCount(), 10000u);
    testing::expect_bit_identical(ours, *ref);
}

TEST(CancellableConversion, EqualsMeshToLevelSetBitForBit) {
    TorusSpec torus;
    expect_bit_identical_to_mesh_to_level_set(make_torus(torus), 6e-4, "torus");
    // Sharp concave notch: the band expansion's own errors there must be reproduced too.
    expect_bit_identical_to_mesh_to_level_set(make_notched_bar(NotchedBarSpec{}), 2.1e-3, "notched bar");
}

TEST(CancellableConversion, SameGridForOneAndTwoThreads) {
    const SurfaceMesh m = make_notched_bar(NotchedBarSpec{});
    auto make = [&] { return level_set_from_mesh(m, 2.1e-3); };
    testing::expect_same_grid(testing::with_threads(1, make), testing::with_threads(2, make));
}

// A run cancelled before or during the conversion ends in Cancelled, never in a grid. Raised from
// another thread at several moments, the flag lands in the voxelisation, the sign classification,
// the band expansion or the renormalisation, where cancelled parallel loops leave partial trees
// behind: the conversion must still stop cleanly (this test is also run under ASan/UBSan).
TEST(CancellableConversion, ACancelledRunThrowsCancelledWhereverTheFlagIsRaised) {
    TorusSpec spec;
    const SurfaceMesh m = make_torus(spec);
    const double r_f = 2.5e-4;
    std::atomic<bool> raised{true};
    EXPECT_THROW(level_set_from_mesh(m, r_f, 3, 2e8, CancelToken(&raised)), Cancelled);

    const auto t0 = std::chrono::steady_clock::now();
    std::atomic<bool> lowered{false};
    const LevelSet whole = level_set_from_mesh(m, r_f, 3, 2e8, CancelToken(&lowered));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("uncancelled conversion: %.3f s\n", seconds);
    for (double f : {0.02, 0.1, 0.25, 0.4, 0.55, 0.7, 0.85}) {
        const bool threw = testing::cancelled_midway(f * seconds, [&](const CancelToken& token) {
            const LevelSet ls = level_set_from_mesh(m, r_f, 3, 2e8, token);
            // Finished before the flag: then it must be the whole grid.
            const GridDifference d = compare_grids(ls, whole);
            EXPECT_EQ(d.active_only_in_a + d.active_only_in_b + d.sign_differs, 0u) << f;
            EXPECT_EQ(d.max_abs_difference, 0.0) << f;
        });
        std::printf("flag at %.0f %% of the conversion: %s\n", 100 * f, threw ? "cancelled" : "finished first");
    }
}

}  // namespace
}  // namespace cf
