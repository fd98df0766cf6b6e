// export.mesh through the per-node harness: output directory, format choice, counts, errors,
// and no temporary files left behind.
#include "graph/node_context.hpp"
#include "nodes/import/read_mesh.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace cf::testing {
namespace {

std::string head(const std::filesystem::path& p, std::size_t n) {
    std::ifstream f(p, std::ios::binary);
    std::string s(n, '\0');
    f.read(s.data(), static_cast<std::streamsize>(n));
    s.resize(static_cast<std::size_t>(f.gcount()));
    return s;
}

TEST(ExportMeshNode, WritesIntoTheOutputDirectory) {
    auto dir = temp_dir("export-node");
    SurfaceMesh cube = transformed(unit_cube(), 0.3, Vec3(0.1, 0.2, 0.3));
    auto r = run_node("export.mesh", {{"path", std::string("meshes/cube.ply")}}, {{"mesh", value(cube)}}, dir);
    const auto file = dir / "meshes" / "cube.ply";
    ASSERT_TRUE(std::filesystem::exists(file));
    EXPECT_EQ(r.counts.at("bytes"), static_cast<double>(std::filesystem::file_size(file)));
    EXPECT_EQ(r.counts.at("triangles"), 12);
    EXPECT_NE(head(file, 40).find("format binary_little_endian"), std::string::npos);  // binary by default
    SurfaceMesh back = read_mesh(file);
    EXPECT_EQ(back.vertices, cube.vertices);
    EXPECT_EQ(back.triangles, cube.triangles);
    // Only the file itself: the temporary file of the atomic write is gone.
    std::size_t entries = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir / "meshes")) entries += (void(e), 1);
    EXPECT_EQ(entries, 1u);
}

TEST(ExportMeshNode, ExplicitFormatAndAscii) {
    auto dir = temp_dir("export-node");
    run_node("export.mesh", {{"path", std::string("a.mesh")}, {"format", std::string("stl")}, {"binary", false}},
             {{"mesh", value(tetrahedron())}}, dir);
    EXPECT_EQ(head(dir / "a.mesh", 16), "solid crackflow\n");
    auto abs = dir / "abs.vtp";
    run_node("export.mesh", {{"path", abs.string()}}, {{"mesh", value(tetrahedron())}}, dir / "elsewhere");
    EXPECT_EQ(head(abs, 21), "<?xml version=\"1.0\"?>");
}

TEST(ExportMeshNode, Errors) {
    auto dir = temp_dir("export-node");
    EXPECT_TRUE(cf::testing::throws<graph::NodeError>(
        [&] { run_node("export.mesh", {{"path", std::string("cube.xyz")}}, {{"mesh", value(unit_cube())}}, dir); },
        {"name it .obj, .off, .ply, .stl, .vtp or .glb, or set format"}));
    EXPECT_THROW(run_node("export.mesh", {{"path", std::string("c.obj")}, {"format", std::string("fbx")}},
                          {{"mesh", value(unit_cube())}}, dir),
                 graph::NodeError);
    SurfaceMesh broken = unit_cube();
    broken.triangles[0][0] = 99;
    EXPECT_TRUE(cf::testing::throws<graph::NodeError>(
        [&] { run_node("export.mesh", {{"path", std::string("b.obj")}}, {{"mesh", value(broken)}}, dir); },
        {"refers to vertex 99"}));
    EXPECT_FALSE(std::filesystem::exists(dir / "b.obj"));  // nothing half-written
    EXPECT_TRUE(std::filesystem::is_empty(dir));
}

}  // namespace
}  // namespace cf::testing
