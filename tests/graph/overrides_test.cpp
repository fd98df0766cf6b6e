// Overrides and input paths: --set takes text for text parameters, a value shared through a YAML
// anchor is overridden in every node sharing it, and input files resolve beside the pipeline file,
// then on CRACKFLOW_DATA_PATH, from any working directory, with every path tried in the error.
#include "graph/input_paths.hpp"
#include "test_registry.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / "crackflow-tests" / ("overrides-" + name);
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

std::string all(const std::vector<cf::graph::Diagnostic>& diags) {
    std::string s;
    for (const auto& d : diags) s += cf::graph::format(d) + "\n";
    return s;
}

cf::graph::Override set(const std::string& node, const std::string& param, const std::string& value) {
    return {node, param, value, {"--set", 0, 0}};
}

// Runs f with the working directory `dir`, restoring it after.
template <class F>
void in_directory(const fs::path& dir, F f) {
    const fs::path before = fs::current_path();
    fs::current_path(dir);
    f();
    fs::current_path(before);
}

}  // namespace

// A text parameter takes the --set value as it is: colons, semicolons and spaces need no quotes
// (they used to be read as YAML: 'a: b' became a mapping). Quoted text is still read as YAML;
// numbers and lists still are.
TEST(Overrides, SetTakesTextForTextParameters) {
    const std::string pipeline = R"(nodes:
  x: {type: core.real, params: {value: 1}}
  w: {type: core.write_real, inputs: {value: x.value}, params: {path: a.txt}}
  s: {type: test.sink, inputs: {value: x.value}, params: {mode: plain}}
)";
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::LoadOptions o;
    o.overrides = {set("w", "path", "z_max: traction 0 0 1; *: x.txt"), set("s", "mode", "scaled"), set("x", "value", "2.5e-3")};
    auto plan = load_text(pipeline, diags, o);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("w")].params.at("path")), "z_max: traction 0 0 1; *: x.txt");
    EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("s")].params.at("mode")), "scaled");
    EXPECT_EQ(std::get<double>(plan.nodes[plan.find("x")].params.at("value")), 2.5e-3);
    // Quoted: read as YAML (what a batch manifest hands on for text it quoted).
    o.overrides = {set("w", "path", "\"quoted: b.txt\""), set("s", "mode", "'plain'")};
    plan = load_text(pipeline, diags, o);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("w")].params.at("path")), "quoted: b.txt");
    EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("s")].params.at("mode")), "plain");
    // A number parameter is still checked as one.
    o.overrides = {set("x", "value", "a: b")};
    load_text(pipeline, diags, o);
    ASSERT_EQ(diags.size(), 1u);
    EXPECT_NE(diags[0].message.find("expects a number"), std::string::npos) << all(diags);
}

// A value shared through an anchor is one value: --set (and fast:) on one node sets it in every
// node that shares it, and in no other.
TEST(Overrides, AnchoredValueIsOverriddenInEveryNodeSharingIt) {
    const std::string pipeline = R"(nodes:
  a: {type: core.real, params: &v {value: 1}}
  b: {type: core.real, params: *v}
  c: {type: core.real, params: {value: 1}}
  d: {type: core.real, params: {value: &w 2}}
  e: {type: core.real, params: {value: *w}}
fast:
  e.value: 7
)";
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::LoadOptions o;
    o.overrides = {set("a", "value", "5")};
    auto plan = load_text(pipeline, diags, o);
    ASSERT_TRUE(diags.empty()) << all(diags);
    auto value = [&](const char* n) { return std::get<double>(plan.nodes[plan.find(n)].params.at("value")); };
    EXPECT_EQ(value("a"), 5.0);
    EXPECT_EQ(value("b"), 5.0);
    EXPECT_EQ(value("c"), 1.0);
    EXPECT_EQ(value("d"), 2.0);
    // An anchored scalar, set through the node that uses the alias, by fast:.
    o.overrides.clear();
    o.fast = true;
    plan = load_text(pipeline, diags, o);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(value("d"), 7.0);
    EXPECT_EQ(value("e"), 7.0);
    EXPECT_EQ(value("a"), 1.0);
}

// Input files: beside the pipeline file whatever the working directory, then on the data path;
// a --set value relative to the working directory; a missing file names every absolute path tried.
TEST(InputPaths, RelativeToThePipelineFileThenTheDataPath) {
    const fs::path d = fresh_dir("paths");
    write(d / "pipes" / "numbers" / "three.txt", "3\n");
    write(d / "shared" / "meshes" / "four.txt", "4\n");
    write(d / "elsewhere" / "five.txt", "5\n");
    write(d / "pipes" / "p.yaml", R"(nodes:
  here: {type: test.read, params: {path: numbers/three.txt}}
  shared: {type: test.read, params: {path: meshes/four.txt}}
)");
    ::setenv(cf::graph::kDataPathVariable, ((d / "nothing").string() + "::" + (d / "shared").string()).c_str(), 1);
    in_directory(d / "elsewhere", [&] {
        std::vector<cf::graph::Diagnostic> diags;
        cf::graph::LoadOptions o;
        auto plan = cf::graph::load_pipeline_file("../pipes/p.yaml", test_registry(), o, diags);
        ASSERT_TRUE(diags.empty()) << all(diags);
        EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("here")].params.at("path")),
                  (d / "pipes" / "numbers" / "three.txt").string());
        EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("shared")].params.at("path")),
                  (d / "shared" / "meshes" / "four.txt").string());
        // --set: relative to the working directory.
        o.overrides = {set("here", "path", "five.txt")};
        plan = cf::graph::load_pipeline_file("../pipes/p.yaml", test_registry(), o, diags);
        ASSERT_TRUE(diags.empty()) << all(diags);
        EXPECT_EQ(std::get<std::string>(plan.nodes[plan.find("here")].params.at("path")), (d / "elsewhere" / "five.txt").string());
        // Missing: every absolute path tried, in order, at the parameter's line.
        o.overrides.clear();
        write(d / "pipes" / "q.yaml", "nodes:\n  gone: {type: test.read, params: {path: meshes/gone.txt}}\n");
        cf::graph::load_pipeline_file("../pipes/q.yaml", test_registry(), o, diags);
        ASSERT_EQ(diags.size(), 1u) << all(diags);
        EXPECT_EQ(diags[0].loc.line, 2);
        const std::string text = all(diags);
        const auto a = text.find((d / "pipes" / "meshes" / "gone.txt").string());
        const auto b = text.find((d / "nothing" / "meshes" / "gone.txt").string());
        const auto c = text.find((d / "shared" / "meshes" / "gone.txt").string());
        EXPECT_NE(a, std::string::npos) << text;
        EXPECT_NE(b, std::string::npos) << text;
        EXPECT_NE(c, std::string::npos) << text;
        EXPECT_TRUE(a < b && b < c) << text;
        EXPECT_NE(text.find("CRACKFLOW_DATA_PATH"), std::string::npos) << text;
    });
    ::unsetenv(cf::graph::kDataPathVariable);
    // Without the variable the shared file is not found (only the build's data directory is left).
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::load_pipeline_file((d / "pipes" / "p.yaml").string(), test_registry(), {}, diags);
    ASSERT_EQ(diags.size(), 1u) << all(diags);
    EXPECT_NE(diags[0].message.find("'meshes/four.txt'"), std::string::npos) << all(diags);
}
