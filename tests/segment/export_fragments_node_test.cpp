// export.fragments through the per-node harness: the displacement options reach the mesh files
// (compared with the plain FragmentDeformation on the same meshes), and a missing input is named.
#include "graph/node_context.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"
#include "nodes/import/read_mesh.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/segment/fragment_displacement.hpp"
#include "nodes/segment/fragments.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/segment/displacement_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>

namespace cf::testing {
namespace {

using namespace displacement_fixture;

struct Cut {
    CrackLevelSets cracks;
    Fragments fragments;
};

const Cut& cut() {
    static const Cut c = [] {
        Cut k;
        k.cracks = CrackLevelSets{kRf, 3, {planar_disk_crack(Vec3(0, 0, kZ0), Vec3::UnitZ(), 1.0, kRf)}};
        k.fragments = find_fragments(broken_object(cube_grid(), k.cracks));
        return k;
    }();
    return c;
}

std::string failure(const Params& p, const Inputs& in) {
    try {
        run_node("export.fragments", p, in, temp_dir("export-fragments-error"));
    } catch (const std::exception& e) {
        return e.what();
    }
    return "no error";
}

TEST(ExportFragmentsNode, DeformedMeshFilesMatchTheAlgorithm) {
    const auto dir = temp_dir("export-fragments-deformed");
    const Vec3 opening(1e-3, 0, -4e-3);  // compressive: the normal part is removed by default
    const auto sol = planar_crack_solution(opening);
    const auto r = run_node("export.fragments",
                            {{"displacement", std::string("continuous_and_opening")},
                             {"displacement_scale", 2.0},
                             {"close_gaps", true},
                             {"vdb", false},
                             {"preview", false}},
                            {{"fragments", value(cut().fragments)}, {"solution", value(*sol)}, {"cracks", value(cut().cracks)}},
                            dir);
    EXPECT_EQ(r.counts.at("files"), 3);  // 2 meshes and their .mtl
    EXPECT_EQ(r.counts.at("compressive_opening_vertices"), 25);
    EXPECT_GT(r.counts.at("vertices_closed"), 2.0 * kFaceVertices);
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous_and_opening;
    opt.scale = 2;
    opt.close_gaps = true;
    const FragmentDeformation def(std::make_shared<const CoarseDisplacement>(coarse_displacement_from(*sol)), &cut().cracks,
                                  kRf, opt);
    for (std::size_t f = 0; f < 2; ++f) {
        SurfaceMesh expected = level_set_to_mesh(cut().fragments.fragments[f].grid);
        def.apply(expected);
        const SurfaceMesh written = read_mesh(dir / ("fragment_00" + std::to_string(f) + ".obj"));
        ASSERT_EQ(written.num_vertices(), expected.num_vertices());
        double err = 0;
        for (std::size_t i = 0; i < expected.num_vertices(); ++i)
            err = std::max(err, (written.vertices[i] - expected.vertices[i]).norm());
        EXPECT_EQ(err, 0.0) << "fragment " << f;  // OBJ carries shortest round-trip doubles
    }
}

TEST(ExportFragmentsNode, MissingInputsAreNamed) {
    const Inputs only_fragments = {{"fragments", value(cut().fragments)}};
    const Params quiet = {{"vdb", false}, {"preview", false}};
    auto with = [&](Params p) {
        p.insert(quiet.begin(), quiet.end());
        return p;
    };
    std::string m = failure(with({{"displacement", std::string("continuous")}}), only_fragments);
    std::cout << "missing solution: " << m << "\n";
    EXPECT_NE(m.find("'displacement'"), std::string::npos) << m;
    EXPECT_NE(m.find("'solution'"), std::string::npos) << m;
    const auto sol = planar_crack_solution(Vec3(0, 0, 1e-3));
    m = failure(with({{"displacement", std::string("continuous_and_opening")}}),
                {{"fragments", value(cut().fragments)}, {"solution", value(*sol)}});
    EXPECT_NE(m.find("'cracks'"), std::string::npos) << m;
    m = failure(with({{"close_gaps", true}}), only_fragments);
    EXPECT_NE(m.find("'close_gaps'"), std::string::npos) << m;
    EXPECT_NE(m.find("'cracks'"), std::string::npos) << m;
    m = failure(with({{"displacement_scale", -1.0}}), only_fragments);
    EXPECT_NE(m.find("displacement_scale"), std::string::npos) << m;
}

TEST(ExportFragmentsNode, PreviewCameraParametersAreChecked) {
    const Inputs only_fragments = {{"fragments", value(cut().fragments)}};
    std::string m = failure({{"vdb", false}, {"meshes", false}, {"up", std::vector<double>{0, 0, 0}}}, only_fragments);
    EXPECT_NE(m.find("'up'"), std::string::npos) << m;
    m = failure({{"vdb", false}, {"meshes", false}, {"up", std::vector<double>{0, 1, 0}}, {"view", std::vector<double>{0, -3, 0}}},
                only_fragments);
    EXPECT_NE(m.find("'view'"), std::string::npos) << m;
    EXPECT_NE(m.find("parallel"), std::string::npos) << m;
    // A y-up camera is accepted and renders.
    const auto r = run_node("export.fragments",
                            {{"vdb", false}, {"meshes", false}, {"width", std::int64_t(64)}, {"height", std::int64_t(48)},
                             {"up", std::vector<double>{0, 1, 0}}, {"view", std::vector<double>{0.9, 0.7, 1.2}}},
                            only_fragments, temp_dir("export-fragments-camera"));
    EXPECT_EQ(r.counts.at("files"), 1);
}


// The same rules are declared beside the ports, so validation names the parameter's FILE:LINE
// before the fracture loop runs (they used to fail only at the end of the run).
TEST(ExportFragmentsNode, ValidationNamesTheInputsTheDisplacementOptionsNeed) {
    // The fragments are exported in the fracture loop's file, pipelines/lib/fracture.yaml, which
    // edge_crack_mode1.yaml uses: an edited copy of it beside a copy of the case.
    std::ifstream f(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/lib/fracture.yaml");
    ASSERT_TRUE(f);
    std::stringstream ss;
    ss << f.rdbuf();
    std::string text = ss.str();
    const std::string plain = "params: {format: obj, adaptivity: 0.05}";
    const std::size_t at = text.find(plain);
    ASSERT_NE(at, std::string::npos);
    const int line = 1 + int(std::count(text.begin(), text.begin() + long(at), '\n'));
    text.replace(at, plain.size(), "params: {format: obj, displacement: continuous_and_opening, close_gaps: true}");
    const std::filesystem::path dir = temp_dir("export-fragments-validation");
    std::filesystem::create_directories(dir / "lib");
    std::ofstream(dir / "lib" / "fracture.yaml") << text;
    std::ifstream c(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/edge_crack_mode1.yaml");
    std::ofstream(dir / "edge.yaml") << c.rdbuf();
    std::vector<graph::Diagnostic> diags;
    graph::load_pipeline_file((dir / "edge.yaml").string(), node_registry(), {}, diags);
    std::string all;
    for (const auto& d : diags) all += graph::format(d) + "\n";
    ASSERT_EQ(diags.size(), 3u) << all;
    for (const auto& d : diags) EXPECT_EQ(d.loc.line, line) << all;
    EXPECT_NE(all.find("parameter 'displacement' = continuous_and_opening of node 'fracture/export' (export.fragments) needs the "
                       "input 'solution' (BemSolution)"), std::string::npos) << all;
    EXPECT_NE(all.find("parameter 'displacement' = continuous_and_opening of node 'fracture/export' (export.fragments) needs the "
                       "input 'cracks'"), std::string::npos) << all;
    EXPECT_NE(all.find("parameter 'close_gaps' = true of node 'fracture/export' (export.fragments) needs the input 'cracks'"),
              std::string::npos) << all;
}

// export.step_preview: a PNG per loop iteration of the recorded cracks (here one plane crack across
// the unit cube), nothing with path 'none', and a bad camera named by its parameters.
TEST(StepPreviewNode, WritesThePngItIsToldToAndNothingForNone) {
    const auto dir = temp_dir("step-preview");
    const SurfaceMesh cube = testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5));
    const Inputs in{{"surface", value(cube)}, {"cracks", value(cut().cracks)}};
    const auto r = run_node("export.step_preview", {{"path", std::string("step_{iteration}.png")}}, in, dir);
    EXPECT_TRUE(std::filesystem::exists(dir / "step_0000.png"));
    EXPECT_GT(r.counts.at("crack_triangles"), 100.0);
    const auto none = temp_dir("step-preview-none");
    run_node("export.step_preview", {{"path", std::string("none")}}, in, none);
    EXPECT_TRUE(std::filesystem::is_empty(none));
    try {
        run_node("export.step_preview", {{"up", std::vector<double>{0, 1, 0}}, {"view", std::vector<double>{0, 2, 0}}}, in,
                 temp_dir("step-preview-bad"));
        ADD_FAILURE() << "a view parallel to up was accepted";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("'view'"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace cf::testing
