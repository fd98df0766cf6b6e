// check_topology on small hand-built meshes whose defects are known.
#include "nodes/domain/mesh_topology.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

// Regular-ish tetrahedron, outward: V = 4, E = 6, F = 4.
SurfaceMesh tetrahedron(Vec3 shift = Vec3::Zero()) {
    SurfaceMesh m;
    m.vertices = {shift + Vec3(0, 0, 0), shift + Vec3(1, 0, 0), shift + Vec3(0, 1, 0), shift + Vec3(0, 0, 1)};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

TEST(MeshTopology, TetrahedronIsClosedOrientedSphere) {
    const SurfaceMesh m = tetrahedron();
    const MeshTopologyReport r = check_topology(m);
    EXPECT_TRUE(r.is_closed_manifold()) << r.describe();
    EXPECT_EQ(r.vertices, 4u);
    EXPECT_EQ(r.edges, 6u);
    EXPECT_EQ(r.triangles, 4u);
    EXPECT_EQ(r.euler_characteristic, 2);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.describe(), "closed 2-manifold, consistently oriented");
    EXPECT_NEAR(signed_volume(m), 1.0 / 6.0, 1e-15);
}

TEST(MeshTopology, MissingFaceLeavesThreeBoundaryEdges) {
    SurfaceMesh m = tetrahedron();
    m.triangles.pop_back();
    const MeshTopologyReport r = check_topology(m);
    EXPECT_FALSE(r.closed());
    EXPECT_EQ(r.boundary_edges, 3u);
    EXPECT_TRUE(r.manifold());
    EXPECT_TRUE(r.consistently_oriented());
    EXPECT_EQ(r.euler_characteristic, 1);  // a disc
    EXPECT_EQ(r.describe(), "3 boundary edges (holes: the surface is not closed)");
}

TEST(MeshTopology, FlippedFaceMisorientsItsThreeEdges) {
    SurfaceMesh m = tetrahedron();
    std::swap(m.triangles[3][1], m.triangles[3][2]);
    const MeshTopologyReport r = check_topology(m);
    EXPECT_TRUE(r.closed());
    EXPECT_EQ(r.misoriented_edges, 3u);
    EXPECT_FALSE(r.is_closed_manifold());
}

TEST(MeshTopology, TwoTetrahedraTouchingAtAVertexMakeItNonManifold) {
    SurfaceMesh m = tetrahedron();
    const SurfaceMesh b = tetrahedron(Vec3(-1, 0, 0));  // its vertex 1 lands on m's vertex 0
    m.vertices.push_back(b.vertices[0]);
    m.vertices.push_back(b.vertices[2]);
    m.vertices.push_back(b.vertices[3]);
    const int map[4] = {4, 0, 5, 6};
    for (const Tri& f : b.triangles) m.triangles.push_back({map[f[0]], map[f[1]], map[f[2]]});
    const MeshTopologyReport r = check_topology(m);
    EXPECT_TRUE(r.closed());
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_EQ(r.nonmanifold_vertices, 1u);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(r.euler_characteristic, 7 - 12 + 8);
    EXPECT_FALSE(r.manifold());
}

TEST(MeshTopology, ThreeTrianglesOnOneEdgeIsNonManifold) {
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const MeshTopologyReport r = check_topology(m);
    EXPECT_EQ(r.nonmanifold_edges, 1u);
    EXPECT_EQ(r.boundary_edges, 6u);
}

TEST(MeshTopology, DegenerateAndInvalidTrianglesAreCounted) {
    SurfaceMesh m = tetrahedron();
    m.vertices.push_back(Vec3(2, 0, 0));              // 4: collinear with 0 and 1
    m.vertices.push_back(Vec3(5, 5, 5));              // 5: unused
    m.triangles.push_back({0, 1, 4});                 // zero area
    m.triangles.push_back({2, 2, 3});                 // repeated vertex
    m.triangles.push_back({0, 1, 17});                // index out of range
    const MeshTopologyReport r = check_topology(m);
    EXPECT_EQ(r.degenerate_triangles, 3u);
    EXPECT_EQ(r.unreferenced_vertices, 1u);
    EXPECT_FALSE(r.is_closed_manifold());
}

TEST(MeshTopology, SliverThresholdIsScaleFree) {
    // Height 1e-7 over a base of 1: twice the area / longest^2 = 1e-7.
    for (double scale : {1e-3, 1.0, 1e3}) {
        SurfaceMesh m;
        m.vertices = {Vec3(0, 0, 0) * scale, Vec3(1, 0, 0) * scale, Vec3(0.5, 1e-7, 0) * scale};
        m.triangles = {{0, 1, 2}};
        EXPECT_EQ(check_topology(m, 1e-8).degenerate_triangles, 0u) << scale;
        EXPECT_EQ(check_topology(m, 1e-6).degenerate_triangles, 1u) << scale;
    }
}

}  // namespace
// triangle_components labels the pieces check_topology counts: two tetrahedra, the second's
// triangles listed between the first's, and a triangle with a repeated corner (-1).
TEST(MeshTopology, TriangleComponentsLabelEachPieceInOrderOfFirstTriangle) {
    SurfaceMesh m = tetrahedron();
    const SurfaceMesh b = tetrahedron(Vec3(5, 0, 0));
    m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
    m.triangles.insert(m.triangles.begin() + 2, {{4, 6, 5}, {4, 5, 7}, {4, 7, 6}, {5, 6, 7}});
    m.triangles.push_back({0, 0, 1});
    const std::vector<int> label = triangle_components(m);
    EXPECT_EQ(label, (std::vector<int>{0, 0, 1, 1, 1, 1, 0, 0, -1}));
    EXPECT_EQ(check_topology(m).components, 2u);
}

}  // namespace cf
