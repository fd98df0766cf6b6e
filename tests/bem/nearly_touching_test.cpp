// Where a BEM surface is too tight for its integrals (nodes/bem/nearly_touching.hpp): triangle
// distances against hand-computed values, and the nearest pair of triangles without a common vertex
// on meshes whose gap is known.
#include "nodes/bem/nearly_touching.hpp"
#include "nodes/bem/operators.hpp"
#include "nodes/bem/test_meshes.hpp"

#include <cmath>

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

TEST(WorstRow, NamesTheTriangleItsSharpestFoldAndItsShape) {
    // Triangle 0 in z = 0 with the edge (0,0,0)-(1,0,0), on its y < 0 side; triangle 1 shares that edge
    // and folds back over triangle 0 at 30 degrees (its third vertex at (0.5, -cos 30, sin 30), the
    // orientation consistent: normals (0, 0, -1) and (0, sin 30, cos 30)); triangle 2 shares only a vertex,
    // triangle 3 the edge (1,0,0)-(0.5,-0.2,0), flat (180 degrees).
    // Triangle 0 has the vertices (0,0,0), (1,0,0), (0.5,-0.2,0): area 0.1, longest edge 1, so 0.1 /
    // (sqrt(3)/4) = 0.231 of an equilateral triangle's area.
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, -0.2, 0}, {0.5, -c, s}, {-1, 0, 0}, {-0.5, -1, 0}, {1, -0.6, 0}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 4, 5}, {2, 1, 6}};
    const std::vector<ElementGeometry> g = element_geometries(m, "test");
    const std::string text = describe_worst_row(g, 0, 0.047);
    EXPECT_NE(text.find("triangle 0 at (0.5, -0.0667, 0) m"), std::string::npos) << text;
    EXPECT_NE(text.find("misses the rigid translations by 0.047"), std::string::npos) << text;
    EXPECT_NE(text.find("folds at 30 degrees against triangle 1"), std::string::npos) << text;
    EXPECT_NE(text.find("has 0.231 of an equilateral"), std::string::npos) << text;
    EXPECT_EQ(describe_worst_row(g, 0, 5e-4), "");  // below the limit: nothing to say
    EXPECT_EQ(describe_worst_row(g, -1, 0.047), "");  // no row measured
}

TEST(WorstRow, TheAssemblyRecordsTheRowOfTheLargestResidual) {
    // The cube's rows all sit near the same residual; whichever is largest, it is the one recorded.
    const SurfaceMesh m = bem_cube_mesh(3, 0.1);
    const auto ops = assemble_surface_operators(m, Material{}, AssemblyOptions{});
    ASSERT_GE(ops->rigid_motion.worst_element, 0);
    ASSERT_LT(ops->rigid_motion.worst_element, int(m.triangles.size()));
    EXPECT_GT(ops->rigid_motion.max_residual, 0.0);
    EXPECT_LT(ops->rigid_motion.max_residual, 1e-3);  // a well-shaped surface: no sentence for it
    EXPECT_EQ(describe_worst_row(ops->geometry, ops->rigid_motion.worst_element, ops->rigid_motion.max_residual), "");
}

}  // namespace
}  // namespace cf::bem
