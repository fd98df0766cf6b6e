// Write then read gives the same mesh: bit-exact coordinates for every ASCII format (shortest
// round-trip decimal text) and for binary PLY (doubles); binary STL stores float32, so it is
// bit-exact for float-representable coordinates and rounds others to the nearest float.
#include "nodes/export/mesh_writers.hpp"
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <random>
#include <sstream>

namespace cf::testing {
namespace {

std::filesystem::path fresh_dir(const std::string& tag) {
    auto d = std::filesystem::temp_directory_path() / "crackflow-tests" / ("export-" + tag);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Cubes with every vertex moved by a random amount up to 0.1 (still closed and outward):
// 24 arbitrary doubles each, most with 17 significant digits.
std::vector<SurfaceMesh> random_cubes(int n) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    std::vector<SurfaceMesh> r;
    for (int i = 0; i < n; ++i) {
        SurfaceMesh m = transformed(unit_cube(), std::pow(10.0, i % 7 - 3), Vec3(u(rng), u(rng), u(rng)));
        for (Vec3& p : m.vertices) p += Vec3(u(rng), u(rng), u(rng)) * std::pow(10.0, i % 7 - 3);
        m.region.assign(m.triangles.size(), 0);
        for (std::size_t t = 6; t < m.triangles.size(); ++t) m.region[t] = 1;
        m.region_names = {"outside", "loaded"};
        r.push_back(m);
    }
    return r;
}

std::vector<std::array<Vec3, 3>> triangle_positions(const SurfaceMesh& m) {
    std::vector<std::array<Vec3, 3>> r;
    for (const Tri& t : m.triangles) r.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
    return r;
}

struct Case {
    const char* file;
    MeshFormat format;
    bool binary;
};

TEST(RoundTrip, IndexedFormatsAreBitExact) {
    auto dir = fresh_dir("indexed");
    const Case cases[] = {{"m.obj", MeshFormat::Obj, false}, {"m.off", MeshFormat::Off, false},
                          {"a.ply", MeshFormat::Ply, false}, {"b.ply", MeshFormat::Ply, true}};
    for (const SurfaceMesh& m : random_cubes(35))
        for (const Case& c : cases) {
            write_mesh_file(dir / c.file, m, c.format, c.binary);
            SurfaceMesh back = read_mesh(dir / c.file);
            ASSERT_EQ(back.vertices, m.vertices) << c.file;
            ASSERT_EQ(back.triangles, m.triangles) << c.file;
        }
}

TEST(RoundTrip, AsciiStlIsBitExact) {
    auto dir = fresh_dir("stl-ascii");
    for (const SurfaceMesh& m : random_cubes(35)) {
        write_mesh_file(dir / "m.stl", m, MeshFormat::Stl, false);
        SurfaceMesh back = read_mesh(dir / "m.stl");
        EXPECT_EQ(back.num_vertices(), 8u);  // welded again
        ASSERT_EQ(triangle_positions(back), triangle_positions(m));
    }
}

TEST(RoundTrip, BinaryStlIsBitExactForFloats) {
    auto dir = fresh_dir("stl-binary");
    // Coordinates that are exact in float32: multiples of 1/8 plus a float-exact shift.
    SurfaceMesh m = transformed(unit_cube(), 0.125, Vec3(0.5, -0.25, 3.0));
    write_mesh_file(dir / "m.stl", m, MeshFormat::Stl, true);
    EXPECT_EQ(std::filesystem::file_size(dir / "m.stl"), 84u + 50u * 12u);
    EXPECT_EQ(triangle_positions(read_mesh(dir / "m.stl")), triangle_positions(m));
    // Other doubles come back as the nearest float.
    for (const SurfaceMesh& r : random_cubes(7)) {
        write_mesh_file(dir / "r.stl", r, MeshFormat::Stl, true);
        SurfaceMesh rounded = r;
        for (Vec3& p : rounded.vertices) p = p.cast<float>().cast<double>();
        EXPECT_EQ(triangle_positions(read_mesh(dir / "r.stl")), triangle_positions(rounded));
    }
}

TEST(RoundTrip, SmallTetrahedronInMillimetres) {
    // A 1 mm tetrahedron far from the origin: the text must keep all digits for the volume to
    // survive (1/6 mm^3 out of coordinates ~1e3 m).
    SurfaceMesh t = transformed(tetrahedron(), 1e-3, Vec3(1234.5678901234567, -987.65432109876543, 0.1));
    auto dir = fresh_dir("tiny");
    for (const Case& c : {Case{"t.obj", MeshFormat::Obj, false}, Case{"t.ply", MeshFormat::Ply, false},
                          Case{"t.off", MeshFormat::Off, false}}) {
        write_mesh_file(dir / c.file, t, c.format, c.binary);
        SurfaceMesh back = read_mesh(dir / c.file);
        EXPECT_EQ(back.vertices, t.vertices) << c.file;
        EXPECT_EQ(signed_volume(back), signed_volume(t)) << c.file;
    }
}

TEST(RoundTrip, WritingIsDeterministic) {
    SurfaceMesh m = random_cubes(1)[0];
    for (const Case& c : {Case{"", MeshFormat::Obj, false}, Case{"", MeshFormat::Ply, true}, Case{"", MeshFormat::Stl, true}}) {
        std::ostringstream a, b;
        if (c.format == MeshFormat::Obj) write_obj(a, m), write_obj(b, m);
        if (c.format == MeshFormat::Ply) write_ply(a, m, true), write_ply(b, m, true);
        if (c.format == MeshFormat::Stl) write_stl(a, m, true), write_stl(b, m, true);
        EXPECT_EQ(a.str(), b.str());
    }
}

TEST(Writers, FileContents) {
    SurfaceMesh t = tetrahedron();
    t.region = {0, 0, 1, 1};
    t.region_names = {"outside", "loaded"};
    std::ostringstream obj, off, ply, stl;
    write_obj(obj, t);
    EXPECT_EQ(obj.str(),
              "# crackflow surface mesh: 4 vertices, 4 triangles\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
              "g outside\nf 1 3 2\nf 1 2 4\ng loaded\nf 1 4 3\nf 2 3 4\n");
    write_off(off, t);
    EXPECT_EQ(off.str(), "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    write_ply(ply, t, false);
    EXPECT_NE(ply.str().find("comment crackflow surface mesh; region names: 0=outside 1=loaded\n"), std::string::npos);
    EXPECT_NE(ply.str().find("end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 0\n3 0 1 3 0\n3 0 3 2 1\n3 1 2 3 1\n"),
              std::string::npos);
    write_stl(stl, t, false);
    // The last facet, the slanted face (1,2,3), has unit normal (1,1,1)/sqrt(3).
    const std::string text = stl.str();
    std::istringstream last(text.substr(text.rfind("facet normal ") + 13));
    double nx, ny, nz;
    last >> nx >> ny >> nz;
    for (double c : {nx, ny, nz}) EXPECT_NEAR(c, 1 / std::sqrt(3.0), 1e-16);
    EXPECT_EQ(text.substr(0, 16), "solid crackflow\n");
}

// The OBJ's lines are formatted in pieces of 16384 on parallel tasks: a mesh of several pieces, with
// groups starting right before, at and after piece boundaries and a group running across one, gives
// the text of a plain serial loop (to_chars numbers), byte for byte.
TEST(Writers, ObjInPiecesIsTheSerialText) {
    SurfaceMesh m;
    const int n = 40000;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < n + 2; ++i) m.vertices.emplace_back(u(rng), u(rng) * 1e-3, u(rng) * 1e5);
    for (int t = 0; t < n; ++t) m.triangles.push_back({t, t + 1, t + 2});
    m.region_names = {"outside", "inside", "loaded"};
    for (int t = 0; t < n; ++t) {
        int r = (t / 1000) % 2;
        if (t == 16383 || t == 16384 || t == 32768) r = 2;
        if (t >= 30000 && t < 36000) r = 1;  // across the boundary at 32768 (but for its one triangle)
        m.region.push_back(r);
    }
    std::ostringstream got;
    write_obj(got, m, "frag.mtl");
    auto num = [](auto v) {
        char b[32];
        return std::string(b, std::to_chars(b, b + sizeof b, v).ptr);
    };
    std::string want = "# crackflow surface mesh: " + num(n + 2) + " vertices, " + num(n) + " triangles\nmtllib frag.mtl\n";
    for (const Vec3& p : m.vertices) want += "v " + num(p.x()) + " " + num(p.y()) + " " + num(p.z()) + "\n";
    int group = -1;
    for (int t = 0; t < n; ++t) {
        if (m.region[std::size_t(t)] != group) {
            group = m.region[std::size_t(t)];
            want += "g " + m.region_names[std::size_t(group)] + "\nusemtl " + m.region_names[std::size_t(group)] + "\n";
        }
        const Tri& f = m.triangles[std::size_t(t)];
        want += "f " + num(f[0] + 1) + " " + num(f[1] + 1) + " " + num(f[2] + 1) + "\n";
    }
    EXPECT_EQ(got.str().size(), want.size());
    EXPECT_TRUE(got.str() == want);
}

// Corner UVs and normals: one vt / vn per distinct value (exact; -0 and +0 are one value), in order
// of first use, and every corner reads back as written.
TEST(Writers, ObjCornerAttributesAreSharedInOrderOfFirstUse) {
    SurfaceMesh m = unit_cube();
    const std::array<Vec2, 4> uv = {Vec2(0.25, 0.5), Vec2(-0.0, 1.0 / 3), Vec2(0.0, 1.0 / 3), Vec2(0.75, 0.1)};
    m.corner_uv.resize(m.triangles.size());
    m.corner_normal.resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            m.corner_uv[t][std::size_t(k)] = uv[(t + std::size_t(k)) % 4];
            m.corner_normal[t][std::size_t(k)] = triangle_normal(m, t);
        }
    std::ostringstream os;
    write_obj(os, m);
    const std::string text = os.str();
    std::vector<std::string> vt;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (line.rfind("vt ", 0) == 0) vt.push_back(line);
    // Triangle 0 uses uv 0, 1 (-0), 2 (+0, the same value): vt lines 0.25 0.5, -0 ..., then 0.75 0.1.
    ASSERT_EQ(vt.size(), 3u) << text;
    EXPECT_EQ(vt[0], "vt 0.25 0.5");
    EXPECT_EQ(vt[1].rfind("vt -0 0.333", 0), 0u) << vt[1];  // the first of -0 / +0 seen is written
    EXPECT_EQ(vt[2], "vt 0.75 0.1");
    const auto dir = fresh_dir("obj-corners");
    write_mesh_file(dir / "c.obj", m, MeshFormat::Obj, false);
    const SurfaceMesh back = read_mesh(dir / "c.obj");
    ASSERT_TRUE(back.has_uv() && back.has_normals());
    ASSERT_EQ(back.triangles.size(), m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(back.corner_uv[t][std::size_t(k)], m.corner_uv[t][std::size_t(k)]) << t;
            EXPECT_EQ(back.corner_normal[t][std::size_t(k)], m.corner_normal[t][std::size_t(k)]) << t;
        }
}

TEST(Writers, BinaryStlHeaderDoesNotStartWithSolid) {
    std::ostringstream os;
    write_stl(os, tetrahedron(), true);
    EXPECT_NE(os.str().substr(0, 5), "solid");
    EXPECT_EQ(os.str().size(), 84u + 4u * 50u);
}

TEST(Writers, RejectBrokenMeshes) {
    SurfaceMesh m = tetrahedron();
    m.triangles[1][2] = 4;
    std::ostringstream os;
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { write_obj(os, m); },
        {"triangle 1 refers to vertex 4 but the mesh has 4 vertices"}));
    SurfaceMesh r = tetrahedron();
    r.region = {0, 1};
    EXPECT_THROW(write_ply(os, r, true), std::invalid_argument);
}

TEST(Writers, FormatFromExtension) {
    EXPECT_EQ(mesh_format_from_extension("a/b.OBJ"), MeshFormat::Obj);
    EXPECT_EQ(mesh_format_from_extension("x.vtp"), MeshFormat::Vtp);
    EXPECT_EQ(mesh_format_from_extension("x.stl"), MeshFormat::Stl);
    EXPECT_THROW(mesh_format_from_extension("x.mesh"), std::invalid_argument);
    EXPECT_THROW(mesh_format_from_extension("noext"), std::invalid_argument);
}

}  // namespace
}  // namespace cf::testing
