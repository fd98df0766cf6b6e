// reorient: consistent orientation per shell by breadth-first search, then outward (or into
// the cavity, for nested shells), checked against the closed-form volumes.
#include "nodes/import/check_closed_surface.hpp"
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"

#include <gtest/gtest.h>

#include <map>

namespace cf::testing {
namespace {

// Every interior edge traversed once in each direction.
bool consistently_oriented(const SurfaceMesh& m) {
    std::map<std::pair<int, int>, int> directed;
    for (const Tri& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : directed)
        if (n != 1 || directed.count({e.second, e.first}) == 0) return false;
    return true;
}

SurfaceCheckResult check(SurfaceMesh& m, bool reorient) {
    return check_closed_surface(m.vertices, m.triangles, "mesh", {}, reorient);
}

TEST(Reorient, FlipsTheInconsistentFaces) {
    SurfaceMesh m = with_flipped(unit_cube(), {5, 9});
    EXPECT_THROW(check(m, false), MeshFileError);
    auto r = check(m, true);
    EXPECT_EQ(r.flipped_triangles, 2u);
    EXPECT_EQ(r.components, 1u);
    EXPECT_TRUE(consistently_oriented(m));
    EXPECT_EQ(m.triangles, unit_cube().triangles);
}

TEST(Reorient, BreadthFirstSearchKeepsTheFirstTriangleAndThenFixesTheSign) {
    // All but triangle 0 flipped: BFS from triangle 0 flips the other 11 to match it, which
    // restores the cube exactly (volume +1, no sign fix needed).
    std::vector<int> all_but_first{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    SurfaceMesh m = with_flipped(unit_cube(), all_but_first);
    auto r = check(m, true);
    EXPECT_EQ(r.flipped_triangles, 11u);
    EXPECT_EQ(m.triangles, unit_cube().triangles);
    // Only triangle 0 flipped: BFS makes the rest agree with the wrong first triangle (11
    // flips), the shell comes out inside-out and is flipped as a whole (12 flips): net 1.
    SurfaceMesh n = with_flipped(unit_cube(), {0});
    r = check(n, true);
    EXPECT_EQ(r.flipped_triangles, 1u);
    EXPECT_EQ(n.triangles, unit_cube().triangles);
    EXPECT_EQ(signed_volume(n), 1.0);
}

TEST(Reorient, InsideOutShellIsFlipped) {
    SurfaceMesh m = with_flipped(tetrahedron(), {0, 1, 2, 3});
    EXPECT_THROW(check(m, false), MeshFileError);
    auto r = check(m, true);
    EXPECT_EQ(r.flipped_triangles, 4u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0);
}

TEST(Reorient, SeparateShellsAreEachOutward) {
    // Two disjoint cubes, the second inside-out; with reorient only the second is flipped.
    SurfaceMesh inv = with_flipped(transformed(unit_cube(), 1, Vec3(2, 0, 0)), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
    SurfaceMesh m = merged(unit_cube(), inv);
    EXPECT_THROW(check(m, false), MeshFileError);
    auto r = check(m, true);
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(r.flipped_triangles, 12u);
    EXPECT_EQ(signed_volume(m), 2.0);
}

TEST(Reorient, CavityFacesInwards) {
    // Hollow cube: side 3 outside, unit cavity inside: volume 27 - 1 = 26.
    SurfaceMesh outer = transformed(unit_cube(), 3, Vec3(-1, -1, -1));
    SurfaceMesh good = merged(outer, with_flipped(unit_cube(), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}));
    SurfaceMesh m = good;
    auto r = check(m, false);  // already right: accepted as is
    EXPECT_EQ(r.components, 2u);
    EXPECT_EQ(signed_volume(m), 26.0);
    SurfaceMesh wrong = merged(outer, unit_cube());
    EXPECT_THROW(check(wrong, false), MeshFileError);
    r = check(wrong, true);
    EXPECT_EQ(r.flipped_triangles, 12u);
    EXPECT_EQ(wrong.triangles, good.triangles);
    EXPECT_EQ(signed_volume(wrong), 26.0);
}

TEST(Reorient, ThroughTheReader) {
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / "import-reorient";
    std::filesystem::create_directories(dir);
    auto path = write_file(dir / "flip.obj", mesh_obj(with_flipped(unit_cube(), {3, 4, 7})));
    ImportOptions o;
    o.reorient = true;
    auto r = read_mesh_file(path, o);
    EXPECT_EQ(r.report.flipped_triangles, 3u);
    EXPECT_EQ(r.mesh.triangles, unit_cube().triangles);
}

}  // namespace
}  // namespace cf::testing
