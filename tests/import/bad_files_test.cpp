// One test per kind of broken file: each must fail with its own message naming the file (and
// the line or byte offset where there is one) and saying what to do.
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace cf::testing {
namespace {

class BadFiles : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() / "crackflow-tests" / (std::string("import-bad-") + info->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    std::filesystem::path file(const std::string& name, const std::string& bytes) {
        return write_file(dir_ / name, bytes);
    }
    // Reads `name` (written with `bytes`) and expects a MeshFileError containing every
    // fragment; returns the message.
    std::string expect_error(const std::string& name, const std::string& bytes, const std::vector<std::string>& fragments,
                             const ImportOptions& o = {}) {
        const auto path = file(name, bytes);
        try {
            read_mesh(path, o);
        } catch (const MeshFileError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(path.string()), std::string::npos) << "message does not name the file: " << msg;
            for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "missing '" << f << "' in: " << msg;
            return msg;
        }
        ADD_FAILURE() << name << ": no error";
        return {};
    }
    std::filesystem::path dir_;
};

TEST_F(BadFiles, EmptyFile) {
    for (const char* name : {"e.obj", "e.off", "e.ply", "e.stl"}) expect_error(name, "", {": error: file is empty (0 bytes)"});
}

TEST_F(BadFiles, MissingFileAndUnknownExtension) {
    EXPECT_TRUE(cf::testing::throws<MeshFileError>([&] { read_mesh(dir_ / "missing.obj"); }, {"missing.obj: error: file not found"}));
    expect_error("cube.3ds", cube_obj(), {"unknown mesh file extension '.3ds'", "use a .obj, .off, .ply or .stl"});
}

TEST_F(BadFiles, NoFaces) {
    expect_error("points.obj", "v 0 0 0\nv 1 0 0\n", {"no faces found (2 vertices)"});
    expect_error("empty.stl", "solid x\nendsolid x\n", {"no faces found"});
}

TEST_F(BadFiles, BinaryStlTruncated) {
    std::string b = mesh_stl_binary(unit_cube());
    b.resize(b.size() - 30);
    expect_error("cut.stl", b, {"binary STL header declares 12 triangles, which need 684 bytes, but the file has 654 bytes (truncated?)"});
}

TEST_F(BadFiles, BinaryStlHugeCountIsRejectedBeforeAllocating) {
    std::string b = mesh_stl_binary(tetrahedron());
    const std::uint32_t n = 4000000000u;
    std::memcpy(&b[80], &n, 4);
    const auto t0 = std::chrono::steady_clock::now();
    expect_error("huge.stl", b, {"declares 4000000000 triangles, which need 200000000084 bytes", "truncated?"});
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.5);
}

TEST_F(BadFiles, TooShortForStl) {
    expect_error("tiny.stl", std::string(40, '\1'), {"40 bytes: too short for binary STL"});
}

TEST_F(BadFiles, PlyHugeCountIsRejectedBeforeAllocating) {
    std::string p = mesh_ply_binary(tetrahedron(), false);
    p.replace(p.find("element vertex 4"), 16, "element vertex 4000000000");
    expect_error("huge.ply", p, {"header declares elements needing at least", "truncated?"});
    std::string a = cube_ply_ascii();
    a.replace(a.find("element face 6"), 14, "element face 4000000000");
    expect_error("huge_ascii.ply", a, {"header declares elements needing at least"});
}

TEST_F(BadFiles, PlyBinaryTruncatedInsideData) {
    std::string p = mesh_ply_binary(tetrahedron(), false);
    p.resize(p.size() - 2);  // cut inside the last face's last index
    const std::size_t last_face = p.size() + 2 - 13;
    expect_error("cut.ply", p, {"cut.ply: byte " + std::to_string(last_face + 9), "file ends inside list entry"});
}

TEST_F(BadFiles, PlyAsciiTruncated) {
    std::string a = cube_ply_ascii();
    a.resize(a.find("4 1 2 6 5"));
    expect_error("cut.ply", a, {"cut.ply:27: error: file ends inside list length (truncated?)"});
}

TEST_F(BadFiles, PlyHeaderProblems) {
    expect_error("nomagic.ply", "format ascii 1.0\n", {"nomagic.ply:1: error: missing 'ply' magic line"});
    expect_error("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", {"no end_header line"});
    expect_error("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", {"fmt.ply:2: error: unknown format"});
    expect_error("nofaces.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                "property float z\nend_header\n0 0 0\n",
                 {"no element 'face'", "point cloud"});
    expect_error("floatidx.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n",
                 {"floatidx.ply:4: error: face vertex indices have a floating-point type"});
}

TEST_F(BadFiles, OffTruncated) {
    std::string o = cube_off();
    o.resize(o.rfind("3 ", o.rfind("3 ") - 1));  // drop the last two faces
    expect_error("cut.off", o, {"cut.off: error: file ends after 10 of 12 faces (truncated?)"});
    std::string v = "OFF\n8 12 0\n0 0 0\n1 0 0\n";
    expect_error("cutv.off", v, {"declares 8 vertices and 12 faces but only"});
    expect_error("cutv2.off", v + std::string(200, ' '), {"file ends after 2 of 8 vertices"});
}

TEST_F(BadFiles, OffHeaderProblems) {
    expect_error("nohead.off", "8 12 0\n", {"nohead.off:1: error: missing 'OFF' header line"});
    expect_error("counts.off", "OFF\neight 12 0\n", {"counts.off:2: error: expected vertex and face counts"});
    expect_error("bin.off", "OFF BINARY\n", {"binary OFF is not supported"});
}

TEST_F(BadFiles, NanAndInfCoordinates) {
    std::string obj = cube_obj();
    obj.replace(obj.find("v 1 1 0"), 7, "v 1 nan 0");
    expect_error("nan.obj", obj, {"nan.obj:5: error: vertex coordinate is nan", "replace NaN/Inf"});
    std::string off = cube_off();
    off.replace(off.find("1 1 1\n"), 5, "1 inf 1");
    expect_error("inf.off", off, {"inf.off:10: error: vertex coordinate is inf"});
    expect_error("word.obj", "v 1 abc 0\n", {"word.obj:1: error: 'abc' is not a finite number"});
    expect_error("bytes.obj", "v 1 \x7f\xff 0\n", {"bytes.obj:1: error: '\\x7f\\xff' is not a finite number"});
    expect_error("huge.obj", "v 1 1e999 0\n", {"huge.obj:1: error: '1e999' is not a finite number"});

    SurfaceMesh t = tetrahedron();
    t.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
    expect_error("nan.stl", mesh_stl_binary(t), {"nan.stl: byte 84: error: triangle 0 has a NaN or infinite coordinate"});
    expect_error("nan.ply", mesh_ply_binary(t, true), {"nan.ply: byte", "vertex 2 has a NaN or infinite coordinate"});
    std::string ascii = mesh_stl_ascii(t);
    expect_error("nan_ascii.stl", ascii, {"nan_ascii.stl:5: error: vertex coordinate is nan"});
}

TEST_F(BadFiles, IndexOutOfRange) {
    std::string obj = cube_obj();
    obj.replace(obj.find("f 3 4 8 7"), 9, "f 3 4 9 7");
    expect_error("oob.obj", obj, {"oob.obj:16: error: face index 9 out of range (file has 8 vertices", "fix the index"});
    std::string off = cube_off();
    off.replace(off.find("3 0 3 2"), 7, "3 0 3 8");
    expect_error("oob.off", off, {"oob.off:12: error: face index 8 out of range (file has 8 vertices, valid indices are 0..7)"});
    std::string ply = cube_ply_ascii();
    ply.replace(ply.find("4 0 1 5 4"), 9, "4 0 1 5 -4");
    expect_error("neg.ply", ply, {"neg.ply:25: error: negative face index -4 out of range"});
    std::string neg = cube_off();
    neg.replace(neg.find("3 0 3 2"), 7, "3 0 -1 2");
    expect_error("neg.off", neg, {"neg.off:12: error: negative face index -1"});
    expect_error("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n",
                 {"rel.obj:4: error: relative face index -4 points before the first vertex (only 3 vertices"});
    expect_error("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", {"zero.obj:4: error: face index 0 is invalid"});
    SurfaceMesh t = tetrahedron();
    t.triangles[3][2] = 1000;
    expect_error("oob_le.ply", mesh_ply_binary(t, false), {"oob_le.ply: byte", "face index 1000 out of range (file has 4 vertices"});
}

TEST_F(BadFiles, FaceWithTooFewCorners) {
    expect_error("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", {"two.obj:3: error: face has 2 vertices"});
}

TEST_F(BadFiles, MalformedStructure) {
    std::string stl = mesh_stl_ascii(tetrahedron());
    stl.replace(stl.find("outer loop"), 10, "outer lop");
    expect_error("typo.stl", stl, {"typo.stl:3: error: expected 'outer loop'"});
    std::string cut = mesh_stl_ascii(tetrahedron());
    cut.resize(cut.find("endsolid"));
    expect_error("noend.stl", cut, {"file ends inside a solid"});
    expect_error("corner.obj", "v 0 0 0\nf 1 x 2\n", {"corner.obj:2: error: face corner 'x' is not a vertex index"});
}

TEST_F(BadFiles, DegenerateTriangles) {
    // A tetrahedron plus a triangle that repeats a vertex; then one whose corners are collinear.
    std::string rep = mesh_obj(tetrahedron()) + "f 1 2 2\n";
    expect_error("rep.obj", rep, {"rep.obj:9: error: degenerate triangle: two of its corners are the same vertex at (1, 0, 0)"});
    std::string line = mesh_obj(tetrahedron()) + "v 2 0 0\nf 1 2 5\n";
    expect_error("flat.obj", line,
                 {"flat.obj:10: error: degenerate triangle with zero area: corners (0, 0, 0), (1, 0, 0), (2, 0, 0)"});
    // In STL, corners equal after welding by position.
    SurfaceMesh t = tetrahedron();
    t.triangles.push_back({0, 1, 0});
    expect_error("rep.stl", mesh_stl_binary(t), {"rep.stl: byte 284: error: degenerate triangle", "welded"});
}

TEST_F(BadFiles, NonManifoldEdge) {
    // Two tetrahedra sharing the edge (0,0,0)-(1,0,0): four triangles on one edge.
    SurfaceMesh b = tetrahedron();
    b.vertices = {{0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    ImportOptions weld;
    weld.weld_tolerance = 1e-12;
    expect_error("fin.obj", mesh_obj(merged(tetrahedron(), b)),
                 {"non-manifold edge: the edge from (0, 0, 0) to (1, 0, 0) is shared by 4 triangles",
                  "fin.obj:9: error", "(line 9, line 10, line 13, line 14)"},
                 weld);
}

TEST_F(BadFiles, NonManifoldVertex) {
    // Two tetrahedra touching only at the origin (the second one mirrored through it).
    SurfaceMesh b = tetrahedron();
    for (Vec3& p : b.vertices) p = -p;
    for (Tri& t : b.triangles) std::swap(t[1], t[2]);  // mirroring reverses orientation
    ImportOptions weld;
    weld.weld_tolerance = 1e-12;
    expect_error("touch.obj", mesh_obj(merged(tetrahedron(), b)), {"touch.obj:13: error: non-manifold vertex at (0, 0, 0): separate sheets of the surface touch only at this point (line 9 and this triangle)"}, weld);
}

TEST_F(BadFiles, OpenBoundary) {
    SurfaceMesh c = unit_cube();
    c.triangles.erase(c.triangles.begin() + 2, c.triangles.begin() + 4);  // drop the top quad
    expect_error("open.obj", mesh_obj(c),
                 {"open.obj:12: error: the surface is open: 4 edges are used by only one triangle, e.g. the edge from "
                  "(0, 0, 1) to (1, 0, 1) of this triangle",
                  "fill the holes"});
}

TEST_F(BadFiles, InconsistentOrientation) {
    expect_error("flip.obj", mesh_obj(with_flipped(unit_cube(), {5})),
                 {"flip.obj:17: error: inconsistent orientation: the triangles at line 14 and line 17 traverse the edge "
                  "from (0, 0, 0) to (0, 0, 1) in the same direction",
                  "set reorient: true"});
}

TEST_F(BadFiles, InsideOut) {
    SurfaceMesh c = with_flipped(unit_cube(), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
    // The signed volume, summed over the 12 triangles in double, comes out 1.1e-16 short of -1; the
    // message prints that double exactly (six significant digits used to round it to -1).
    expect_error("inv.off", [&] {
        std::string s = "OFF\n8 12 0\n";
        for (const Vec3& p : c.vertices) s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
        for (const Tri& t : c.triangles) s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
        return s;
    }(), {"inv.off:11: error: the surface is inside-out: its normals point inwards (signed volume -0.9999999999999999 cubic "
          "file units",
       "set reorient: true"});
}

TEST_F(BadFiles, NonOrientable) {
    // The 6-vertex real projective plane (hemi-icosahedron): closed, manifold, non-orientable.
    // Vertices on the moment curve (t, t^2, t^3), so no three are collinear.
    std::string obj;
    for (int t = 1; t <= 6; ++t) obj += "v " + std::to_string(t) + " " + std::to_string(t * t) + " " + std::to_string(t * t * t) + "\n";
    obj += "f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 6\nf 1 6 2\nf 2 3 5\nf 3 4 6\nf 4 5 2\nf 5 6 3\nf 6 2 4\n";
    expect_error("rp2.obj", obj, {"inconsistent orientation"});
    ImportOptions o;
    o.reorient = true;
    expect_error("rp2.obj", obj, {"non-orientable", "Moebius"}, o);
}

TEST_F(BadFiles, ZeroVolumeShell) {
    expect_error("sheet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n", {"sheet.obj:4: error: the closed shell", "encloses no volume"});
}

TEST_F(BadFiles, CavityFacingTheWrongWay) {
    // A unit cube inside a cube of side 3, both outward: the inner one should face inwards.
    SurfaceMesh outer = transformed(unit_cube(), 3, Vec3(-1, -1, -1));
    expect_error("cavity.obj", mesh_obj(merged(outer, unit_cube())),
                 {"cavity.obj:29: error: the closed shell containing this triangle lies inside 1 other shell(s)"});
}

}  // namespace
}  // namespace cf::testing
