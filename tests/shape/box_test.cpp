// Box: volume, area and face areas are exact for any subdivision.
#include "nodes/shape/box.hpp"
#include "tests/shape/mesh_checks.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

using testing::expect_closed_outward;
using testing::region_area;
using testing::region_triangles;

TEST(Box, VolumeAreaAndFacesAreExact) {
    BoxSpec s;
    s.size = Vec3(1.0, 2.0, 0.5);
    s.centre = Vec3(0.3, -0.2, 1.1);
    s.subdivisions = 3;
    const SurfaceMesh m = make_box(s);
    EXPECT_EQ(m.num_triangles(), 6u * 2 * 3 * 3);
    EXPECT_EQ(m.num_vertices(), 6u * 3 * 3 + 2);  // (n+1)^3 - (n-1)^3 lattice points on the surface
    expect_closed_outward(m, 2);
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-14);
    EXPECT_NEAR(surface_area(m), 2 * (1.0 * 2.0 + 2.0 * 0.5 + 0.5 * 1.0), 1e-13);
    const double face[3] = {2.0 * 0.5, 0.5 * 1.0, 1.0 * 2.0};  // faces normal to x, y, z
    const char* names[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    for (int r = 0; r < 6; ++r) {
        EXPECT_EQ(m.region_name(r), names[r]);
        EXPECT_NEAR(region_area(m, names[r]), face[r / 2], 1e-14) << names[r];
        EXPECT_EQ(region_triangles(m, names[r]), 18u) << names[r];
    }
    const Box3 b = bounding_box(m);
    EXPECT_TRUE(b.min.isApprox(Vec3(-0.2, -1.2, 0.85), 1e-15));
    EXPECT_TRUE(b.max.isApprox(Vec3(0.8, 0.8, 1.35), 1e-15));
}

TEST(Box, EveryFaceTriangleFacesItsRegionsNormal) {
    BoxSpec s;
    s.subdivisions = 5;
    const SurfaceMesh m = make_box(s);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const int r = m.region_of(t);
        Vec3 expected = Vec3::Zero();
        expected[r / 2] = r % 2 ? 1 : -1;
        EXPECT_TRUE(triangle_normal(m, t).isApprox(expected, 1e-14)) << t;
        // The centroid lies on that face's plane.
        EXPECT_NEAR(triangle_centroid(m, t)[r / 2], 0.5 * expected[r / 2], 1e-15);
    }
}

TEST(Box, SingleCellBoxIsTheTwelveTriangleCube) {
    const SurfaceMesh m = make_box(BoxSpec{Vec3(2, 2, 2), Vec3::Zero(), 1});
    EXPECT_EQ(m.num_triangles(), 12u);
    EXPECT_EQ(m.num_vertices(), 8u);
    expect_closed_outward(m, 2);
    EXPECT_DOUBLE_EQ(signed_volume(m), 8.0);
}

TEST(Box, BadSpecsAreRejectedNamingTheParameter) {
    BoxSpec s;
    s.size = Vec3(1, 0, 1);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { make_box(s); }, {"parameter 'size': every edge length must be > 0 m, got 0 m for axis y"}));
    s.size = Vec3(1, 1, 1);
    s.subdivisions = 0;
    EXPECT_THROW(make_box(s), std::invalid_argument);
}

}  // namespace
}  // namespace cf
