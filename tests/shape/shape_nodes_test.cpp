// The shape nodes through the per-node harness: parameters reach the shape, counts are reported,
// bad parameters become node errors.
#include "nodes/domain/mesh_topology.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

using testing::run_node;

std::string error_of(const std::string& type, const testing::Params& p) {
    try {
        run_node(type, p);
    } catch (const graph::NodeError& e) {
        return e.what();
    }
    return "no error";
}

TEST(ShapeNodes, BoxReportsTrianglesAndFaceAreas) {
    auto r = run_node("shape.box", {{"size", std::vector<double>{1, 2, 3}}, {"subdivisions", 2LL}});
    const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
    EXPECT_NEAR(signed_volume(m), 6.0, 1e-14);
    EXPECT_EQ(r.counts.at("triangles"), 48);
    EXPECT_EQ(r.counts.at("vertices"), 26);
    EXPECT_EQ(r.counts.at("region.x_min.triangles"), 8);
    EXPECT_NEAR(r.counts.at("region.x_min.area"), 6.0, 1e-14);
    EXPECT_NEAR(r.counts.at("region.z_max.area"), 2.0, 1e-14);
}

TEST(ShapeNodes, SphereSaysWhichCountItAchieved) {
    auto r = run_node("shape.sphere", {{"radius", 2.0}, {"triangles", 1000LL}, {"centre", std::vector<double>{1, 1, 1}}});
    EXPECT_EQ(r.counts.at("triangles"), 1280);
    EXPECT_EQ(r.counts.at("level"), 3);
    const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
    for (const Vec3& p : m.vertices) EXPECT_NEAR((p - Vec3(1, 1, 1)).norm(), 2.0, 1e-14);
    auto once = run_node("shape.sphere", {{"projection", std::string("once")}, {"triangles", 320LL}});
    EXPECT_EQ(once.counts.at("triangles"), 320);
}

TEST(ShapeNodes, CylinderTorusAndNotchedBarAreClosedAndNamed) {
    for (const char* type : {"shape.cylinder", "shape.torus", "shape.notched_bar"}) {
        auto r = run_node(type);
        const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
        const MeshTopologyReport t = check_topology(m);
        EXPECT_TRUE(t.is_closed_manifold()) << type << ": " << t.describe();
        EXPECT_GT(signed_volume(m), 0) << type;
        EXPECT_EQ(r.counts.at("triangles"), static_cast<double>(m.num_triangles())) << type;
    }
    auto cyl = run_node("shape.cylinder", {{"caps", std::string("rings")}, {"segments", 16LL}, {"cap_rings", 2LL}});
    EXPECT_EQ(cyl.counts.at("region.top.triangles"), 16 * 3);
    auto bar = run_node("shape.notched_bar", {{"notch", std::string("rectangular")}});
    EXPECT_NEAR(bar.counts.at("region.load.area"), 0.02 * 0.05, 1e-15);
    auto torus = run_node("shape.torus");
    EXPECT_EQ(torus.counts.at("region.pull_left.triangles"), 16);
}

TEST(ShapeNodes, BadParametersAreNodeErrors) {
    EXPECT_EQ(error_of("shape.box", {{"size", std::vector<double>{1, 0, 1}}}),
              "parameter 'size' value 0 is outside the allowed range (0, inf)");
    EXPECT_EQ(error_of("shape.torus", {{"major_segments", 7LL}}),
              "parameter 'major_segments' must be even and >= 4 (so the left and right pulled faces are mirror "
              "images), got 7");
    EXPECT_EQ(error_of("shape.notched_bar", {{"notch_width", 0.5}}),
              "parameter 'notch_width' must be in (0, length = 0.4 m), got 0.5 m");
}

}  // namespace
}  // namespace cf
