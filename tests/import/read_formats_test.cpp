// Each reader on hand-written files of the unit cube: same vertices, same triangles (fan
// triangulated quads), volume 1 and area 6 exactly (all coordinates are 0 or 1).
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

namespace cf::testing {
namespace {

std::filesystem::path fresh_dir(const std::string& tag) {
    auto d = std::filesystem::temp_directory_path() / "crackflow-tests" / ("import-" + tag);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Triangles as position triples, to compare meshes whose vertex numbering may differ (STL).
std::vector<std::array<Vec3, 3>> triangle_positions(const SurfaceMesh& m) {
    std::vector<std::array<Vec3, 3>> r;
    for (const Tri& t : m.triangles) r.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
    return r;
}

void expect_unit_cube(const SurfaceMesh& m, bool same_numbering, const std::string& region = "default") {
    const SurfaceMesh cube = unit_cube();
    ASSERT_EQ(m.num_vertices(), 8u);
    ASSERT_EQ(m.num_triangles(), 12u);
    if (same_numbering) {
        EXPECT_EQ(m.vertices, cube.vertices);
        EXPECT_EQ(m.triangles, cube.triangles);
    }
    EXPECT_EQ(triangle_positions(m), triangle_positions(cube));
    EXPECT_EQ(signed_volume(m), 1.0);
    EXPECT_EQ(surface_area(m), 6.0);
    ASSERT_EQ(m.region.size(), 12u);
    for (int r : m.region) EXPECT_EQ(r, 0);
    EXPECT_EQ(m.region_names, std::vector<std::string>{region});
    EXPECT_EQ(m.num_regions(), 1);
}

TEST(ReadFormats, ObjQuadsWithSlashesAndRelativeIndices) {
    auto dir = fresh_dir("obj");
    auto r = read_mesh_file(write_file(dir / "cube.obj", cube_obj()));
    expect_unit_cube(r.mesh, true, "all");  // the file's 'g all' (after 'o cube') names every face
    EXPECT_EQ(r.report.file_faces, 6u);
    EXPECT_EQ(r.report.components, 1u);
    EXPECT_EQ(r.report.flipped_triangles, 0u);
}

TEST(ReadFormats, OffAndUpperCaseExtension) {
    auto dir = fresh_dir("off");
    expect_unit_cube(read_mesh(write_file(dir / "cube.off", cube_off())), true);
    expect_unit_cube(read_mesh(write_file(dir / "CUBE.OFF", cube_off())), true);
}

TEST(ReadFormats, OffWithCountsOnHeaderLineAndCrLf) {
    auto dir = fresh_dir("off-crlf");
    std::string s = cube_off();
    s.replace(0, s.find("8 12 0\n") + 7, "OFF 8 12 0\n");
    std::string crlf;
    for (char c : s) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    expect_unit_cube(read_mesh(write_file(dir / "cube.off", crlf)), true);
}

TEST(ReadFormats, PlyAsciiSkipsOtherPropertiesAndElements) {
    auto dir = fresh_dir("ply-ascii");
    expect_unit_cube(read_mesh(write_file(dir / "cube.ply", cube_ply_ascii())), true);
}

TEST(ReadFormats, PlyBinaryBothByteOrders) {
    auto dir = fresh_dir("ply-bin");
    expect_unit_cube(read_mesh(write_file(dir / "le.ply", mesh_ply_binary(unit_cube(), false))), true);
    expect_unit_cube(read_mesh(write_file(dir / "be.ply", mesh_ply_binary(unit_cube(), true))), true);
}

TEST(ReadFormats, PlyBinaryDoublesAreExact) {
    // Coordinates that are not representable in float survive a double PLY bit-exactly.
    SurfaceMesh t = transformed(tetrahedron(), 0.1, Vec3(1.0 / 3.0, -2.0 / 7.0, 1e-7));
    auto dir = fresh_dir("ply-exact");
    for (bool big : {false, true}) {
        SurfaceMesh m = read_mesh(write_file(dir / "t.ply", mesh_ply_binary(t, big)));
        EXPECT_EQ(m.vertices, t.vertices);
        EXPECT_EQ(m.triangles, t.triangles);
    }
}

TEST(ReadFormats, StlAsciiIsWeldedByPosition) {
    auto dir = fresh_dir("stl-ascii");
    auto r = read_mesh_file(write_file(dir / "cube.stl", mesh_stl_ascii(unit_cube())));
    expect_unit_cube(r.mesh, false);
    EXPECT_EQ(r.report.file_vertices, 36u);
    EXPECT_EQ(r.report.welded_vertices, 28u);
}

TEST(ReadFormats, StlBinaryIsWeldedByPosition) {
    auto dir = fresh_dir("stl-bin");
    auto r = read_mesh_file(write_file(dir / "cube.stl", mesh_stl_binary(unit_cube())));
    expect_unit_cube(r.mesh, false);
    // Vertices are numbered by first appearance: triangle 0 is (0, 3, 2) of the cube.
    EXPECT_EQ(r.mesh.triangles[0], (Tri{0, 1, 2}));
    EXPECT_EQ(r.mesh.vertices[1], Vec3(0, 1, 0));
}

TEST(ReadFormats, BinaryStlWhoseHeaderStartsWithSolid) {
    // Some exporters start the binary header with "solid"; the exact size decides.
    std::string b = mesh_stl_binary(unit_cube());
    b.replace(0, 5, "solid");
    auto dir = fresh_dir("stl-solid");
    expect_unit_cube(read_mesh(write_file(dir / "cube.stl", b)), false);
}

TEST(ReadFormats, IsolatedAndDuplicateVertices) {
    // libraries.md's test cube: v8 duplicates v0's position and is used instead of it by one
    // quad, v9 is isolated. Unwelded the cube is open along v0/v8; with welding it is closed.
    std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nv 0 0 0\nv 5 5 5\n"
                      "f 1 4 3 2\nf 5 6 7 8\nf 9 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";
    auto dir = fresh_dir("dup");
    auto path = write_file(dir / "dup.obj", obj);
    EXPECT_TRUE(cf::testing::throws<MeshFileError>([&] { read_mesh(path); }, {"weld_tolerance"}));
    ImportOptions o;
    o.weld_tolerance = 1e-9;
    auto r = read_mesh_file(path, o);
    expect_unit_cube(r.mesh, true);
    EXPECT_EQ(r.report.welded_vertices, 1u);
    EXPECT_EQ(r.report.unreferenced_vertices, 1u);
}

TEST(ReadFormats, WeldToleranceMergesNearbyVertices) {
    // The cube with every second use of a corner moved by 1e-7: welded within 1e-6.
    SurfaceMesh c = unit_cube();
    SurfaceMesh soup;
    for (std::size_t t = 0; t < c.triangles.size(); ++t) {
        Tri f;
        for (int k = 0; k < 3; ++k) {
            f[k] = static_cast<int>(soup.vertices.size());
            soup.vertices.push_back(c.vertices[c.triangles[t][k]] + Vec3::Constant((t + k) % 2 ? 1e-7 : 0.0));
        }
        soup.triangles.push_back(f);
    }
    auto dir = fresh_dir("weld");
    ImportOptions o;
    o.weld_tolerance = 1e-6;
    SurfaceMesh m = read_mesh(write_file(dir / "soup.obj", mesh_obj(soup)), o);
    EXPECT_EQ(m.num_vertices(), 8u);
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-6);
    // Tolerance given in metres applies after scaling: 1e-6 m is 1e-3 file units at scale 1e-3.
    o.scale = 1e-3;
    o.weld_tolerance = 1e-9;  // 1e-6 file units: still merges the 1e-7 offsets
    EXPECT_EQ(read_mesh(dir / "soup.obj", o).num_vertices(), 8u);
    o.weld_tolerance = 1e-11;  // 1e-8 file units: too small, the cube stays open
    EXPECT_THROW(read_mesh(dir / "soup.obj", o), MeshFileError);
}

TEST(ReadFormats, ScaleConvertsFileUnitsToMetres) {
    auto dir = fresh_dir("scale");
    ImportOptions o;
    o.scale = 1e-3;  // file in millimetres
    SurfaceMesh m = read_mesh(write_file(dir / "cube.obj", cube_obj()), o);
    EXPECT_EQ(m.vertices[6], Vec3(1e-3, 1e-3, 1e-3));
    EXPECT_NEAR(signed_volume(m), 1e-9, 1e-24);
}

TEST(ReadFormats, NumbersInMessagesKeepEveryDigit) {
    // Messages print numbers through graph::format_number: six significant digits would show
    // the scale as -1.23457 and ten the vertex as (0.1234567891, 0, 0).
    auto dir = fresh_dir("digits");
    ImportOptions o;
    o.scale = -1.2345678;
    EXPECT_TRUE(cf::testing::throws<MeshFileError>([&] { read_mesh(write_file(dir / "cube.obj", cube_obj()), o); },
                                                   {"scale -1.2345678 is not a positive number"}));
    const auto path = write_file(dir / "repeated.obj", "v 0.1234567891234 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\n");
    EXPECT_TRUE(cf::testing::throws<MeshFileError>(
        [&] { read_mesh(path); }, {"two of its corners are the same vertex at (0.1234567891234, 0, 0)"}));
}

TEST(ReadFormats, PolygonsAreFanTriangulated) {
    // A hexagonal prism: two hexagons and six quads -> 2*4 + 6*2 = 20 triangles.
    std::string obj;
    for (int z = 0; z < 2; ++z)
        for (int k = 0; k < 6; ++k) {
            char line[96];
            std::snprintf(line, sizeof line, "v %.17g %.17g %d\n", std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), z);
            obj += line;
        }
    obj += "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n";
    for (int k = 0; k < 6; ++k) {
        int a = k + 1, b = (k + 1) % 6 + 1;
        obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(b + 6) + " " +
               std::to_string(a + 6) + "\n";
    }
    auto dir = fresh_dir("fan");
    SurfaceMesh m = read_mesh(write_file(dir / "prism.obj", obj));
    ASSERT_EQ(m.num_triangles(), 20u);
    EXPECT_EQ(m.triangles[0], (Tri{5, 4, 3}));
    EXPECT_EQ(m.triangles[3], (Tri{5, 1, 0}));
    // Regular hexagon of circumradius 1: area 3*sqrt(3)/2; prism height 1.
    EXPECT_NEAR(signed_volume(m), 1.5 * std::sqrt(3.0), 1e-14);
}

}  // namespace
}  // namespace cf::testing
