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

TEST(Box, CellSizeGivesCellsPerAxisForSlenderBoxes) {
    // A 1.5 x 0.06 x 0.06 m bar with cells of 0.03 m: 50 x 2 x 2 cells, square cells on every face.
    BoxSpec s;
    s.size = Vec3(1.5, 0.06, 0.06);
    s.cell_size = 0.03;
    EXPECT_EQ(box_cells(s), (std::array<int, 3>{50, 2, 2}));
    const SurfaceMesh m = make_box(s);
    // Faces normal to x: 2 x 2 cells; to y and z: 2 x 50; two triangles a cell.
    EXPECT_EQ(m.num_triangles(), 2u * 2 * (2 * 2 + 2 * 50 + 50 * 2));
    EXPECT_EQ(m.num_vertices(), 51u * 3 * 3 - 49u * 1 * 1);  // lattice points on the surface
    expect_closed_outward(m, 2);
    EXPECT_NEAR(signed_volume(m), 1.5 * 0.06 * 0.06, 1e-15);
    EXPECT_NEAR(region_area(m, "z_max"), 1.5 * 0.06, 1e-15);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const double a = triangle_area(m, t);
        EXPECT_NEAR(a, 0.5 * 0.03 * 0.03, 1e-12) << t;  // every cell is 0.03 x 0.03
    }
    // A cell larger than an edge still gives one cell there.
    s.cell_size = 0.5;
    EXPECT_EQ(box_cells(s), (std::array<int, 3>{3, 1, 1}));
    expect_closed_outward(make_box(s), 2);
    // Too fine or negative: refused with the parameter.
    s.cell_size = 1e-7;
    EXPECT_THROW(make_box(s), std::invalid_argument);
    s.cell_size = -1;
    try {
        make_box(s);
        FAIL() << "expected an error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("parameter 'cell_size'"), std::string::npos) << e.what();
    }
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
