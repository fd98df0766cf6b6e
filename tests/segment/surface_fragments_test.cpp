// The surface mesher (issue 14) against independent truth: the textured box of textured_box.hpp
// (exact UVs and materials in closed form) cut by two planar cracks into four fragments.
#include "graph/atomic_write.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/domain/triangle_closest_point.hpp"
#include "nodes/import/read_mesh.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/segment/fragment_cells.hpp"
#include "nodes/segment/fragment_mesher.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/segment/surface_fragments.hpp"
#include "tests/segment/textured_box.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cf {
namespace {

namespace fs = std::filesystem;

using namespace textured_box;

struct Fixture {
    SurfaceMesh input;
    Fragments fragments;
    std::vector<SurfaceMesh> meshes;
    std::vector<std::string> warnings;
};

const Fixture& fixture() {
    static const Fixture fx = [] {
        Fixture f;
        const fs::path dir = fs::temp_directory_path() / "crackflow-tests" / "surface_fragments";
        fs::create_directories(dir);
        const fs::path obj = dir / "box.obj";
        // Written atomically: ctest -j2 runs these tests as parallel processes, and one re-writing
        // box.obj in place while another read it failed a test now and then.
        graph::write_atomically(obj, [](std::ostream& os) { os << box_obj(); });
        ImportOptions io;
        io.weld_tolerance = 1e-9;
        f.input = read_mesh(obj, io);
        const LevelSet object = level_set_from_mesh(f.input, kRf);
        const CrackLevelSets cracks{kRf, 3, {planar_disk_crack(kP1, kN1, 1.0, kRf), planar_disk_crack(kP2, kN2, 1.0, kRf)}};
        f.fragments = find_fragments(broken_object(object, cracks));
        f.fragments.object = object;  // as segment.fragments sets it: the cells offset the object
        FragmentMesherOptions o;
        o.kind = FragmentMesherKind::surface;
        o.surface = &f.input;
        const FragmentMesher mesher(f.fragments, o);
        for (std::size_t i = 0; i < f.fragments.fragments.size(); ++i) {
            std::string w;
            f.meshes.push_back(mesher.mesh(i, &w));
            if (!w.empty()) f.warnings.push_back(w);
        }
        return f;
    }();
    return fx;
}

int region_id(const SurfaceMesh& m, const std::string& name) {
    for (int r = 0; r < int(m.region_names.size()); ++r)
        if (m.region_names[std::size_t(r)] == name) return r;
    return -1;
}

TEST(SurfaceFragments, ImportKeepsTextureCoordinatesAndMaterials) {
    const SurfaceMesh& in = fixture().input;
    ASSERT_TRUE(in.has_uv());
    ASSERT_EQ(in.num_triangles(), std::size_t(6 * kSplit * kSplit * 2));
    for (std::size_t t = 0; t < in.num_triangles(); ++t) {
        BoxFace face{};
        box_distance(triangle_centroid(in, t), &face);
        EXPECT_EQ(in.region_name(in.region_of(t)), exact_material(face));
        for (int k = 0; k < 3; ++k)
            EXPECT_LT((in.corner_uv[t][k] - exact_uv(in.vertices[std::size_t(in.triangles[t][k])], face)).norm(), 1e-12);
    }
}

TEST(SurfaceFragments, FourClosedManifoldFragmentsWithoutFallBack) {
    const Fixture& f = fixture();
    ASSERT_EQ(f.fragments.fragments.size(), 4u);
    EXPECT_TRUE(f.warnings.empty()) << f.warnings.front();
    for (const SurfaceMesh& m : f.meshes) {
        const MeshTopologyReport topo = check_topology(m, 0.0);
        EXPECT_TRUE(topo.closed() && topo.manifold() && topo.consistently_oriented()) << topo.describe();
        EXPECT_GT(signed_volume(m), 0);
    }
}

// Outer faces: on the input surface (to rounding), with the material and the exact UVs of the face
// they lie on, interpolated where the cracks clipped them.
TEST(SurfaceFragments, OuterFacesCarryTheInputMaterialsAndUvs) {
    const Fixture& f = fixture();
    double worst_uv = 0, worst_distance = 0;
    std::size_t outer = 0;
    for (const SurfaceMesh& m : f.meshes) {
        const int inside = region_id(m, kInsideRegion);
        ASSERT_GE(inside, 0);
        ASSERT_TRUE(m.has_uv());
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            if (m.region_of(t) == inside) continue;
            ++outer;
            BoxFace face{};
            worst_distance = std::max(worst_distance, box_distance(triangle_centroid(m, t), &face));
            EXPECT_EQ(m.region_name(m.region_of(t)), exact_material(face));
            for (int k = 0; k < 3; ++k) {
                const Vec3& p = m.vertices[std::size_t(m.triangles[t][k])];
                worst_distance = std::max(worst_distance, box_distance(p));
                worst_uv = std::max(worst_uv, (m.corner_uv[t][k] - exact_uv(p, face)).norm());
            }
        }
    }
    EXPECT_GT(outer, std::size_t(6 * kSplit * kSplit * 2));  // clipping adds triangles
    EXPECT_LT(worst_distance, 1e-12);  // outer faces lie on the input (one-sided Hausdorff)
    EXPECT_LT(worst_uv, 1e-9);
}

// Inside faces: tagged, near a crack plane (within the half gap + one voxel), box-projected UVs.
TEST(SurfaceFragments, InsideFacesAreTaggedAndLieOnTheCracks) {
    const Fixture& f = fixture();
    InsideUvProjection proj;
    proj.origin = kLo;
    proj.scale = (kHi - kLo).maxCoeff();
    double worst = 0, worst_uv = 0, area = 0;
    for (const SurfaceMesh& m : f.meshes) {
        const int inside = region_id(m, kInsideRegion);
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            if (m.region_of(t) != inside) continue;
            area += triangle_area(m, t);
            const Vec3 c = triangle_centroid(m, t);
            worst = std::max(worst, std::min(std::abs((c - kP1).dot(kN1)), std::abs((c - kP2).dot(kN2))));
            const Vec3 n = triangle_normal(m, t);
            for (int k = 0; k < 3; ++k) {
                const Vec3& p = m.vertices[std::size_t(m.triangles[t][k])];
                worst_uv = std::max(worst_uv, (m.corner_uv[t][k] - proj(p, n)).norm());
            }
        }
    }
    // Both sides of both cracks: twice the cut areas, each at least the box's smallest section.
    EXPECT_GT(area, 2 * 2 * 0.3 * 0.4 * 0.9);
    EXPECT_LT(worst, kRf);
    EXPECT_LT(worst_uv, 1e-12);
}

// Volumes against the level set's: within one voxel layer times the fragment's crack area, plus
// the level set's own error on the outer surface (the rounded edges and corners of the box at r_f,
// measured on the uncut box).
TEST(SurfaceFragments, VolumesMatchTheLevelSetWithinOneVoxelLayerOfCrackArea) {
    const Fixture& f = fixture();
    const double exact_box = (kHi - kLo).prod();
    const double outer_error = std::abs(level_set_volume(level_set_from_mesh(f.input, kRf)) - exact_box);
    double total_mesh = 0;
    for (std::size_t i = 0; i < f.meshes.size(); ++i) {
        const SurfaceMesh& m = f.meshes[i];
        const int inside = region_id(m, kInsideRegion);
        double crack_area = 0;
        for (std::size_t t = 0; t < m.num_triangles(); ++t)
            if (m.region_of(t) == inside) crack_area += triangle_area(m, t);
        const double v = signed_volume(m);
        total_mesh += v;
        EXPECT_LE(std::abs(v - f.fragments.fragments[i].volume), kRf * crack_area + outer_error)
            << "fragment " << i << ": mesh " << v << " m^3, level set " << f.fragments.fragments[i].volume
            << " m^3, crack area " << crack_area << " m^2";
    }
    // The cells meet in the middle of the crack gaps, so the pieces fill the input box, up to where
    // the dual-contoured bisectors of two neighbouring cells differ (a small fraction of a voxel):
    // bound 0.05 r_f times the crack area (half the inside faces' area: each crack has two sides).
    double inside_area = 0;
    for (const SurfaceMesh& m : f.meshes)
        for (std::size_t t = 0; t < m.num_triangles(); ++t)
            if (m.region_of(t) == region_id(m, kInsideRegion)) inside_area += triangle_area(m, t);
    EXPECT_LE(std::abs(total_mesh - exact_box), 0.05 * kRf * 0.5 * inside_area)
        << "pieces " << total_mesh << " m^3, box " << exact_box << " m^3, crack area " << 0.5 * inside_area << " m^2";
}

// Two-sided: every input point is within 0.05 r_f of some fragment's outer faces (the cells meet in
// the crack gaps; their dual-contoured bisectors differ by a small fraction of a voxel). Sampled on
// a 6 x 6 barycentric lattice per input triangle.
TEST(SurfaceFragments, UnionOfOuterFacesCoversTheInput) {
    const Fixture& f = fixture();
    double worst = 0;
    const SurfaceMesh& in = f.input;
    for (std::size_t t = 0; t < in.num_triangles(); ++t)
        for (int a = 0; a <= 6; ++a)
            for (int b = 0; a + b <= 6; ++b) {
            const Vec3 w(a / 6.0, b / 6.0, (6 - a - b) / 6.0);
            const Tri& s = in.triangles[t];
            const Vec3 p = w[0] * in.vertices[std::size_t(s[0])] + w[1] * in.vertices[std::size_t(s[1])] +
                           w[2] * in.vertices[std::size_t(s[2])];
            double best = 1e300;
            for (const SurfaceMesh& m : f.meshes) {
                const int inside = region_id(m, kInsideRegion);
                for (std::size_t u = 0; u < m.num_triangles(); ++u) {
                    if (m.region_of(u) == inside) continue;
                    const Tri& q = m.triangles[u];
                    best = std::min(best, closest_point_on_triangle(p, m.vertices[std::size_t(q[0])], m.vertices[std::size_t(q[1])],
                                                                    m.vertices[std::size_t(q[2])])
                                              .distance2);
                }
            }
            worst = std::max(worst, std::sqrt(best));
        }
    EXPECT_LT(worst, 0.05 * kRf);
    std::cout << "input to outer faces: " << worst / kRf << " r_f\n";
}

// A fragment broken again (rigid-body scenes): the box cut by crack 1, the fragment on crack 1's
// negative side cut by crack 2 from its own level set, its pieces' cells bounded by its cell of the
// first break, the input clipped once per piece. Truth: the pieces keep the first break's fracture
// face (no vertex beyond crack 1's plane farther than the first break's mesh reaches; without the
// bound a cell reaches its margin, 2 r_f, past it), their fracture faces lie on the two planes, they
// are closed, and together they fill that fragment's first-break mesh (volumes within 0.05 r_f times
// the new crack's area, as the four pieces fill the box above).
TEST(SurfaceFragments, AFragmentBrokenAgainKeepsItsFirstFractureFace) {
    const Fixture& f = fixture();
    const LevelSet object = level_set_from_mesh(f.input, kRf);
    Fragments first = find_fragments(broken_object(object, CrackLevelSets{kRf, 3, {planar_disk_crack(kP1, kN1, 1.0, kRf)}}));
    first.object = object;
    ASSERT_EQ(first.fragments.size(), 2u);
    const std::size_t lower = (first.fragments[0].centroid - kP1).dot(kN1) < 0 ? 0 : 1;
    FragmentMesherOptions o;
    o.kind = FragmentMesherKind::surface;
    o.surface = &f.input;
    LevelSet cell;
    std::string warning;
    const SurfaceMesh parent = FragmentMesher(first, o).mesh(lower, &warning, nullptr, &cell);
    ASSERT_TRUE(warning.empty()) << warning;
    ASSERT_FALSE(cell.empty());

    const LevelSet& fragment = first.fragments[lower].grid;  // the broken piece's object, as in a scene
    Fragments second =
        find_fragments(broken_object(fragment, CrackLevelSets{kRf, 3, {planar_disk_crack(kP2, kN2, 1.0, kRf)}}));
    second.object = fragment;
    ASSERT_EQ(second.fragments.size(), 2u);
    o.bound = &cell;
    const FragmentMesher mesher(second, o);
    double beyond = -1, off_planes = 0, volume = 0, new_crack = 0;
    for (std::size_t i = 0; i < 2; ++i) {
        const SurfaceMesh m = mesher.mesh(i, &warning);
        ASSERT_TRUE(warning.empty()) << warning;
        const MeshTopologyReport topo = check_topology(m, 0.0);
        EXPECT_TRUE(topo.closed() && topo.manifold() && topo.consistently_oriented()) << topo.describe();
        volume += signed_volume(m);
        for (const Vec3& p : m.vertices) beyond = std::max(beyond, (p - kP1).dot(kN1));
        const int inside = region_id(m, kInsideRegion);
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            if (m.region_of(t) != inside) continue;
            const Vec3 c = triangle_centroid(m, t);
            const double d1 = std::abs((c - kP1).dot(kN1)), d2 = std::abs((c - kP2).dot(kN2));
            off_planes = std::max(off_planes, std::min(d1, d2));
            if (d2 < d1) new_crack += 0.5 * triangle_area(m, t);  // two sides
        }
    }
    // The first break's fracture face is the dual-contoured bisector of crack 1's gap, off its plane
    // by up to a quarter voxel (the parent mesh's own farthest vertex): no piece goes farther.
    double parent_beyond = -1;
    for (const Vec3& p : parent.vertices) parent_beyond = std::max(parent_beyond, (p - kP1).dot(kN1));
    EXPECT_LT(parent_beyond, 0.3 * kRf);
    EXPECT_LT(beyond, parent_beyond + 0.01 * kRf) << "a piece reaches " << beyond / kRf << " r_f past crack 1's plane, "
                                                  << "its parent " << parent_beyond / kRf << " r_f";
    EXPECT_LT(off_planes, kRf);
    EXPECT_NEAR(volume, signed_volume(parent), 0.05 * kRf * new_crack);
}

TEST(SurfaceFragments, OpenInputIsRejectedWithTheWayOut) {
    SurfaceMesh open = fixture().input;
    open.triangles.pop_back();
    open.region.pop_back();
    try {
        SurfaceClipper c(open);
        FAIL() << "an open input was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("mesher: levelset"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace cf
