// import.mesh through the per-node harness: parameters, counts, and errors as a node sees them.
#include "graph/node_context.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/import/mesh_fixtures.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

namespace cf::testing {
namespace {

TEST(ImportMeshNode, ReadsAndCounts) {
    auto dir = temp_dir("import-node");
    auto path = write_file(dir / "cube.stl", mesh_stl_binary(unit_cube()));
    auto r = run_node("import.mesh", {{"path", path.string()}, {"scale", 0.5}});
    const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
    EXPECT_EQ(m.num_triangles(), 12u);
    EXPECT_EQ(signed_volume(m), 0.125);  // (0.5 m)^3
    EXPECT_EQ(r.counts.at("vertices"), 8);
    EXPECT_EQ(r.counts.at("triangles"), 12);
    EXPECT_EQ(r.counts.at("regions"), 1);
    EXPECT_EQ(r.counts.at("welded_vertices"), 28);
    EXPECT_EQ(m.region_name(0), "default");
}

TEST(ImportMeshNode, ReorientParameter) {
    auto dir = temp_dir("import-node");
    auto path = write_file(dir / "flip.obj", mesh_obj(with_flipped(unit_cube(), {2})));
    EXPECT_THROW(run_node("import.mesh", {{"path", path.string()}}), graph::NodeError);
    auto r = run_node("import.mesh", {{"path", path.string()}, {"reorient", true}});
    EXPECT_EQ(r.counts.at("flipped_triangles"), 1);
    EXPECT_EQ(r.out<SurfaceMesh>("mesh").triangles, unit_cube().triangles);
}

TEST(ImportMeshNode, FileErrorsBecomeNodeErrors) {
    auto dir = temp_dir("import-node");
    auto path = write_file(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    EXPECT_TRUE(cf::testing::throws<graph::NodeError>(
        [&] { run_node("import.mesh", {{"path", path.string()}}); },
        {"bad.obj:4: error: face index 7 out of range (file has 3 vertices"}));
}

TEST(ImportMeshNode, ParameterChecks) {
    EXPECT_THROW(run_node("import.mesh", {}), graph::NodeError);  // path is required
    EXPECT_THROW(run_node("import.mesh", {{"path", std::string("x.obj")}, {"scale", 0.0}}), graph::NodeError);
    EXPECT_THROW(run_node("import.mesh", {{"path", std::string("x.obj")}, {"weld_tolerance", -1.0}}), graph::NodeError);
}

}  // namespace
}  // namespace cf::testing
