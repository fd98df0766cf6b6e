// SurfaceClipper's own behaviours (issue 14), on a cell made by hand. A folded cell: dual contouring
// at an adaptivity > 0 occasionally folds a few triangles of a fragment's cell on the bisector of a
// crack gap, deep inside the object; the surface mesher cuts the folded fracture faces out of the
// clipped result and fills the hole, checked against the exact half cube it must give. And the
// result does not depend on the order CGAL happens to list it in.
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/segment/surface_fragments.hpp"
#include "nodes/shape/box.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace cf {
namespace {

int region_id(const SurfaceMesh& m, const std::string& name) {
    for (int r = 0; r < int(m.region_names.size()); ++r)
        if (m.region_names[std::size_t(r)] == name) return r;
    return -1;
}

// The unit cube [0, 1]^3, and a cell that keeps its half x < 1/2: a box reaching 1/2 beyond the
// cube on every other side, whose face x = 1/2 (the fracture face, 0.125 m grid cells) has the
// vertex at (1/2, 1/2, 1/2) pushed 1.6 cells along y within the plane, past its one-ring: its fan
// now overlaps itself and its neighbours (coplanar crossings, as a fold of dual contouring).
struct FoldedCell {
    SurfaceMesh input, cell;
    FoldedCell() {
        BoxSpec cube;
        cube.centre = Vec3(0.5, 0.5, 0.5);
        input = make_box(cube);
        BoxSpec reach;
        reach.size = Vec3(1, 2, 2);
        reach.centre = Vec3(0, 0.5, 0.5);
        reach.subdivisions = 16;
        cell = make_box(reach);
        for (Vec3& p : cell.vertices)
            if ((p - Vec3(0.5, 0.5, 0.5)).norm() < 1e-12) p.y() += 0.2;
    }
};

TEST(SurfaceClip, FoldedFractureFacesAreMendedIntoTheExactHalfCube) {
    const FoldedCell f;
    int moved = 0;
    for (const Vec3& p : f.cell.vertices) moved += (p - Vec3(0.5, 0.7, 0.5)).norm() < 1e-12;
    ASSERT_EQ(moved, 1);
    const SurfaceClipper clipper(f.input);
    SurfaceMesh m;
    std::string problem;
    ASSERT_TRUE(clipper.clip(f.cell, m, &problem)) << problem;
    const MeshTopologyReport topo = check_topology(m, 0.0);
    EXPECT_TRUE(topo.closed() && topo.manifold() && topo.consistently_oriented()) << topo.describe();
    EXPECT_NEAR(signed_volume(m), 0.5, 1e-12);
    // The fracture faces: all on the plane x = 1/2, facing +x (none flipped), covering the unit
    // square once (a fold left in place would add the area of its overlaps).
    const int inside = region_id(m, kInsideRegion);
    ASSERT_GE(inside, 0);
    double area = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        if (m.region_of(t) != inside) continue;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.vertices[std::size_t(m.triangles[t][k])].x(), 0.5, 1e-15);
        const Vec3 n = triangle_normal_unnormalised(m, t);
        EXPECT_GT(n.x(), 0) << "fracture face " << t << " is flipped";
        area += triangle_area(m, t);
    }
    EXPECT_NEAR(area, 1.0, 1e-12);
    // The outer faces are the cube's own, clipped at x = 1/2: on its faces x = 0, y = 0 or 1, z = 0 or 1.
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        if (m.region_of(t) == inside) continue;
        const Vec3 c = triangle_centroid(m, t);
        const double off = std::min({std::abs(c.x()), std::abs(c.y()), std::abs(c.y() - 1), std::abs(c.z()), std::abs(c.z() - 1)});
        EXPECT_LT(off, 1e-15) << "outer face " << t << " is not on the cube";
        EXPECT_LE(c.x(), 0.5);
    }
}

// The same cell listed in another order (vertices and triangles reversed, each triangle's corners
// rotated) gives the same result, value for value: the corefinement's own output order changes
// with it (and from run to run with heap addresses), the clipper's must not.
TEST(SurfaceClip, ResultDoesNotDependOnTheOrderOfTheCell) {
    const FoldedCell f;
    SurfaceMesh shuffled = f.cell;
    const int n = int(shuffled.vertices.size());
    std::reverse(shuffled.vertices.begin(), shuffled.vertices.end());
    std::reverse(shuffled.triangles.begin(), shuffled.triangles.end());
    std::reverse(shuffled.region.begin(), shuffled.region.end());
    for (Tri& t : shuffled.triangles) t = {n - 1 - t[1], n - 1 - t[2], n - 1 - t[0]};
    const SurfaceClipper clipper(f.input);
    SurfaceMesh a, b;
    std::string problem;
    ASSERT_TRUE(clipper.clip(f.cell, a, &problem)) << problem;
    ASSERT_TRUE(clipper.clip(shuffled, b, &problem)) << problem;
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t v = 0; v < a.vertices.size(); ++v) EXPECT_EQ(a.vertices[v], b.vertices[v]) << "vertex " << v;
    for (std::size_t t = 0; t < a.triangles.size(); ++t) {
        EXPECT_EQ(a.triangles[t], b.triangles[t]) << "triangle " << t;
        EXPECT_EQ(a.region_of(t), b.region_of(t)) << "triangle " << t;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(a.corner_uv[t][k], b.corner_uv[t][k]) << "triangle " << t;
    }
}

}  // namespace
}  // namespace cf
