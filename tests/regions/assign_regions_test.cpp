// Region assignment by centroid, first match wins, default and kept regions, per-region stats.
#include "nodes/regions/assign_regions.hpp"
#include "nodes/regions/region_stats.hpp"
#include "nodes/shape/box.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

SurfaceMesh unit_cube(int n) { return make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), n}); }

TEST(AssignRegions, BoxFacesByPlanesMatchTheBoxOwnRegions) {
    const SurfaceMesh box = unit_cube(4);
    const auto a = assign_regions(box, parse_region_spec("top: z >= 0.49; bottom: z <= -0.49"), false);
    EXPECT_EQ(a.mesh.region_names, (std::vector<std::string>{"default", "top", "bottom"}));
    EXPECT_EQ(a.region_id, (std::vector<int>{1, 2}));
    EXPECT_EQ(a.matched, (std::vector<std::size_t>{32, 32}));
    EXPECT_EQ(a.unmatched, 4u * 32);
    for (std::size_t t = 0; t < box.num_triangles(); ++t) {
        const std::string face = box.region_name(box.region_of(t));
        const int expected = face == "z_max" ? 1 : face == "z_min" ? 2 : 0;
        EXPECT_EQ(a.mesh.region_of(t), expected) << t;
    }
    const auto stats = region_stats(a.mesh);
    ASSERT_EQ(stats.size(), 3u);
    EXPECT_EQ(stats[0].name, "default");
    EXPECT_EQ(stats[0].triangles, 128u);
    EXPECT_NEAR(stats[0].area, 4.0, 1e-14);
    EXPECT_EQ(stats[1].name, "top");
    EXPECT_NEAR(stats[1].area, 1.0, 1e-15);
    EXPECT_NEAR(stats[2].area, 1.0, 1e-15);
    // Geometry is untouched.
    EXPECT_EQ(a.mesh.vertices, box.vertices);
    EXPECT_EQ(a.mesh.triangles, box.triangles);
}

TEST(AssignRegions, FirstMatchingRegionWins) {
    const SurfaceMesh box = unit_cube(2);
    const auto a = assign_regions(box, parse_region_spec("right: x >= 0; all: x >= -1"), false);
    EXPECT_EQ(a.unmatched, 0u);
    for (std::size_t t = 0; t < box.num_triangles(); ++t)
        EXPECT_EQ(a.mesh.region_of(t), triangle_centroid(box, t).x() >= 0 ? 1 : 2);
    // The x_max face (8 triangles) and the halves of four side faces (4 each) are right of x = 0.
    EXPECT_EQ(a.matched[0], 8u + 4 * 4);
}

TEST(AssignRegions, TheCentroidDecidesAStraddlingTriangle) {
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}};  // centroid (1, 1, 0) exactly
    m.triangles = {{0, 1, 2}};
    auto region_for = [&m](const std::string& spec) {
        return assign_regions(m, parse_region_spec(spec), false).mesh.region_of(0);
    };
    EXPECT_EQ(region_for("r: x >= 1"), 1);     // the plane through the centroid, inclusive
    EXPECT_EQ(region_for("r: x > 1"), 0);      // strict: not included
    EXPECT_EQ(region_for("r: x >= 1.01"), 0);  // two vertices are in, the centroid is not
    EXPECT_EQ(region_for("r: x <= 0.99"), 0);  // two vertices are in, the centroid is not
    EXPECT_EQ(region_for("r: x + y <= 2"), 1);
}

TEST(AssignRegions, KeepUnmatchedKeepsRegionsAndMergesByName) {
    const SurfaceMesh box = unit_cube(2);
    const auto a = assign_regions(box, parse_region_spec("top_left: z >= 0.49 & x <= 0; x_min: x <= -0.49"), true);
    EXPECT_EQ(a.mesh.region_names,
              (std::vector<std::string>{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max", "top_left"}));
    EXPECT_EQ(a.region_id, (std::vector<int>{6, 0}));
    EXPECT_EQ(a.matched[0], 4u);
    EXPECT_EQ(a.matched[1], 8u);
    for (std::size_t t = 0; t < box.num_triangles(); ++t) {
        const bool top_left = box.region_of(t) == 5 && triangle_centroid(box, t).x() <= 0;
        EXPECT_EQ(a.mesh.region_of(t), top_left ? 6 : box.region_of(t));
    }
    const auto stats = region_stats(a.mesh);
    EXPECT_NEAR(stats[5].area, 0.5, 1e-15);  // z_max lost its left half
    EXPECT_NEAR(stats[6].area, 0.5, 1e-15);
}

TEST(AssignRegions, KeepUnmatchedOnAMeshWithoutRegions) {
    SurfaceMesh m = unit_cube(1);
    m.region.clear();
    m.region_names.clear();
    const auto a = assign_regions(m, parse_region_spec("top: z >= 0.5"), true);
    EXPECT_EQ(a.mesh.region_names, (std::vector<std::string>{"region0", "top"}));
    EXPECT_EQ(a.matched[0], 2u);
    EXPECT_EQ(a.unmatched, 10u);
}

TEST(AssignRegions, StatsCoverEveryTriangleOnce) {
    const SurfaceMesh box = unit_cube(3);
    const auto a = assign_regions(box, parse_region_spec("a: x + y + z >= 0.5; b: x - y > 0.2 & z < 0"), false);
    std::size_t n = 0;
    double area = 0;
    for (const RegionStats& s : region_stats(a.mesh)) n += s.triangles, area += s.area;
    EXPECT_EQ(n, box.num_triangles());
    EXPECT_NEAR(area, 6.0, 1e-13);
}

}  // namespace
}  // namespace cf
