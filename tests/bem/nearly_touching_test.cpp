// Where a BEM surface is too tight for its integrals (nodes/bem/nearly_touching.hpp): triangle
// distances against hand-computed values, and the nearest pair of triangles without a common vertex
// on meshes whose gap is known.
#include "nodes/bem/nearly_touching.hpp"
#include "nodes/bem/test_meshes.hpp"

#include <gtest/gtest.h>

namespace cf::bem {
namespace {

ElementGeometry triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    SurfaceMesh m;
    m.vertices = {a, b, c};
    m.triangles = {{0, 1, 2}};
    return element_geometry(m, 0);
}

// Two cubes of side L, the second shifted along x by L + gap: one mesh, two shells.
SurfaceMesh two_cubes(double L, double gap) {
    SurfaceMesh m = bem_cube_mesh(3, L);
    const SurfaceMesh other = bem_cube_mesh(3, L, Vec3(L + gap, 0, 0));
    const int n = int(m.vertices.size());
    m.vertices.insert(m.vertices.end(), other.vertices.begin(), other.vertices.end());
    for (Tri t : other.triangles) m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
    m.region.clear();
    return m;
}

TEST(NearlyTouching, TriangleDistancesAreTheHandComputedOnes) {
    const double h = 0.003;
    // Parallel, one above the other: the plane distance, midway between them.
    Vec3 mid;
    EXPECT_NEAR(triangle_distance(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), triangle({0.1, 0.1, h}, {0.6, 0.1, h}, {0.1, 0.6, h}), &mid), h,
                1e-15);
    EXPECT_NEAR(mid.z(), 0.5 * h, 1e-15);
    // Perpendicular sheets whose closest points lie on an edge of each: h between (0.5, 0, 0) and (0.5, 0, h).
    const ElementGeometry a = triangle({0, 0, 0}, {1, 0, 0}, {0.5, -1, 0});
    const ElementGeometry b = triangle({0.5, -0.5, h}, {0.5, 0.5, h}, {0.5, 0, h + 1});
    EXPECT_NEAR(triangle_distance(a, b), h, 1e-15);
    // Skew edges, closest points inside both: edge x in [0, 1] at y = z = 0 and edge y in [-1, 1] at
    // x = 0.5, z = h, their triangles turned away from each other (below z = 0, above z = h).
    EXPECT_NEAR(triangle_distance(triangle({0, 0, 0}, {1, 0, 0}, {0.5, 0, -1}), triangle({0.5, -1, h}, {0.5, 1, h}, {0.5, 0, h + 1})),
                h, 1e-15);
    // Crossing: 0.
    EXPECT_EQ(triangle_distance(a, triangle({0.5, -0.5, -0.5}, {0.5, -0.5, 0.5}, {0.5, -0.8, 0})), 0.0);
}

TEST(NearlyTouchingPair, TwoCubesAGapApartAreFoundWithTheGap) {
    const double L = 0.1, gap = 0.002;
    const SurfaceMesh m = two_cubes(L, gap);
    const std::vector<ElementGeometry> g = element_geometries(m, "test");
    const NearlyTouchingPair p = nearly_touching_pair(g);
    ASSERT_TRUE(p.found);
    EXPECT_NEAR(p.gap, gap, 1e-12);
    // The facing faces: x_max of the first cube (triangles below its count) and x_min of the second.
    EXPECT_LT(p.a, int(m.triangles.size() / 2));
    EXPECT_GE(p.b, int(m.triangles.size() / 2));
    EXPECT_NEAR(p.where.x(), 0.5 * L + 0.5 * gap, 1e-12);
    EXPECT_NEAR(p.size, std::sqrt(2.0) * L / 3, 1e-12);  // the diagonal of a face square
    const std::string text = describe_nearly_touching(g);
    EXPECT_NE(text.find("lie 0.002 m apart"), std::string::npos) << text;
    EXPECT_NE(text.find("target_triangles"), std::string::npos) << text;
}

TEST(NearlyTouchingPair, AConvexSurfaceHasNoneToReport) {
    // On a cube of 3 x 3 squares per face (side h = L/3, each cut along a diagonal) the nearest
    // triangles without a common vertex lie on two faces meeting at an edge, along the two
    // diagonals beside it: skew lines with directions (0, 1, 1) and (1, 0, 1) whose distance is
    // |(0, h, 0).(1, 1, -1)| / sqrt(3) = h / sqrt(3); over the diagonal sqrt(2) h, 1 / sqrt(6) =
    // 0.408, above the limit 0.25.
    const std::vector<ElementGeometry> g = element_geometries(bem_cube_mesh(3, 0.1), "test");
    const NearlyTouchingPair p = nearly_touching_pair(g);
    ASSERT_TRUE(p.found);
    EXPECT_NEAR(p.gap, 0.1 / 3 / std::sqrt(3.0), 1e-12);
    EXPECT_NEAR(p.ratio(), 1 / std::sqrt(6.0), 1e-12);
    EXPECT_EQ(describe_nearly_touching(g), "");
    EXPECT_EQ(describe_nearly_touching(element_geometries(bem_icosphere_mesh(2, 0.05), "test")), "");
}

}  // namespace
}  // namespace cf::bem
