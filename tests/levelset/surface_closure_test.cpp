// surface_closure_triangles (nodes/levelset/crack_grids.hpp): the fan between a marker that stopped
// at one face of a box's edge and a neighbour that left through the other face cuts across the
// corner; the closure continues the crack's plane from that chord to the surface, so the corner
// voxels are cut, and adds nothing where no surface is within reach.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

constexpr double kRf = 0.02;  // [m]; the box is [-0.5, 0.5]^3

// In the plane z = 0: A stopped 0.5 r_f inside the face x = -0.5; B and C cross the face y = 0.5.
FrontMotion corner_motion(const Vec3& shift = Vec3::Zero()) {
    FrontMotion m;
    m.closed = false;
    m.p0 = {Vec3(-0.49, 0.30, 0), Vec3(-0.38, 0.46, 0), Vec3(-0.30, 0.46, 0)};
    m.p1 = {Vec3(-0.49, 0.30, 0), Vec3(-0.39, 0.52, 0), Vec3(-0.30, 0.52, 0)};
    for (Vec3& p : m.p0) p += shift;
    for (Vec3& p : m.p1) p += shift;
    return m;
}

LevelSet record(const std::vector<Triangle3>& tris) {
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_triangles(0, tris);
    return rec.snapshot().cracks[0];
}

TEST(SurfaceClosure, CutsTheCornerBetweenAFanAndTheTwoFaces) {
    const LevelSet box = level_set_from_mesh(testmesh::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)), kRf);
    const FrontMotion m = corner_motion();
    const std::vector<Triangle3> strips = strip_triangles(m), closure = surface_closure_triangles(m, box);
    ASSERT_FALSE(closure.empty());
    std::vector<Triangle3> both = strips;
    both.insert(both.end(), closure.begin(), closure.end());
    const LevelSet without = record(strips), with = record(both);
    // Q: 2 r_f inside both faces (inside for segmentation: Phi_o < -r_f) and about 2 r_f outside the
    // fan's chord. Segmentation cuts a voxel whose crack value is at most s = r_f.
    const Vec3 q(-0.46, 0.46, 0);
    EXPECT_NEAR(sample(box, q), -2 * kRf, 0.05 * kRf);
    EXPECT_GT(sample(without, q), kRf);  // a bridge voxel without the closure
    EXPECT_LE(sample(with, q), 0.0);     // on the closed plane
    // The closure stays in the fan's plane and at the corner: off the plane, and inside the fan, the
    // values are those of the strips alone.
    for (const Vec3& p : {Vec3(-0.46, 0.46, 4 * kRf), Vec3(-0.34, 0.48, 0), Vec3(-0.30, 0.30, 0)})
        EXPECT_EQ(sample(with, p), sample(without, p)) << p.transpose();
    // Every closure triangle lies in the plane z = 0 and within half the chord of it.
    for (const Triangle3& t : closure)
        for (const Vec3& p : t) {
            EXPECT_NEAR(p.z(), 0.0, 1e-12);
            EXPECT_LT(p.x(), -0.38);
        }
}

TEST(SurfaceClosure, NothingWhereTheFanIsFarFromTheSurface) {
    const LevelSet box = level_set_from_mesh(testmesh::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)), kRf);
    // The same fan 0.3 m inwards: both chord ends deep inside.
    EXPECT_TRUE(surface_closure_triangles(corner_motion(Vec3(0.3, -0.3, 0)), box).empty());
    // Both markers moving, or both stopped: no fan.
    FrontMotion moving = corner_motion();
    moving.p1[0] += Vec3(0, 0.01, 0);
    FrontMotion stopped = corner_motion();
    stopped.p1 = stopped.p0;
    const std::vector<Triangle3> a = surface_closure_triangles(moving, box), b = surface_closure_triangles(stopped, box);
    EXPECT_TRUE(b.empty());
    // moving: the pair (A, B) is no longer a fan; (B, C) never was.
    EXPECT_TRUE(a.empty());
}

TEST(SurfaceClosure, RecordSubstepAddsItWithAnObject) {
    const LevelSet box = level_set_from_mesh(testmesh::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)), kRf);
    CrackRecorder rec(kRf);
    rec.add_crack();
    const auto tests = rec.record_substep({corner_motion()}, &box);
    EXPECT_EQ(tests[0][1].hit, MarkerHit::left_object);
    EXPECT_LE(sample(rec.snapshot().cracks[0], Vec3(-0.46, 0.46, 0)), 0.0);
    // Without an object there is no surface to close onto: the strips alone.
    CrackRecorder bare(kRf);
    bare.add_crack();
    bare.record_substep({corner_motion()}, nullptr);
    EXPECT_GT(sample(bare.snapshot().cracks[0], Vec3(-0.46, 0.46, 0)), kRf);
}

}  // namespace
}  // namespace cf
