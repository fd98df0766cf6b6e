// The shipped estimator pipelines are their full-BEM cases with one line changed (the method the
// case file gives the fracture loop of pipelines/lib/fracture.yaml), and they run the same with
// one thread and with two.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/register_all.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

const std::string kDir = std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/";

// The file's lines without the top-level `description:` block (prose about the case).
std::vector<std::string> pipeline_lines(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> out;
    std::string line;
    bool in_description = false;
    while (std::getline(in, line)) {
        if (line.rfind("description:", 0) == 0) {
            in_description = true;
            continue;
        }
        if (in_description && (line.empty() || line[0] == ' ')) continue;
        in_description = false;
        out.push_back(line);
    }
    return out;
}

}  // namespace

TEST(EstimatorPipelines, EachDiffersFromItsFullBemCaseInOneLine) {
    int pairs = 0;
    for (const auto& e : std::filesystem::directory_iterator(kDir)) {
        const std::string stem = e.path().stem().string();
        const std::string suffix = "_estimator";
        if (stem.size() <= suffix.size() || stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
        const std::string base = kDir + stem.substr(0, stem.size() - suffix.size()) + ".yaml";
        ASSERT_TRUE(std::filesystem::exists(base)) << stem << " has no full-BEM case " << base;
        const auto a = pipeline_lines(base), b = pipeline_lines(e.path().string());
        ASSERT_EQ(a.size(), b.size()) << stem;
        int differ = 0;
        for (std::size_t i = 0; i < a.size(); ++i)
            if (a[i] != b[i]) {
                ++differ;
                EXPECT_NE(a[i].find("method: full"), std::string::npos) << stem << ": " << a[i];
                EXPECT_NE(b[i].find("method: estimator"), std::string::npos) << stem << ": " << b[i];
            }
        EXPECT_EQ(differ, 1) << stem << " differs from " << base << " in " << differ << " lines";
        ++pairs;
    }
    EXPECT_GE(pairs, 6);
}

namespace {
void expect_thread_independent(const std::string& file, const std::vector<cf::graph::Override>& sets) {
    std::vector<std::vector<std::map<std::string, double>>> per_run;
    std::vector<cf::SurfaceMesh> cracks;
    for (int threads : {1, 2}) {
        tbb::global_control g(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<cf::graph::Diagnostic> diags;
        cf::graph::LoadOptions lo;
        lo.fast = true;
        lo.overrides = sets;
        auto plan = cf::graph::load_pipeline_file(kDir + file, cf::node_registry(), lo, diags);
        ASSERT_TRUE(diags.empty());
        cf::graph::RunOptions run;
        run.fast = true;
        run.output_dir = cf::testing::temp_dir("estimator-threads-" + std::to_string(threads) + "-" + file);
        auto res = cf::graph::execute(plan, run);
        ASSERT_TRUE(res.ok) << res.error;
        for (const auto& s : res.stats)
            if (s.name == "fracture/sifs") {
                auto counts = s.iteration_counts;
                for (auto& c : counts) c.erase("wall_seconds");
                per_run.push_back(counts);
            }
        cracks.push_back(res.outputs.at("fracture/final").at("cracks").get<cf::SurfaceMesh>());
    }
    ASSERT_EQ(per_run.size(), 2u);
    EXPECT_EQ(per_run[0], per_run[1]) << file;
    EXPECT_EQ(cracks[0].vertices, cracks[1].vertices) << file;
    EXPECT_EQ(cracks[0].triangles, cracks[1].triangles) << file;
}
}  // namespace

TEST(EstimatorPipelines, SameResultsWithOneAndTwoThreads) {
    expect_thread_independent("edge_crack_mode2_estimator.yaml", {{"fracture", "max_iterations", "4", {}}});
    // A hybrid run that switches mid-way (frozen cracks, estimated growth after step 3).
    expect_thread_independent("edge_crack_mode1.yaml", {{"fracture", "method", "hybrid", {}},
                                                        {"fracture", "switch_elements", "370", {}},
                                                        {"fracture", "max_iterations", "5", {}}});
}
