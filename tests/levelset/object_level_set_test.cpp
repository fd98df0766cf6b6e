// Object signed distance grid (ch. 6.1): values against the exact box distance, sign everywhere,
// volume, meshing back, VDB round trip and the bad-input errors.
#include "nodes/levelset/level_set.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace cf {
namespace {

const Vec3 kLo(-0.5, -0.3, -0.2), kHi(0.5, 0.3, 0.2);  // 1 x 0.6 x 0.4 m box
constexpr double kRf = 0.02;

// Exact signed distance to the box (negative inside).
double box_distance(const Vec3& p) {
    const Vec3 c = 0.5 * (kLo + kHi), h = 0.5 * (kHi - kLo);
    const Vec3 q = (p - c).cwiseAbs() - h;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

std::string error_of(const SurfaceMesh& m, double r_f) {
    try {
        level_set_from_mesh(m, r_f);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(ObjectLevelSet, ValuesMatchExactDistanceInTheBandAndSignEverywhere) {
    const LevelSet ls = level_set_from_mesh(testmesh::box(kLo, kHi), kRf);
    EXPECT_DOUBLE_EQ(ls.voxel_size, kRf);
    EXPECT_DOUBLE_EQ(ls.half_width, 3);
    double worst_band = 0;
    int checked = 0;
    for (double x = -0.6; x <= 0.6; x += 0.037)
        for (double y = -0.4; y <= 0.4; y += 0.031)
            for (double z = -0.3; z <= 0.3; z += 0.029) {
                const Vec3 p(x, y, z);
                const double exact = box_distance(p), got = sample(ls, p);
                // Sign everywhere (interior tiles filled), away from the zero crossing.
                if (std::abs(exact) > 0.5 * kRf) {
                    ASSERT_EQ(got < 0, exact < 0) << "at " << p.transpose();
                }
                // Inside the band (minus one voxel for interpolation at its rim) values are distances.
                // Near edges/corners the trilinear interpolation of a kinked field errs by up to ~r_f/2.
                if (std::abs(exact) < 2 * kRf) {
                    worst_band = std::max(worst_band, std::abs(got - exact));
                    ++checked;
                }
            }
    EXPECT_GT(checked, 100);
    EXPECT_LT(worst_band, 0.5 * kRf);
    EXPECT_NEAR(sample(ls, Vec3(0, 0, 0)), -3 * kRf, 1e-6);    // deep inside: -background
    EXPECT_NEAR(sample(ls, Vec3(0, 0, 1.0)), 3 * kRf, 1e-6);    // far outside: +background
    // On a face, away from edges, the field is linear: interpolation is exact to float precision.
    EXPECT_NEAR(sample(ls, Vec3(0.013, 0.007, 0.2 - 0.031)), -0.031, 1e-3 * kRf);
    EXPECT_NEAR(sample(ls, Vec3(0.013, 0.007, 0.2 + 0.017)), 0.017, 1e-3 * kRf);
}

TEST(ObjectLevelSet, VolumeMeasuredFromTheGrid) {
    const LevelSet ls = level_set_from_mesh(testmesh::box(kLo, kHi), kRf);
    const double exact = 1.0 * 0.6 * 0.4;
    // Sharp edges are rounded at the voxel scale: allow edge length x r_f^2 (~1 % here).
    const double edge_length = 4 * (1.0 + 0.6 + 0.4);
    EXPECT_NEAR(level_set_volume(ls), exact, edge_length * kRf * kRf);
    EXPECT_NEAR(level_set_volume(ls) / exact, 1.0, 0.01);
}

TEST(ObjectLevelSet, MeshingGivesClosedOrientedSurfaceOfTheSameVolume) {
    const LevelSet ls = level_set_from_mesh(testmesh::box(kLo, kHi), kRf);
    for (double adaptivity : {0.0, 0.5}) {
        const SurfaceMesh m = level_set_to_mesh(ls, adaptivity);
        const MeshTopologyReport topo = check_topology(m);
        EXPECT_TRUE(topo.is_closed_manifold()) << topo.describe();
        EXPECT_EQ(topo.euler_characteristic, 2);
        EXPECT_NEAR(signed_volume(m) / (1.0 * 0.6 * 0.4), 1.0, 0.01) << "adaptivity " << adaptivity;
        const Box3 b = bounding_box(m);
        EXPECT_NEAR(b.min.x(), kLo.x(), 0.5 * kRf);
        EXPECT_NEAR(b.max.z(), kHi.z(), 0.5 * kRf);
    }
    // Adaptivity merges the flat faces: far fewer triangles.
    EXPECT_LT(level_set_to_mesh(ls, 0.5).num_triangles(), level_set_to_mesh(ls, 0).num_triangles() / 2);
}

TEST(ObjectLevelSet, VdbRoundTripKeepsValues) {
    const LevelSet ls = level_set_from_mesh(testmesh::box(kLo, kHi), kRf);
    const auto dir = std::filesystem::temp_directory_path() / "cf_levelset_vdb_roundtrip";
    std::filesystem::create_directories(dir);
    write_vdb(dir / "object.vdb", {{"object", ls}});
    const auto back = read_vdb(dir / "object.vdb");
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0].first, "object");
    EXPECT_NEAR(back[0].second.voxel_size, kRf, 1e-12);
    EXPECT_NEAR(back[0].second.half_width, 3, 1e-5);
    EXPECT_EQ(active_voxel_count(back[0].second), active_voxel_count(ls));
    for (const Vec3& p : {Vec3(0.1, 0.2, 0.19), Vec3(-0.49, 0, 0), Vec3(0, 0, 0)})
        EXPECT_EQ(sample(back[0].second, p), sample(ls, p));
    std::filesystem::remove_all(dir);
}

TEST(ObjectLevelSet, TwoSeparateBoxesGiveTheSumOfVolumes) {
    const SurfaceMesh two = testmesh::merge(testmesh::box({0, 0, 0}, {0.4, 0.4, 0.4}), testmesh::box({1, 0, 0}, {1.2, 0.4, 0.4}));
    const LevelSet ls = level_set_from_mesh(two, kRf);
    EXPECT_NEAR(level_set_volume(ls) / (0.064 + 0.032), 1.0, 0.02);
    EXPECT_GT(sample(ls, Vec3(0.7, 0.2, 0.2)), 0);  // the gap between them is outside
}

TEST(ObjectLevelSetErrors, OpenMeshIsRejectedWithTheCount) {
    SurfaceMesh open = testmesh::box(kLo, kHi);
    open.triangles.pop_back();
    const std::string e = error_of(open, kRf);
    EXPECT_NE(e.find("closed"), std::string::npos) << e;
    EXPECT_NE(e.find("3 boundary edges"), std::string::npos) << e;
}

TEST(ObjectLevelSetErrors, InwardOrientationIsRejected) {
    SurfaceMesh flipped = testmesh::box(kLo, kHi);
    for (Tri& t : flipped.triangles) std::swap(t[1], t[2]);
    const std::string e = error_of(flipped, kRf);
    EXPECT_NE(e.find("inward"), std::string::npos) << e;
}

TEST(ObjectLevelSetErrors, VoxelTooLargeForTheObject) {
    const std::string e = error_of(testmesh::box(kLo, kHi), 0.15);  // thinnest side 0.4 m < 4 * 0.15
    EXPECT_NE(e.find("too large"), std::string::npos) << e;
    EXPECT_NE(e.find("r_f <= 0.1"), std::string::npos) << e;
}

TEST(ObjectLevelSetErrors, VoxelTooSmallForMemory) {
    const std::string e = error_of(testmesh::box(kLo, kHi), 1e-5);
    EXPECT_NE(e.find("too small"), std::string::npos) << e;
}

TEST(ObjectLevelSetErrors, NonPositiveVoxelSize) {
    EXPECT_NE(error_of(testmesh::box(kLo, kHi), 0).find("positive"), std::string::npos);
    EXPECT_NE(error_of(testmesh::box(kLo, kHi), -1).find("positive"), std::string::npos);
}

}  // namespace
}  // namespace cf
