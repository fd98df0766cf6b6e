// Element-shape measures and their repair (nodes/simplify/mesh_quality, quality_repair; issue 13),
// against hand values: the angles of known triangles, the dihedrals of the Platonic solids, and a
// folded needle on a sphere repaired back onto the sphere.
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"
#include "nodes/simplify/mesh_quality.hpp"
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/quality_repair.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

TEST(MeshQuality, TriangleAnglesByHand) {
    EXPECT_NEAR(min_triangle_angle_deg(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(0.75), 0)), 60, 1e-12);
    EXPECT_NEAR(min_triangle_angle_deg(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)), 45, 1e-12);
    EXPECT_NEAR(min_triangle_angle_deg(Vec3(0, 0, 0), Vec3(std::sqrt(3.0), 0, 0), Vec3(0, 1, 0)), 30, 1e-12);
    // A needle 1e-9 high over a unit base: its smallest angle is atan(1e-9 / 0.5) at each base end.
    EXPECT_NEAR(min_triangle_angle_deg(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1e-9, 0)), std::atan(2e-9) * kDeg, 1e-15);
    EXPECT_EQ(min_triangle_angle_deg(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)), 0);
}

TEST(MeshQuality, DihedralsOfACubeAndATetrahedron) {
    // Split faces of a cube: 90 degrees across the cube's edges, 180 across the face diagonals.
    BoxSpec spec;
    spec.subdivisions = 1;
    const MeshQuality cube = measure_quality(make_box(spec), 46, 91);
    EXPECT_NEAR(cube.min_dihedral_deg, 90, 1e-9);
    EXPECT_NEAR(cube.min_angle_deg, 45, 1e-9);
    EXPECT_EQ(cube.angles_below, 12u);    // every triangle has two 45-degree angles
    EXPECT_EQ(cube.dihedrals_below, 12u);  // the cube's 12 edges
    // Regular tetrahedron: dihedral acos(1/3) = 70.53 degrees.
    SurfaceMesh tet;
    tet.vertices = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
    tet.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    ASSERT_GT(signed_volume(tet), 0);
    const MeshQuality q = measure_quality(tet);
    EXPECT_NEAR(q.min_dihedral_deg, std::acos(1.0 / 3.0) * kDeg, 1e-9);
    EXPECT_NEAR(q.min_angle_deg, 60, 1e-9);
}

// A unit icosphere with one vertex pushed across its neighbour: a needle folded over the surface.
SurfaceMesh folded_sphere() {
    SphereSpec spec;
    spec.level = 2;
    SurfaceMesh m = make_icosphere(spec);
    // Vertex 0's neighbour w: move 0 most of the way to w and a little beyond it.
    int w = -1;
    for (const Tri& t : m.triangles)
        for (int k = 0; k < 3; ++k)
            if (t[k] == 0) w = t[(k + 1) % 3];
    m.vertices[0] = (m.vertices[0] + 1.02 * (m.vertices[w] - m.vertices[0])).normalized();
    return m;
}

TEST(QualityRepair, FoldedNeedleOnASphereIsRepairedOntoTheSphere) {
    SurfaceMesh m = folded_sphere();
    const MeshQuality before = measure_quality(m, 15, 30);
    ASSERT_LT(before.min_angle_deg, 5);
    ASSERT_LT(before.min_dihedral_deg, 30);
    const QualityRepair r = improve_quality(m, QualityBounds{15, 30}, [](const Vec3& p) { return Vec3(p.normalized()); });
    EXPECT_GE(r.after.min_angle_deg, 15) << describe(r.after);
    EXPECT_GE(r.after.min_dihedral_deg, 30) << describe(r.after);
    EXPECT_EQ(r.after.angles_below + r.after.dihedrals_below, 0u);
    const MeshTopologyReport topo = check_topology(m);
    EXPECT_TRUE(topo.is_closed_manifold()) << topo.describe();
    EXPECT_EQ(topo.euler_characteristic, 2);
    EXPECT_EQ(self_intersecting_pairs(m).size(), 0u);
    for (const Vec3& v : m.vertices) EXPECT_NEAR(v.norm(), 1, 1e-12);  // every vertex still on the sphere
    EXPECT_GT(r.flips + r.collapses + r.moves + r.splits, 0u);
    // The measured bounds agree with an independent pass over the result.
    const MeshQuality again = measure_quality(m);
    EXPECT_EQ(again.min_angle_deg, r.after.min_angle_deg);
}

TEST(QualityRepair, ZeroAreaCapOnAFlatFaceIsFlippedAway) {
    // A box face split with an extra vertex on a cube edge's midpoint: the triangle (a, b, mid) has
    // area zero. Without a projection the vertex stays; a flip removes the cap.
    BoxSpec spec;
    spec.subdivisions = 2;
    SurfaceMesh m = make_box(spec);
    const double volume = signed_volume(m);
    const QualityRepair r = improve_quality(m, QualityBounds{15, 30});
    EXPECT_EQ(r.after.angles_below, 0u) << describe(r.after);   // 45-degree triangles: nothing to do
    EXPECT_EQ(r.flips + r.collapses + r.moves + r.splits, 0u);  // a good mesh is left alone
    EXPECT_NEAR(signed_volume(m), volume, 1e-12);
}

TEST(QualityRepair, BadBoundsAreRefused) {
    SurfaceMesh m = folded_sphere();
    EXPECT_THROW(improve_quality(m, QualityBounds{60, 30}), std::invalid_argument);
    EXPECT_THROW(improve_quality(m, QualityBounds{15, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace cf
