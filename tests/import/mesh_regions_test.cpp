// Regions read from mesh files (issue 13): OBJ g/o/usemtl names, PLY integer face properties, and
// the errors for names boundary conditions could not address. The unit cube's faces are known by
// hand: each quad is two triangles of area 1/2.
#include "nodes/import/read_mesh.hpp"
#include "tests/harness/expect_error.hpp"
#include "tests/import/mesh_fixtures.hpp"

#include <gtest/gtest.h>

#include <map>

namespace cf::testing {
namespace {

std::filesystem::path fresh_dir(const std::string& tag) {
    auto d = std::filesystem::temp_directory_path() / "crackflow-tests" / ("import-regions-" + tag);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

std::string obj_vertices() {
    std::string s;
    for (const Vec3& v : cube_vertices())
        s += "v " + std::to_string(int(v.x())) + " " + std::to_string(int(v.y())) + " " + std::to_string(int(v.z())) + "\n";
    return s;
}
std::string obj_face(int q) {
    const auto f = cube_quads()[std::size_t(q)];
    return "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + " " +
           std::to_string(f[3] + 1) + "\n";
}

// Region name -> (triangles, area).
std::map<std::string, std::pair<int, double>> per_region(const SurfaceMesh& m) {
    std::map<std::string, std::pair<int, double>> r;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        auto& e = r[m.region_name(m.region_of(t))];
        e.first += 1;
        e.second += triangle_area(m, t);
    }
    return r;
}

}  // namespace

TEST(MeshRegions, ObjGroupsObjectsAndMaterialsNameTheFacesThatFollow) {
    const auto dir = fresh_dir("obj");
    // Bottom before any name (default); 'o Cube' is followed at once by 'usemtl top', so only the
    // material names faces; a bare 'g' returns to default; 'g default' is that same region.
    const std::string text = obj_vertices() + obj_face(0) + "o Cube\nusemtl top\n" + obj_face(1) + "g sides extra\n" + obj_face(2) +
                             obj_face(3) + "g\n" + obj_face(4) + "g default\n" + obj_face(5);
    const SurfaceMesh m = read_mesh(write_file(dir / "cube.obj", text));
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"default", "top", "sides"}));  // in order of first use
    const auto r = per_region(m);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r.at("default"), std::make_pair(6, 3.0));  // bottom, x = 0, x = 1
    EXPECT_EQ(r.at("top"), std::make_pair(2, 1.0));
    EXPECT_EQ(r.at("sides"), std::make_pair(4, 2.0));
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        if (m.region_name(m.region_of(t)) == "top") {
            EXPECT_EQ(triangle_normal(m, t), Vec3(0, 0, 1));
        }
    }
}

TEST(MeshRegions, ObjWithoutNamesIsOneDefaultRegion) {
    const auto dir = fresh_dir("obj-plain");
    std::string text = obj_vertices();
    for (int q = 0; q < 6; ++q) text += obj_face(q);
    const SurfaceMesh m = read_mesh(write_file(dir / "cube.obj", text));
    EXPECT_EQ(m.region_names, std::vector<std::string>{"default"});
    EXPECT_EQ(m.region, std::vector<int>(12, 0));
}

TEST(MeshRegions, ObjNamesBoundaryConditionsCannotUseAreErrorsAtTheirLine) {
    const auto dir = fresh_dir("obj-bad");
    const std::string text = obj_vertices() + "usemtl a:b\n" + obj_face(0);
    EXPECT_TRUE(throws<MeshFileError>([&] { read_mesh(write_file(dir / "cube.obj", text)); },
                                      {"cube.obj:9", "'a:b'", "no ':' or ';'"}));
    const std::string star = obj_vertices() + "g *\n" + obj_face(0);
    EXPECT_TRUE(throws<MeshFileError>([&] { read_mesh(write_file(dir / "star.obj", star)); }, {"star.obj:9", "'*'"}));
}

TEST(MeshRegions, PlyIntegerFacePropertyNamesRegions) {
    const auto dir = fresh_dir("ply");
    // The first region property in the order region, material_index, material, group wins.
    std::string text = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 6\nproperty uchar material\nproperty list uchar int vertex_indices\n"
                       "property int region\nproperty float quality\nend_header\n";
    for (const Vec3& v : cube_vertices()) text += std::to_string(v.x()) + " " + std::to_string(v.y()) + " " + std::to_string(v.z()) + "\n";
    const int region[6] = {5, 2, 5, 5, 7, 7};
    for (int q = 0; q < 6; ++q) {
        const auto f = cube_quads()[std::size_t(q)];
        text += "9 4 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + " " +
                std::to_string(f[3]) + " " + std::to_string(region[q]) + " 0.5\n";
    }
    const SurfaceMesh m = read_mesh(write_file(dir / "cube.ply", text));
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"region5", "region2", "region7"}));
    const auto r = per_region(m);
    EXPECT_EQ(r.at("region5"), std::make_pair(6, 3.0));
    EXPECT_EQ(r.at("region2"), std::make_pair(2, 1.0));
    EXPECT_EQ(r.at("region7"), std::make_pair(4, 2.0));
}

TEST(MeshRegions, PlyMaterialIndexInBinaryFiles) {
    const auto dir = fresh_dir("ply-binary");
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty double x\nproperty double y\n"
                       "property double z\nelement face 6\nproperty list uchar int vertex_indices\nproperty ushort material_index\n"
                       "end_header\n";
    auto put = [&](const void* p, std::size_t n) { text.append(static_cast<const char*>(p), n); };
    for (const Vec3& v : cube_vertices()) put(v.data(), 24);
    const auto quads = cube_quads();
    for (int q = 0; q < 6; ++q) {
        const unsigned char four = 4;
        put(&four, 1);
        for (int c : quads[std::size_t(q)]) put(&c, 4);
        const std::uint16_t material = q == 1 ? 1 : 0;
        put(&material, 2);
    }
    const SurfaceMesh m = read_mesh(write_file(dir / "cube.ply", text));
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"material_index0", "material_index1"}));
    EXPECT_EQ(per_region(m).at("material_index1"), std::make_pair(2, 1.0));
}

}  // namespace cf::testing
