// Crack recording (ch. 6.2) on degenerate input, one scope per case: what the recorder does with
// nothing to record, with triangles of zero area, with a front without markers and with a strip
// that lies inside the band an earlier strip already recorded. Values are checked at voxel
// positions, where the trilinear sample is the stored value: the thickened distance d - r_f sqrt(3)/2.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace cf {
namespace {

constexpr double kRf = 0.02;
const double kThick = crack_half_thickness(kRf);

// Sampled (as the grids store floats) at voxel positions, exactly the distance minus the thickness.
constexpr double kFloat = 1e-7;

TEST(CrackRecording, EdgeCases) {
    {
        SCOPED_TRACE("an empty triangle list records nothing");
        CrackRecorder rec(kRf);
        rec.add_crack();
        EXPECT_EQ(rec.add_triangles(0, {}), 0u);
        EXPECT_EQ(active_voxel_count(rec.snapshot().cracks[0]), 0u);
    }
    {
        SCOPED_TRACE("a triangle of three equal points is that point: a ball of radius r_f sqrt(3)/2");
        CrackRecorder rec(kRf);
        rec.add_crack();
        const Vec3 p = kRf * Vec3(3, -2, 5);  // on a voxel
        EXPECT_GT(rec.add_triangles(0, {Triangle3{p, p, p}}), 0u);
        const LevelSet g = rec.snapshot().cracks[0];
        for (int k = 0; k <= 3; ++k)
            for (const Vec3& dir : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)})
                EXPECT_NEAR(sample(g, p + k * kRf * dir), k * kRf - kThick, kFloat) << k;
        EXPECT_NEAR(sample(g, p + kRf * Vec3(1, 1, 1)), std::sqrt(3.0) * kRf - kThick, kFloat);
    }
    {
        SCOPED_TRACE("a triangle with a collapsed edge is its segment");
        CrackRecorder rec(kRf);
        rec.add_crack();
        const Vec3 a = kRf * Vec3(-4, 0, 0), b = kRf * Vec3(4, 0, 0);
        for (const Triangle3& t : {Triangle3{a, a, b}, Triangle3{a, b, b}, Triangle3{b, a, a}}) {
            CrackRecorder one(kRf);
            one.add_crack();
            EXPECT_GT(one.add_triangles(0, {t}), 0u);
            const LevelSet g = one.snapshot().cracks[0];
            for (int i = -6; i <= 6; ++i)
                for (int k = 0; k <= 3; ++k) {
                    const Vec3 x = kRf * Vec3(i, 0, k);
                    const double d = (x - Vec3(std::clamp(x.x(), a.x(), b.x()), 0, 0)).norm();
                    if (d < 3 * kRf) {
                        EXPECT_NEAR(sample(g, x), d - kThick, kFloat) << i << " " << k;
                    }
                }
        }
    }
    {
        SCOPED_TRACE("a front without markers sweeps nothing and is tested for nothing");
        CrackRecorder rec(kRf);
        rec.add_crack();
        std::size_t written = 99;
        const auto tests = rec.record_substep({FrontMotion{}}, nullptr, &written);
        ASSERT_EQ(tests.size(), 1u);
        EXPECT_TRUE(tests[0].empty());
        EXPECT_EQ(written, 0u);
        EXPECT_EQ(active_voxel_count(rec.snapshot().cracks[0]), 0u);
    }
    {
        SCOPED_TRACE("a strip inside an already-recorded band changes no value");
        CrackRecorder rec(kRf);
        rec.add_crack();
        const Vec3 a(-0.1, -0.1, 0), b(0.1, -0.1, 0), c(0.1, 0.1, 0), d(-0.1, 0.1, 0);
        const std::vector<Triangle3> sheet = {{a, b, c}, {a, c, d}};
        const std::size_t first = rec.add_triangles(0, sheet);
        const LevelSet before = rec.snapshot().cracks[0];
        EXPECT_EQ(first, active_voxel_count(before));  // on an empty grid: the band's voxels
        // The same sheet again, and a smaller strip inside it: every voxel already holds a
        // distance no larger than theirs, so no value changes and the band does not grow. (The
        // returned count may include voxels written again with their own value: the start of
        // each voxel's search is decoded from the stored float, the new distance is a double.)
        EXPECT_LE(rec.add_triangles(0, sheet), first);
        const Vec3 e(-0.05, -0.05, 0), f(0.05, -0.05, 0), h(0.05, 0.05, 0);
        EXPECT_LE(rec.add_triangles(0, {{e, f, h}}), first);
        const LevelSet after = rec.snapshot().cracks[0];
        EXPECT_EQ(active_voxel_count(after), active_voxel_count(before));
        for (double x = -0.15; x <= 0.15; x += 0.013)
            for (double z = -0.07; z <= 0.07; z += 0.011) EXPECT_EQ(sample(after, Vec3(x, 0.03, z)), sample(before, Vec3(x, 0.03, z)));
    }
}

}  // namespace
}  // namespace cf
