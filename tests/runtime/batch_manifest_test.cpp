// Batch manifests: parsing (CSV and YAML) and validation against the rows' pipelines. Every
// problem is reported at once, located by manifest line and character column.
#include "nodes/register_all.hpp"
#include "runtime/batch_manifest.hpp"
#include "runtime/batch_validation.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace cf::runtime::batch {
namespace {

namespace fs = std::filesystem;

std::string src(const std::string& rel) { return std::string(CRACKFLOW_SOURCE_DIR) + "/" + rel; }

// The manifest lives in a temporary folder beside a copy of the test pipeline, so that relative
// pipeline paths are exercised.
fs::path write_manifest(const std::string& name, const std::string& text) {
    const fs::path dir = cf::testing::temp_dir("manifest");
    fs::copy_file(src("tests/runtime/data/batch/tension.yaml"), dir / "tension.yaml");
    fs::copy_file(src("tests/runtime/data/batch/box.off"), dir / "box.off");  // read beside the pipeline
    std::ofstream(dir / name) << text;
    return dir / name;
}

std::string all(const std::vector<Problem>& ps) {
    std::string s;
    for (const auto& p : ps) s += format(p) + "\n";
    return s;
}

bool has(const std::vector<Problem>& ps, int line, int column, const std::string& part) {
    for (const auto& p : ps)
        if (p.line == line && p.column == column && format(p).find(part) != std::string::npos) return true;
    return false;
}

TEST(BatchManifest, CsvRowsWithQuotedCellsCommentsAndEmptyCells) {
    const fs::path f = write_manifest("m.csv",
                                      "# a comment line\n"
                                      "id,pipeline,solution.boundary_conditions,operators.E\n"
                                      "a,tension.yaml,\"bottom: displacement 0 0 0; top: traction 0 0 2e6, *: x\",\n"
                                      "\n"
                                      "b, tension.yaml ,,1e9\n");
    std::vector<Problem> ps;
    const Manifest m = read_manifest(f.string(), ps);
    ASSERT_TRUE(ps.empty()) << all(ps);
    ASSERT_EQ(m.rows.size(), 2u);
    EXPECT_EQ(m.rows[0].id, "a");
    EXPECT_EQ(m.rows[0].number, 1);
    EXPECT_EQ(m.rows[0].line, 3);
    EXPECT_EQ(m.rows[0].pipeline, (f.parent_path() / "tension.yaml").string());
    ASSERT_EQ(m.rows[0].overrides.size(), 1u);  // the empty E cell keeps the pipeline's value
    // Text YAML would take for a mapping is a string (no parameter takes a mapping).
    EXPECT_EQ(m.rows[0].overrides[0].value, "\"bottom: displacement 0 0 0; top: traction 0 0 2e6, *: x\"");
    EXPECT_EQ(m.rows[0].overrides[0].column_number, 16);
    ASSERT_EQ(m.rows[1].overrides.size(), 1u);
    EXPECT_EQ(m.rows[1].overrides[0].column, "operators.E");
    EXPECT_EQ(m.rows[1].overrides[0].line, 5);
    EXPECT_EQ(m.rows[1].overrides[0].column_number, 19);
    EXPECT_EQ(m.rows[1].pipeline_column, 4);  // after the space, which is layout
    EXPECT_EQ(set_arguments(m.rows[1]), std::vector<std::string>{"operators.E=1e9"});
}

TEST(BatchManifest, EveryCsvProblemAtOnceWithLineAndColumn) {
    const fs::path f = write_manifest("bad.csv",
                                      "id,pipeline,operators.E,colour\n"           // line 1: unknown column at col 25
                                      "a,tension.yaml,1e9,red\n"
                                      "a,tension.yaml,2e9,blue\n"                  // line 3: duplicate id
                                      "b,missing.yaml,1e9,red\n"                   // line 4: unknown pipeline at col 3
                                      "c d,tension.yaml,1e9,red\n"                 // line 5: id with a space
                                      "e,tension.yaml,1e9\n");                     // line 6: a field short
    std::vector<Problem> ps;
    read_manifest(f.string(), ps);
    EXPECT_EQ(ps.size(), 5u) << all(ps);
    EXPECT_TRUE(has(ps, 1, 25, "column 'colour': unknown column")) << all(ps);
    EXPECT_TRUE(has(ps, 3, 1, "row 'a', column 'id': duplicate id: row 2 repeats the id of line 2")) << all(ps);
    EXPECT_TRUE(has(ps, 4, 3, "row 'b', column 'pipeline': unknown pipeline: the file")) << all(ps);
    EXPECT_TRUE(has(ps, 5, 1, "holds the character ' '")) << all(ps);
    EXPECT_TRUE(has(ps, 6, 16, "row 5 has 3 fields, the header 4")) << all(ps);
    EXPECT_NE(all(ps).find("bad.csv:1:25: error: column 'colour': unknown column"), std::string::npos) << all(ps);
}

TEST(BatchManifest, MissingIdColumnAndUnclosedQuote) {
    std::vector<Problem> ps;
    parse_manifest_csv("pipeline,operators.E\nx.yaml,\"1e9\n", "m.csv", ps);
    EXPECT_TRUE(has(ps, 1, 1, "the header has no 'id' column")) << all(ps);
    EXPECT_TRUE(has(ps, 2, 8, "a quoted field is not closed")) << all(ps);
    std::vector<Problem> ps2;
    parse_manifest_csv("ID,pipeline\na,x.yaml\n", "m.csv", ps2);
    EXPECT_TRUE(has(ps2, 1, 1, "unknown column")) << all(ps2);
    EXPECT_NE(all(ps2).find("did you mean 'id'?"), std::string::npos) << all(ps2);
}

TEST(BatchManifest, YamlRowsWithDefaultsAndLocations) {
    const fs::path f = write_manifest("m.yaml",
                                      "defaults: {pipeline: tension.yaml, operators.E: 2e9}\n"
                                      "rows:\n"
                                      "  - {id: a, solution.boundary_conditions: \"top: traction 0 0 1e6; *: traction 0 0 0\"}\n"
                                      "  - {id: b, operators.E: 1e9, box.path: [1, 2]}\n"
                                      "  - {id: c, operators.E: ~}\n");
    std::vector<Problem> ps;
    const Manifest m = read_manifest(f.string(), ps);
    ASSERT_TRUE(ps.empty()) << all(ps);
    ASSERT_EQ(m.rows.size(), 3u);
    EXPECT_EQ(set_arguments(m.rows[0]),
              (std::vector<std::string>{"operators.E=2e9", "solution.boundary_conditions=\"top: traction 0 0 1e6; *: traction 0 0 0\""}));
    EXPECT_EQ(set_arguments(m.rows[1]), (std::vector<std::string>{"operators.E=1e9", "box.path=[1, 2]"}));
    EXPECT_EQ(m.rows[1].overrides[0].line, 4);
    EXPECT_EQ(m.rows[1].overrides[0].column_number, 26);
    EXPECT_TRUE(m.rows[2].overrides.empty());  // ~: the pipeline's own value
}

TEST(BatchManifest, YamlProblemsWithLineAndColumn) {
    const fs::path f = write_manifest("bad.yaml",
                                      "rows:\n"
                                      "  - {id: a, pipeline: tension.yaml, colour: red}\n"
                                      "  - {pipeline: tension.yaml}\n"
                                      "  - {id: a, pipeline: tension.yaml}\n"
                                      "extra: 1\n");
    std::vector<Problem> ps;
    read_manifest(f.string(), ps);
    EXPECT_TRUE(has(ps, 2, 37, "column 'colour': unknown column")) << all(ps);
    EXPECT_TRUE(has(ps, 3, 1, "row 2 has no 'id'")) << all(ps);
    EXPECT_TRUE(has(ps, 4, 10, "duplicate id")) << all(ps);
    EXPECT_TRUE(has(ps, 5, 1, "unknown top-level key 'extra'")) << all(ps);
    EXPECT_EQ(ps.size(), 4u) << all(ps);
}

// Validation as `crackflow validate` and `run --set` check: a failing override is reported at its
// cell, with the row and the column; a column naming no node of any pipeline at its header.
TEST(BatchManifest, ValidationReportsFailingOverridesAtTheirCells) {
    const fs::path f = write_manifest("m.csv",
                                      "id,pipeline,operators.E,operators.nu,labeled.regions\n"
                                      "ok,tension.yaml,1e9,0.3,\n"
                                      "negative,tension.yaml,-5,0.3,\n"
                                      "word,tension.yaml,1e9,soft,\n"
                                      "typo,tension.yaml,1e9,0.3,x\n");
    std::vector<Problem> ps;
    const Manifest m = read_manifest(f.string(), ps);
    ASSERT_TRUE(ps.empty()) << all(ps);
    validate_manifest(m, node_registry(), false, ps);
    EXPECT_EQ(ps.size(), 3u) << all(ps);
    EXPECT_TRUE(has(ps, 3, 23, "row 'negative', column 'operators.E': parameter 'E' of node 'operators'")) << all(ps);
    EXPECT_TRUE(has(ps, 4, 23, "row 'word', column 'operators.nu'")) << all(ps);
    EXPECT_TRUE(has(ps, 1, 38, "column 'labeled.regions': unknown column: no pipeline of this manifest has a node 'labeled'"))
        << all(ps);
    EXPECT_NE(all(ps).find("did you mean 'labelled'?"), std::string::npos) << all(ps);
}

TEST(BatchManifest, ValidationReportsABrokenPipelineOnceAndFastSections) {
    const fs::path f = write_manifest("m.csv",
                                      "id,pipeline\n"
                                      "a,broken.yaml\n"
                                      "b,broken.yaml\n"
                                      "c,tension.yaml\n");
    std::ofstream(f.parent_path() / "broken.yaml") << "nodes:\n  box: {type: shape.bx}\n";
    std::vector<Problem> ps;
    const Manifest m = read_manifest(f.string(), ps);
    ASSERT_TRUE(ps.empty()) << all(ps);
    validate_manifest(m, node_registry(), false, ps);
    ASSERT_EQ(ps.size(), 1u) << all(ps);
    EXPECT_NE(format(ps[0]).find("broken.yaml:2:15: error: unknown node type 'shape.bx'"), std::string::npos) << all(ps);
    EXPECT_NE(format(ps[0]).find("in the pipeline of row 'a', manifest line 2"), std::string::npos) << all(ps);
}

TEST(BatchManifest, UnknownFormatAndMissingFile) {
    std::vector<Problem> ps;
    read_manifest("/nonexistent/m.csv", ps);
    ASSERT_EQ(ps.size(), 1u);
    EXPECT_NE(format(ps[0]).find("/nonexistent/m.csv: error: cannot open the manifest file"), std::string::npos);
    const fs::path f = write_manifest("m.txt", "id,pipeline\n");
    ps.clear();
    read_manifest(f.string(), ps);
    ASSERT_EQ(ps.size(), 1u);
    EXPECT_NE(format(ps[0]).find("unknown manifest format '.txt'"), std::string::npos);
}

}  // namespace
}  // namespace cf::runtime::batch
