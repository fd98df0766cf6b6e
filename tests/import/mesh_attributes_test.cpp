// Texture coordinates and normals read from mesh files (issue 14): OBJ vt/vn per corner, PLY
// per-vertex u v / nx ny nz, kept with the right corner through triangulation and re-orientation.
// Each file gives a corner values that are a known function of its position (or of its face), so
// the expected value of every corner is computed independently of the reader.
#include "nodes/import/read_mesh.hpp"
#include "tests/import/mesh_fixtures.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace cf::testing {
namespace {

std::filesystem::path write(const std::string& name, const std::string& text) {
    auto d = std::filesystem::temp_directory_path() / "crackflow-tests" / "import-attributes";
    std::filesystem::create_directories(d);
    std::ofstream(d / name) << text;
    return d / name;
}

// Per-vertex values of the unit cube's corners.
Vec2 uv_of(const Vec3& p) { return Vec2(0.5 * p.x() + 0.1, 0.25 * p.y() + p.z()); }
Vec3 normal_of(const Vec3& p) { return (p - Vec3(0.5, 0.5, 0.5)).normalized(); }
// Per-face (OBJ) texture coordinates: face q's corner k.
Vec2 face_uv(int q, int k) { return Vec2(q + 0.1 * k, -0.5 * q + 0.01 * k); }

TEST(MeshAttributes, PlyPerVertexUvAndNormalsReachEveryCorner) {
    std::string text = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                       "property float nx\nproperty float ny\nproperty float nz\nproperty float s\nproperty float t\n"
                       "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& v : cube_vertices()) {
        const Vec3 n = 2.0 * normal_of(v);  // not unit in the file: the reader normalises
        const Vec2 uv = uv_of(v);
        text += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + " " +
                std::to_string(n.x()) + " " + std::to_string(n.y()) + " " + std::to_string(n.z()) + " " +
                std::to_string(uv.x()) + " " + std::to_string(uv.y()) + "\n";
    }
    for (const auto& f : cube_quads())
        text += "4 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " " +
                std::to_string(f[3]) + "\n";
    const SurfaceMesh m = read_mesh(write("cube.ply", text));
    ASSERT_TRUE(m.has_uv());
    ASSERT_TRUE(m.has_normals());
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = m.vertices[std::size_t(m.triangles[t][k])];
            EXPECT_LT((m.corner_uv[t][k] - uv_of(p)).norm(), 1e-6);  // std::to_string prints 6 decimals
            EXPECT_LT((m.corner_normal[t][k] - normal_of(p)).norm(), 1e-5);
        }
}

// An OBJ whose first face is written inside out: re-orientation flips it, and its corners must keep
// their own texture coordinates and normals (given by relative, negative indices).
TEST(MeshAttributes, ObjCornersFollowTheirVertexThroughReorientation) {
    std::string text;
    for (const Vec3& v : cube_vertices())
        text += "v " + std::to_string(int(v.x())) + " " + std::to_string(int(v.y())) + " " + std::to_string(int(v.z())) + "\n";
    for (int q = 0; q < 6; ++q) {
        auto f = cube_quads()[std::size_t(q)];
        int order[4] = {0, 1, 2, 3};
        if (q == 0) std::swap(order[1], order[3]);  // reversed
        for (int k = 0; k < 4; ++k) {
            const Vec2 uv = face_uv(q, order[k]);
            const Vec3 n = normal_of(cube_vertices()[std::size_t(f[std::size_t(order[k])])]);
            text += "vt " + std::to_string(uv.x()) + " " + std::to_string(uv.y()) + "\n";
            text += "vn " + std::to_string(n.x()) + " " + std::to_string(n.y()) + " " + std::to_string(n.z()) + "\n";
        }
        text += "f";
        for (int k = 0; k < 4; ++k)
            text += " " + std::to_string(f[std::size_t(order[k])] + 1) + "/" + std::to_string(k - 4) + "/" + std::to_string(k - 4);
        text += "\n";
    }
    ImportOptions o;
    o.reorient = true;
    const ImportedMesh im = read_mesh_file(write("flipped.obj", text), o);
    EXPECT_EQ(im.report.flipped_triangles, 2u);
    const SurfaceMesh& m = im.mesh;
    ASSERT_TRUE(m.has_uv());
    ASSERT_TRUE(m.has_normals());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const int q = int(t / 2);  // fan triangulation: two triangles per quad, in file order
        for (int k = 0; k < 3; ++k) {
            const int v = m.triangles[t][k];
            const auto f = cube_quads()[std::size_t(q)];
            const int corner = int(std::find(f.begin(), f.end(), v) - f.begin());
            EXPECT_LT((m.corner_uv[t][k] - face_uv(q, corner)).norm(), 1e-6) << "triangle " << t << " corner " << k;
            EXPECT_LT((m.corner_normal[t][k] - normal_of(m.vertices[std::size_t(v)])).norm(), 1e-5);
        }
    }
}

TEST(MeshAttributes, ObjWithUvsOnSomeFacesOnlyHasNone) {
    std::string text = cube_obj();
    text += "vt 0 0\n";
    const std::size_t f = text.find("\nf ");
    ASSERT_NE(f, std::string::npos);
    const std::size_t end = text.find('\n', f + 1);
    std::string first = text.substr(f + 1, end - f - 1);  // "f a b c d" -> "f a/1 b/1 c/1 d/1"
    std::string with;
    for (std::size_t i = 0; i < first.size(); ++i) {
        with += first[i];
        if (std::isdigit(static_cast<unsigned char>(first[i])) && (i + 1 == first.size() || first[i + 1] == ' ')) with += "/-1";
    }
    text.replace(f + 1, first.size(), with);
    text.insert(f + 1, "vt 0.5 0.5\n");
    const SurfaceMesh m = read_mesh(write("some.obj", text));
    EXPECT_FALSE(m.has_uv());
}

// A corner referring to a texture coordinate the file never defines (files like that exist): the
// geometry is read, the mesh has no UVs; its normals, all defined, are kept.
TEST(MeshAttributes, ObjDanglingTextureIndexLeavesTheMeshWithoutUvs) {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\n"
                             "f 1/1/1 3/2/1 2/1/1\nf 1/1/1 2/1/1 4/1/1\nf 2/1/1 3/1/1 4/1/1\nf 1/1/1 4/1/1 3/1/1\n";
    const SurfaceMesh m = read_mesh(write("dangling.obj", text));
    EXPECT_EQ(m.num_triangles(), 4u);
    EXPECT_FALSE(m.has_uv());
    EXPECT_TRUE(m.has_normals());
}

}  // namespace
}  // namespace cf::testing
