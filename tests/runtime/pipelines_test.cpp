// Every shipped pipeline validates and runs to completion in fast mode.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <variant>

namespace {

std::vector<std::filesystem::path> shipped_pipelines() {
    std::vector<std::filesystem::path> r;
    for (const auto& e : std::filesystem::directory_iterator(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines"))
        if (e.path().extension() == ".yaml") r.push_back(e.path());
    std::sort(r.begin(), r.end());
    return r;
}

class ShippedPipeline : public ::testing::TestWithParam<std::filesystem::path> {};

// "lib/fracture.yaml" -> "fracture.yaml"
std::string fs_name(const std::string& use) { return std::filesystem::path(use).filename().string(); }

}  // namespace

// Run from a working directory that is not the repository (input paths resolve beside the
// pipeline file and on the data path, so no pipeline depends on where it is started).
TEST_P(ShippedPipeline, ValidatesAndRunsInFastModeFromAnotherDirectory) {
    const std::filesystem::path elsewhere = cf::testing::temp_dir("pipeline-cwd-" + GetParam().stem().string());
    const std::filesystem::path before = std::filesystem::current_path();
    std::filesystem::current_path(elsewhere);
    struct Back {
        std::filesystem::path p;
        ~Back() { std::filesystem::current_path(p); }
    } back{before};
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::LoadOptions options;
    options.fast = true;
    auto plan = cf::graph::load_pipeline_file(GetParam().string(), cf::node_registry(), options, diags);
    std::string text;
    for (const auto& d : diags) text += cf::graph::format(d) + "\n";
    // Pipelines on libcgal-demo's meshes: CMake extracts them into the build's data directory
    // (setup.sh installs the package). Without it the case fails, saying how to fix the set-up.
    if (!std::filesystem::exists("/usr/share/doc/libcgal-demo/data.tar.gz") && text.find("'meshes/") != std::string::npos)
        FAIL() << "install the Debian package libcgal-demo (it ships data.tar.gz with the meshes) and re-run cmake";
    ASSERT_TRUE(diags.empty()) << text;
    cf::graph::RunOptions run;
    run.fast = true;
    run.output_dir = cf::testing::temp_dir("pipeline-" + GetParam().stem().string());
    auto result = cf::graph::execute(plan, run);
    EXPECT_TRUE(result.ok) << result.error;
    for (const auto& s : result.stats) EXPECT_GE(s.runs, 1) << s.name << " never ran";
    // Where a pipeline gives export.fragments the input surface, every fragment keeps it: none
    // falls back to its level-set mesh (the count exists only with the surface mesher).
    for (const auto& s : result.stats)
        if (s.type == "export.fragments" && s.counts.count("fallback_fragments"))
            EXPECT_EQ(s.counts.at("fallback_fragments"), 0) << s.name << " wrote level-set meshes";
}

INSTANTIATE_TEST_SUITE_P(All, ShippedPipeline, ::testing::ValuesIn(shipped_pipelines()),
                         [](const auto& info) {
                             std::string n = info.param.stem().string();
                             for (char& c : n) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

// The thesis cases are short files around the one fracture loop of pipelines/lib/fracture.yaml:
// each uses it, and none holds a loop of its own.
TEST(ShippedPipelines, ThesisCasesUseTheFractureLibrary) {
    int cases = 0;
    for (const auto& p : shipped_pipelines()) {
        std::ifstream in(p);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (text.find("use: lib/fracture.yaml") == std::string::npos) continue;
        ++cases;
        EXPECT_EQ(text.find("type: loop"), std::string::npos) << p;
        EXPECT_LE(std::count(text.begin(), text.end(), '\n'), 45) << p << " is longer than a case file should be";
    }
    EXPECT_GE(cases, 23);
}

// The pipelines an artist starts from (the default, the cut box, the dataset's mesh, torus and
// cylinder runs) keep the input surface: their export.fragments gets the object's input mesh.
// The thesis cases write the thesis' level-set meshes (docs/pipelines.md says why and how to
// switch); their surface-mesher runs are tested by tests/segment.
TEST(ShippedPipelines, ArtistPipelinesKeepTheInputSurface) {
    for (const std::string file : {"default.yaml", "cut_box.yaml", "batch/fracture_mesh.yaml", "batch/fracture_torus.yaml",
                                   "batch/fracture_cylinder.yaml"}) {
        std::vector<cf::graph::Diagnostic> diags;
        cf::graph::LoadOptions options;
        options.fast = true;
        const auto plan = cf::graph::load_pipeline_file(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/" + file,
                                                        cf::node_registry(), options, diags);
        ASSERT_TRUE(diags.empty()) << file;
        int exports = 0, with_surface = 0;
        for (const auto& n : plan.nodes) {
            if (n.is_loop() || n.type->name() != "export.fragments") continue;
            ++exports;
            with_surface += std::any_of(n.inputs.begin(), n.inputs.end(), [](const auto& in) { return in.port == "surface"; });
        }
        EXPECT_GE(exports, 1) << file;
        EXPECT_EQ(with_surface, exports) << file << ": export.fragments without the input surface";
    }
}

// Every case on the fracture library runs, at --fast, with the surface mesher too: its `use` node
// gets the mesh its object's level set is made from as `surface` (one line, as docs/pipelines.md
// says), and every fragment keeps the input surface, none falls back to its level-set mesh.
class CaseWithSurfaceMesher : public ::testing::TestWithParam<std::filesystem::path> {};

std::vector<std::filesystem::path> fracture_library_cases() {
    std::vector<std::filesystem::path> r;
    for (const auto& p : shipped_pipelines()) {
        std::ifstream in(p);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (text.find("use: lib/fracture.yaml") != std::string::npos) r.push_back(p);
    }
    return r;
}

TEST_P(CaseWithSurfaceMesher, EveryFragmentKeepsTheInputSurface) {
    YAML::Node doc = YAML::LoadFile(GetParam().string());
    YAML::Node nodes = doc["nodes"];
    std::string mesh, use_node;
    for (const auto& n : nodes) {
        const YAML::Node v = n.second;
        if (v["use"] && v["use"].as<std::string>() == "lib/fracture.yaml") use_node = n.first.as<std::string>();
        if (v["use"] && v["use"].as<std::string>() == "lib/surface.yaml") mesh = v["inputs"]["mesh"].as<std::string>();
        if (n.first.as<std::string>() == "object" && v["type"] && v["type"].as<std::string>() == "levelset.from_mesh")
            mesh = v["inputs"]["mesh"].as<std::string>();
    }
    ASSERT_FALSE(mesh.empty()) << "no object mesh found in " << GetParam();
    ASSERT_FALSE(use_node.empty());
    nodes[use_node]["inputs"]["surface"] = mesh;
    const std::string lib = std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/lib/";
    for (auto n : nodes)
        if (n.second["use"]) n.second["use"] = lib + fs_name(n.second["use"].as<std::string>());
    const std::filesystem::path dir = cf::testing::temp_dir("surface-case-" + GetParam().stem().string());
    const std::filesystem::path file = dir / GetParam().filename();
    {
        YAML::Emitter e;
        e << doc;
        std::ofstream(file) << e.c_str() << '\n';
    }
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::LoadOptions options;
    options.fast = true;
    auto plan = cf::graph::load_pipeline_file(file.string(), cf::node_registry(), options, diags);
    std::string text;
    for (const auto& d : diags) text += cf::graph::format(d) + "\n";
    ASSERT_TRUE(diags.empty()) << text;
    cf::graph::RunOptions run;
    run.fast = true;
    run.output_dir = dir / "out";
    auto result = cf::graph::execute(plan, run);
    ASSERT_TRUE(result.ok) << result.error;
    int exports = 0;
    for (const auto& st : result.stats)
        if (st.type == "export.fragments") {
            ++exports;
            ASSERT_TRUE(st.counts.count("fallback_fragments")) << st.name << " did not use the surface mesher";
            EXPECT_EQ(st.counts.at("fallback_fragments"), 0) << st.name;
        }
    EXPECT_EQ(exports, 1);
}

INSTANTIATE_TEST_SUITE_P(FractureLibrary, CaseWithSurfaceMesher, ::testing::ValuesIn(fracture_library_cases()),
                         [](const auto& info) {
                             std::string n = info.param.stem().string();
                             for (char& c : n) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return n;
                         });

TEST(ShippedPipelines, ThereIsADefaultPipeline) {
    EXPECT_TRUE(std::filesystem::exists(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/default.yaml"));
}
