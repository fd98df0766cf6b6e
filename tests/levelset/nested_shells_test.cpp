// Objects with cavities (issue 16): a closed mesh whose inner shell faces into a cavity keeps the
// cavity in its level set (mesh-to-volume's flood fill used to fill it: 0.998 m^3 instead of 0.657)
// and the BEM remesh keeps both surfaces; an inner shell facing the wrong way gets the
// re-orientation hint.
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/shape/icosphere.hpp"
#include "nodes/simplify/remesh.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <numeric>

namespace cf {
namespace {

SurfaceMesh flipped(SurfaceMesh m) {
    for (Tri& t : m.triangles) std::swap(t[1], t[2]);
    return m;
}

// Connected shells of a mesh, each with its signed volume [m^3] and its vertices' distances
// from the origin (smallest, largest).
struct ShellFigures {
    double volume;
    double r_min, r_max;
};
std::vector<ShellFigures> shell_figures(const SurfaceMesh& m) {
    std::vector<int> parent(m.vertices.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> find = [&](int v) { return parent[v] == v ? v : parent[v] = find(parent[v]); };
    for (const Tri& t : m.triangles) parent[find(t[1])] = parent[find(t[2])] = find(t[0]);
    std::map<int, ShellFigures> by_root;
    for (const Tri& t : m.triangles) {
        auto [it, fresh] = by_root.emplace(find(t[0]), ShellFigures{0, INFINITY, 0});
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        it->second.volume += a.dot(b.cross(c)) / 6;
        for (const Vec3* p : {&a, &b, &c}) {
            it->second.r_min = std::min(it->second.r_min, p->norm());
            it->second.r_max = std::max(it->second.r_max, p->norm());
        }
    }
    std::vector<ShellFigures> out;
    for (const auto& [root, f] : by_root) out.push_back(f);
    std::sort(out.begin(), out.end(), [](const ShellFigures& a, const ShellFigures& b) { return a.r_max > b.r_max; });
    return out;
}

constexpr double kRf = 0.02;

// A 1 m cube with a 0.7 m cubic cavity: 1 - 0.343 = 0.657 m^3.
TEST(NestedShells, HollowCubeKeepsItsCavityAndBothSurfaces) {
    const SurfaceMesh hollow = testmesh::merge(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)),
                                               flipped(testmesh::box(Vec3::Constant(-0.35), Vec3::Constant(0.35))));
    ASSERT_NEAR(signed_volume(hollow), 0.657, 1e-12);
    const LevelSet ls = level_set_from_mesh(hollow, kRf);
    // Grid volume within a tenth of a voxel layer over both surfaces (6 m^2 + 2.94 m^2).
    EXPECT_NEAR(level_set_volume(ls), 0.657, 0.1 * kRf * (6 + 2.94));
    EXPECT_GT(sample(ls, Vec3::Zero()), 0.0) << "the cavity's centre must be outside the object";
    EXPECT_LT(sample(ls, Vec3(0.42, 0, 0)), 0.0) << "the wall is inside";
    EXPECT_NEAR(sample(ls, Vec3(0.34, 0, 0)), 0.01, 0.1 * kRf) << "1 cm from the cavity wall, in the cavity";

    // The remesh on a coarser grid: QEM on large flat faces is slow (46k dense triangles took ~55 s).
    RemeshOptions o;
    o.target_triangles = 800;
    o.offset_voxels = 0;
    const RemeshResult r = remesh(level_set_from_mesh(hollow, 2 * kRf), o);
    const auto shells = shell_figures(r.mesh);
    ASSERT_EQ(shells.size(), 2u) << "the remesh must keep the outer and the cavity surface";
    EXPECT_GT(shells[0].volume, 0.0);
    EXPECT_LT(shells[1].volume, 0.0) << "the cavity surface faces into the cavity";
    EXPECT_NEAR(shells[0].volume, 1.0, 0.02);
    EXPECT_NEAR(-shells[1].volume, 0.343, 0.02);
    EXPECT_NEAR(signed_volume(r.mesh), 0.657, 0.03);
}

// A sphere of radius 0.5 m with a spherical cavity of radius 0.3 m: 4/3 pi (0.125 - 0.027) m^3.
TEST(NestedShells, HollowSphereKeepsItsCavityAndBothSurfaces) {
    SphereSpec outer, inner;
    outer.radius = 0.5;
    outer.level = 5;
    inner.radius = 0.3;
    inner.level = 5;
    const SurfaceMesh hollow = testmesh::merge(make_icosphere(outer), flipped(make_icosphere(inner)));
    const double exact = 4.0 / 3.0 * M_PI * (0.125 - 0.027);
    const double area = 4 * M_PI * (0.25 + 0.09);
    ASSERT_NEAR(signed_volume(hollow), exact, 1e-3 * exact);  // the polyhedra are close to the spheres
    const LevelSet ls = level_set_from_mesh(hollow, kRf);
    EXPECT_NEAR(level_set_volume(ls), exact, 0.1 * kRf * area);
    EXPECT_GT(sample(ls, Vec3::Zero()), 0.0);
    EXPECT_NEAR(sample(ls, Vec3(0, 0.35, 0)), -0.05, 0.1 * kRf) << "half-way into the wall";

    RemeshOptions o;
    o.target_triangles = 2000;
    o.offset_voxels = 0;
    const RemeshResult r = remesh(ls, o);
    const auto shells = shell_figures(r.mesh);
    ASSERT_EQ(shells.size(), 2u) << "the remesh must keep the outer and the cavity surface";
    EXPECT_NEAR(shells[0].r_max, 0.5, kRf);
    EXPECT_NEAR(shells[1].r_min, 0.3, kRf);
    EXPECT_LT(shells[1].volume, 0.0);
    EXPECT_NEAR(signed_volume(r.mesh) / exact, 1.0, 0.03);
}

// An inner shell facing outwards (a solid inside a solid) is refused with the re-orientation hint.
TEST(NestedShells, CavityFacingTheWrongWayGetsTheReorientationHint) {
    const SurfaceMesh wrong = testmesh::merge(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)),
                                              testmesh::box(Vec3::Constant(-0.35), Vec3::Constant(0.35)));
    try {
        level_set_from_mesh(wrong, kRf);
        FAIL() << "accepted";
    } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("cavity"), std::string::npos) << m;
        EXPECT_NE(m.find("reorient: true"), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace cf
