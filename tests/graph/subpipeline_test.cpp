// Sub-pipelines (`type: use`): a file used twice with different parameters, errors inside a used
// file (both files and lines), overrides of a use node's parameters, optional inputs, nesting and
// self-use, the printed pipeline and the dot graph.
#include "graph/executor.hpp"
#include "graph/input_paths.hpp"
#include "test_registry.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / "crackflow-tests" / ("subpipeline-" + name);
    fs::remove_all(d);
    fs::create_directories(d / "lib");
    return d;
}

void write(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

double read_number(const fs::path& p) {
    std::ifstream in(p);
    double v = -1;
    in >> v;
    return v;
}

std::string all(const std::vector<cf::graph::Diagnostic>& diags) {
    std::string s;
    for (const auto& d : diags) s += cf::graph::format(d) + "\n";
    return s;
}

// y = x + k, written to `out`; k and out are the file's parameters.
const char* kAddLib = R"(description: adds k to x
parameters:
  k: {to: k.value, doc: "the number added"}
  out: {to: write.path}
inputs:
  x: {type: Real, doc: "the number k is added to"}
outputs:
  y: add.sum
nodes:
  k: {type: core.real, params: {value: 1}}
  add: {type: core.add, inputs: {a: input.x, b: k.value}}
  write: {type: core.write_real, inputs: {value: add.sum}, params: {path: y.txt}}
)";

}  // namespace

// The same file used twice in one pipeline, chained, with different parameters: every node is
// there twice (a/..., b/...), each with its own values, and the results are the hand values
// 2 + 3 = 5 and 5 + 10 = 15.
TEST(SubPipeline, UsedTwiceWithDifferentParameters) {
    const fs::path d = fresh_dir("twice");
    write(d / "lib" / "add.yaml", kAddLib);
    write(d / "main.yaml", R"(nodes:
  x: {type: core.real, params: {value: 2}}
  a: {type: use, use: lib/add.yaml, inputs: {x: x.value}, params: {k: 3, out: a.txt}}
  b: {type: use, use: lib/add.yaml, inputs: {x: a.y}, params: {k: 10, out: b.txt}}
  total: {type: core.write_real, inputs: {value: b.y}, params: {path: total.txt}}
)");
    std::vector<cf::graph::Diagnostic> diags;
    const auto plan = cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), {}, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    ASSERT_GE(plan.find("a/k"), 0);
    ASSERT_GE(plan.find("b/k"), 0);
    EXPECT_EQ(std::get<double>(plan.nodes[plan.find("a/k")].params.at("value")), 3.0);
    EXPECT_EQ(std::get<double>(plan.nodes[plan.find("b/k")].params.at("value")), 10.0);
    ASSERT_EQ(plan.uses.size(), 2u);
    EXPECT_EQ(plan.uses[0].name, "a");
    EXPECT_EQ(plan.uses[0].file, (d / "lib" / "add.yaml").string());
    cf::graph::RunOptions run;
    run.output_dir = d / "out";
    const auto r = cf::graph::execute(plan, run);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(read_number(d / "out" / "a.txt"), 5.0);
    EXPECT_EQ(read_number(d / "out" / "b.txt"), 15.0);
    EXPECT_EQ(read_number(d / "out" / "total.txt"), 15.0);
    EXPECT_FALSE(fs::exists(d / "out" / "y.txt"));  // the file's own default path was replaced in both uses

    // --set on a use node's parameter, and on one of its nodes directly.
    cf::graph::LoadOptions o;
    o.overrides = {{"a", "k", "7", {"--set", 0, 0}}, {"b/k", "value", "0.5", {"--set", 0, 0}}};
    const auto p2 = cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), o, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(std::get<double>(p2.nodes[p2.find("a/k")].params.at("value")), 7.0);
    EXPECT_EQ(std::get<double>(p2.nodes[p2.find("b/k")].params.at("value")), 0.5);
    o.overrides = {{"a", "kk", "7", {"--set", 0, 0}}};
    cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), o, diags);
    ASSERT_EQ(diags.size(), 1u) << all(diags);
    EXPECT_NE(diags[0].message.find("has no parameter 'kk'"), std::string::npos) << all(diags);
    EXPECT_NE(diags[0].hint.find("did you mean 'k'?"), std::string::npos) << all(diags);

    // The dot graph draws each use as a cluster around its nodes.
    const std::string dot = cf::graph::to_dot(plan);
    EXPECT_NE(dot.find("subgraph \"cluster_use_a\""), std::string::npos) << dot;
    EXPECT_NE(dot.find("subgraph \"cluster_use_b\""), std::string::npos) << dot;
}

// An error inside a used file is reported at its line in that file, with the line of the use
// node in the using file.
TEST(SubPipeline, ErrorInsideNamesBothFilesAndLines) {
    const fs::path d = fresh_dir("error");
    write(d / "lib" / "bad.yaml", R"(inputs:
  x: {type: Real}
outputs:
  y: add.sum
nodes:
  add: {type: core.add, inputs: {a: input.x, b: input.x}}
  oops: {type: core.real, params: {valeu: 1}}
)");
    write(d / "main.yaml", R"(nodes:
  x: {type: core.real, params: {value: 2}}

  inner: {type: use, use: lib/bad.yaml, inputs: {x: x.value}}
)");
    std::vector<cf::graph::Diagnostic> diags;
    cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), {}, diags);
    ASSERT_EQ(diags.size(), 1u) << all(diags);
    const auto& e = diags[0];
    EXPECT_EQ(e.loc.file, (d / "lib" / "bad.yaml").string());
    EXPECT_EQ(e.loc.line, 7);  // `valeu:` in bad.yaml
    EXPECT_EQ(e.loc.column, 36);
    EXPECT_EQ(e.loc.via, (d / "main.yaml").string() + ":4:3 (node 'inner')");
    const std::string text = cf::graph::format(e);
    EXPECT_NE(text.find("lib/bad.yaml:7:36: error: unknown parameter 'valeu' for node 'inner/oops'"), std::string::npos) << text;
    EXPECT_NE(text.find("in a sub-pipeline used at " + (d / "main.yaml").string() + ":4:3 (node 'inner')"), std::string::npos)
        << text;

    // Wiring mistakes are reported in the using file: an undeclared input, a missing one, a wrong
    // type and an output the file does not declare.
    write(d / "main2.yaml", R"(nodes:
  x: {type: core.real, params: {value: 2}}
  blob: {type: test.blob}
  inner: {type: use, use: lib/add.yaml, inputs: {x: blob.blob, z: x.value}, params: {k: 2}}
  other: {type: use, use: lib/add.yaml, params: {k: 2}}
  sum: {type: core.add, inputs: {a: inner.why, b: x.value}}
)");
    write(d / "lib" / "add.yaml", kAddLib);
    diags.clear();
    cf::graph::load_pipeline_file((d / "main2.yaml").string(), test_registry(), {}, diags);
    const std::string t2 = all(diags);
    EXPECT_NE(t2.find("main2.yaml:4:64: error: sub-pipeline " + (d / "lib" / "add.yaml").string() +
                      " (node 'inner') has no input 'z'"),
              std::string::npos)
        << t2;
    EXPECT_NE(t2.find("main2.yaml:5:3: error: input 'x' (Real) of sub-pipeline"), std::string::npos) << t2;
    EXPECT_NE(t2.find("main2.yaml:4:53: error: input 'x' of sub-pipeline"), std::string::npos) << t2;
    EXPECT_NE(t2.find("is Real, but 'blob.blob' is TestBlob"), std::string::npos) << t2;
    EXPECT_NE(t2.find("main2.yaml:6:37: error: 'inner.why': sub-pipeline"), std::string::npos) << t2;
    EXPECT_NE(t2.find("did you mean 'y'?"), std::string::npos) << t2;

    // A file cannot use itself; a missing file names the absolute path tried.
    write(d / "lib" / "self.yaml", "inputs: {x: Real}\nnodes:\n  again: {type: use, use: self.yaml, inputs: {x: input.x}}\n");
    write(d / "main3.yaml", "nodes:\n  x: {type: core.real}\n  s: {type: use, use: lib/self.yaml, inputs: {x: x.value}}\n"
                            "  m: {type: use, use: lib/missing.yaml}\n");
    diags.clear();
    cf::graph::load_pipeline_file((d / "main3.yaml").string(), test_registry(), {}, diags);
    const std::string t3 = all(diags);
    EXPECT_NE(t3.find("uses itself"), std::string::npos) << t3;
    EXPECT_NE(t3.find("not found: " + (d / "lib" / "missing.yaml").string()), std::string::npos) << t3;

    // A sub-pipeline on its own is not a runnable pipeline.
    diags.clear();
    cf::graph::load_pipeline_file((d / "lib" / "add.yaml").string(), test_registry(), {}, diags);
    EXPECT_NE(all(diags).find("declares a sub-pipeline's interface; this file is run on its own"), std::string::npos)
        << all(diags);
}

// Nested uses, an optional input left unconnected, and a use node's parameter that targets a
// parameter of a nested use node.
TEST(SubPipeline, NestedUsesAndOptionalInputs) {
    const fs::path d = fresh_dir("nested");
    write(d / "lib" / "add.yaml", kAddLib);
    write(d / "lib" / "twice.yaml", R"(parameters:
  k: {to: [first.k, second.k]}
inputs:
  x: {type: Real}
  unused: {type: Real, optional: true}
outputs:
  y: second.y
nodes:
  first: {type: use, use: add.yaml, inputs: {x: input.x}, params: {out: first.txt}}
  second: {type: use, use: add.yaml, inputs: {x: first.y}, params: {out: second.txt}}
  sink: {type: test.sink, inputs: {value: input.unused}}
)");
    write(d / "main.yaml", R"(nodes:
  x: {type: core.real, params: {value: 1}}
  t: {type: use, use: lib/twice.yaml, inputs: {x: x.value}, params: {k: 4}}
  w: {type: core.write_real, inputs: {value: t.y}, params: {path: w.txt}}
)");
    std::vector<cf::graph::Diagnostic> diags;
    const auto plan = cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), {}, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_GE(plan.find("t/first/k"), 0);
    EXPECT_TRUE(plan.nodes[plan.find("t/sink")].inputs.empty());  // the optional input stayed unconnected
    cf::graph::RunOptions run;
    run.output_dir = d / "out";
    const auto r = cf::graph::execute(plan, run);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(read_number(d / "out" / "w.txt"), 9.0);  // 1 + 4 + 4
    EXPECT_EQ(read_number(d / "out" / "first.txt"), 5.0);
}

// --print-pipeline's text (graph::to_yaml) loads again to the same plan: same nodes, parameters
// and connections, with no sub-pipeline left.
TEST(SubPipeline, PrintedPipelineLoadsToTheSamePlan) {
    const fs::path d = fresh_dir("print");
    write(d / "lib" / "add.yaml", kAddLib);
    write(d / "main.yaml", R"(nodes:
  x: {type: core.real, params: {value: 0.1}}
  a: {type: use, use: lib/add.yaml, inputs: {x: x.value}, params: {k: 2.9499e-4, out: a.txt}}
  grow:
    type: loop
    params: {max_iterations: 3}
    inputs: {v: a.y}
    body:
      more: {type: core.add, inputs: {a: grow.v, b: x.value}}
    next: {v: more.sum}
  w: {type: core.write_real, inputs: {value: grow.final.v}, params: {path: "w: final.txt"}}
fast:
  a.k: 5
)");
    cf::graph::LoadOptions o;
    o.fast = true;
    o.overrides = {{"x", "value", "0.25", {"--set", 0, 0}}};
    std::vector<cf::graph::Diagnostic> diags;
    const auto plan = cf::graph::load_pipeline_file((d / "main.yaml").string(), test_registry(), o, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    const std::string text = cf::graph::to_yaml(plan);
    EXPECT_NE(text.find("a/k:"), std::string::npos) << text;
    EXPECT_EQ(text.find("type: use"), std::string::npos) << text;
    const auto again = cf::graph::load_pipeline_text(text, "printed.yaml", test_registry(), {}, diags);
    ASSERT_TRUE(diags.empty()) << all(diags) << text;
    ASSERT_EQ(again.nodes.size(), plan.nodes.size()) << text;
    for (std::size_t i = 0; i < plan.nodes.size(); ++i) {
        const auto& p = plan.nodes[i];
        const int j = again.find(p.name);
        ASSERT_GE(j, 0) << p.name;
        const auto& q = again.nodes[static_cast<std::size_t>(j)];
        EXPECT_EQ(p.params, q.params) << p.name;
        EXPECT_EQ(p.max_iterations, q.max_iterations) << p.name;
        ASSERT_EQ(p.inputs.size(), q.inputs.size()) << p.name;
        for (std::size_t k = 0; k < p.inputs.size(); ++k) {
            EXPECT_EQ(plan.nodes[p.inputs[k].source].name, again.nodes[q.inputs[k].source].name) << p.name;
            EXPECT_EQ(p.inputs[k].source_port, q.inputs[k].source_port) << p.name;
            EXPECT_EQ(p.inputs[k].kind, q.inputs[k].kind) << p.name;
        }
    }
    // The overrides are in it: --fast's a.k and --set's x.value.
    EXPECT_EQ(std::get<double>(again.nodes[again.find("a/k")].params.at("value")), 5.0);
    EXPECT_EQ(std::get<double>(again.nodes[again.find("x")].params.at("value")), 0.25);
    EXPECT_EQ(std::get<std::string>(again.nodes[again.find("w")].params.at("path")), "w: final.txt");
}

// A sub-pipeline not beside the using file is looked up on CRACKFLOW_PIPELINE_PATH, in order (a
// library of the user's own, shared by pipelines in other directories); a file beside the using
// file comes first; a file found nowhere names every absolute path tried, in order.
TEST(SubPipeline, FoundOnThePipelinePathAfterTheUsingFilesDirectory) {
    const fs::path d = fresh_dir("search-path");
    write(d / "shared" / "lib" / "add.yaml", kAddLib);
    write(d / "project" / "main.yaml", R"(nodes:
  x: {type: core.real, params: {value: 2}}
  a: {type: use, use: lib/add.yaml, inputs: {x: x.value}, params: {k: 3, out: a.txt}}
)");
    ::setenv(cf::graph::kPipelinePathVariable, ((d / "empty").string() + "::" + (d / "shared").string()).c_str(), 1);
    std::vector<cf::graph::Diagnostic> diags;
    auto plan = cf::graph::load_pipeline_file((d / "project" / "main.yaml").string(), test_registry(), {}, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    ASSERT_EQ(plan.uses.size(), 1u);
    EXPECT_EQ(plan.uses[0].file, (d / "shared" / "lib" / "add.yaml").string());
    cf::graph::RunOptions run;
    run.output_dir = d / "out";
    auto r = cf::graph::execute(plan, run);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(read_number(d / "out" / "a.txt"), 5.0);  // 2 + 3 by the shared file

    // A file of the same name beside the using file shadows the shared one: it adds k twice.
    write(d / "project" / "lib" / "add.yaml", R"(parameters:
  k: {to: k.value}
  out: {to: write.path}
inputs:
  x: {type: Real}
outputs:
  y: twice.sum
nodes:
  k: {type: core.real, params: {value: 1}}
  once: {type: core.add, inputs: {a: input.x, b: k.value}}
  twice: {type: core.add, inputs: {a: once.sum, b: k.value}}
  write: {type: core.write_real, inputs: {value: twice.sum}, params: {path: y.txt}}
)");
    diags.clear();
    plan = cf::graph::load_pipeline_file((d / "project" / "main.yaml").string(), test_registry(), {}, diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    r = cf::graph::execute(plan, run);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(read_number(d / "out" / "a.txt"), 8.0);  // 2 + 3 + 3 by the local file

    write(d / "project" / "missing.yaml", "nodes:\n  m: {type: use, use: lib/none.yaml}\n");
    diags.clear();
    cf::graph::load_pipeline_file((d / "project" / "missing.yaml").string(), test_registry(), {}, diags);
    ::unsetenv(cf::graph::kPipelinePathVariable);
    ASSERT_EQ(diags.size(), 1u) << all(diags);
    const std::string text = all(diags);
    EXPECT_EQ(diags[0].loc.line, 2);
    const auto a = text.find((d / "project" / "lib" / "none.yaml").string());
    const auto b = text.find((d / "empty" / "lib" / "none.yaml").string());
    const auto c = text.find((d / "shared" / "lib" / "none.yaml").string());
    EXPECT_NE(a, std::string::npos) << text;
    EXPECT_TRUE(a < b && b < c && c != std::string::npos) << text;
    EXPECT_NE(text.find("CRACKFLOW_PIPELINE_PATH"), std::string::npos) << text;
}
