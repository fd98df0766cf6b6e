// Pipeline validation: every problem of a file is reported at once, at FILE:LINE:COL, with a hint.
#include "test_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using namespace cf::graph;

namespace {

std::string all(const std::vector<Diagnostic>& diags) {
    std::string s;
    for (const auto& d : diags) s += format(d) + "\n";
    return s;
}

bool has(const std::vector<Diagnostic>& diags, const std::string& needle, int line = 0) {
    for (const auto& d : diags)
        if (format(d).find(needle) != std::string::npos && (line == 0 || d.loc.line == line)) return true;
    return false;
}

}  // namespace

TEST(PipelineValidation, ValidPipelineHasNoDiagnostics) {
    std::vector<Diagnostic> diags;
    Plan plan = load_text(R"(
nodes:
  a: {type: core.real, params: {value: 2}}
  b: {type: core.real, params: {value: 3.5}}
  s: {type: core.add, inputs: {a: a.value, b: b.value}}
)", diags);
    EXPECT_TRUE(diags.empty()) << all(diags);
    ASSERT_EQ(plan.nodes.size(), 3u);
    EXPECT_EQ(plan.nodes.back().name, "s");  // dependencies come first
    EXPECT_DOUBLE_EQ(std::get<double>(plan.nodes[plan.find("a")].params.at("value")), 2.0);
}

TEST(PipelineValidation, ReportsEveryMistakeOfAFileAtOnce) {
    std::vector<Diagnostic> diags;
    load_text(R"(nodes:
  a: {type: core.reel}
  b: {type: core.real, params: {valu: 1}}
  c: {type: core.wait, params: {seconds: 1000}, inputs: {value: b.value}}
  d: {type: core.wait, params: {seconds: fast}, inputs: {value: b.value}}
  e: {type: core.add, inputs: {a: b.valeu, b: b.value}}
  f: {type: core.add, inputs: {a: b.value}}
  g: {type: core.add, inputs: {a: blob.blob, b: b.value}}
  blob: {type: test.blob}
  h: {type: core.add, inputs: {x: b.value, a: b.value, b: b.value}}
  w: {type: core.write_real, inputs: {value: b.value}}
  i: {type: core.add, inputs: {a: nosuch.value, b: b.value}}
)", diags);
    const std::string text = all(diags);
    EXPECT_TRUE(has(diags, "test.yaml:2:13: error: unknown node type 'core.reel'")) << text;
    EXPECT_TRUE(has(diags, "did you mean 'core.real'?")) << text;
    EXPECT_TRUE(has(diags, "unknown parameter 'valu'", 3)) << text;
    EXPECT_TRUE(has(diags, "did you mean 'value'?")) << text;
    EXPECT_TRUE(has(diags, "outside the allowed range [0, 60]", 4)) << text;
    EXPECT_TRUE(has(diags, "expects a number, got 'fast'", 5)) << text;
    EXPECT_TRUE(has(diags, "has no output 'valeu'", 6)) << text;
    EXPECT_TRUE(has(diags, "required input 'b' (Real) of node 'f' is not connected", 7)) << text;
    EXPECT_TRUE(has(diags, "type mismatch: input 'a' of node 'g' expects Real, but 'blob.blob' is TestBlob", 8)) << text;
    EXPECT_TRUE(has(diags, "has no input 'x'", 10)) << text;
    EXPECT_TRUE(has(diags, "missing required parameter 'path'", 11)) << text;
    EXPECT_TRUE(has(diags, "unknown node 'nosuch'", 12)) << text;
    EXPECT_EQ(diags.size(), 10u) << text;
}

TEST(PipelineValidation, YamlSyntaxErrorHasLineAndColumn) {
    std::vector<Diagnostic> diags;
    load_text("nodes:\n  a: {type: core.real\n  b: [\n", diags);
    ASSERT_EQ(diags.size(), 1u);
    EXPECT_NE(format(diags[0]).find("test.yaml:"), std::string::npos);
    EXPECT_NE(format(diags[0]).find("YAML syntax error"), std::string::npos);
    EXPECT_GT(diags[0].loc.line, 1);
}

// A second YAML document used to be ignored silently; now the file is rejected at the second one.
TEST(PipelineValidation, SeveralYamlDocumentsAreAnError) {
    std::vector<Diagnostic> diags;
    load_text("nodes:\n  a: {type: core.real, params: {value: 1}}\n---\nnodes:\n  b: {type: core.real, params: {value: 2}}\n", diags);
    ASSERT_EQ(diags.size(), 1u);
    EXPECT_NE(diags[0].message.find("2 YAML documents"), std::string::npos) << format(diags[0]);
    EXPECT_EQ(diags[0].loc.line, 4) << format(diags[0]);
}

TEST(PipelineValidation, IllegalCycleIsNamed) {
    std::vector<Diagnostic> diags;
    load_text(R"(nodes:
  one: {type: core.real}
  x: {type: core.add, inputs: {a: y.sum, b: one.value}}
  y: {type: core.add, inputs: {a: x.sum, b: one.value}}
)", diags);
    ASSERT_EQ(diags.size(), 1u) << all(diags);
    EXPECT_NE(diags[0].message.find("illegal cycle"), std::string::npos);
    EXPECT_NE(diags[0].message.find("x"), std::string::npos);
    EXPECT_NE(diags[0].message.find("y"), std::string::npos);
    EXPECT_NE(diags[0].hint.find("loop"), std::string::npos);
}

TEST(PipelineValidation, UnknownKeysAndMissingNodes) {
    std::vector<Diagnostic> diags;
    load_text("nodez: {}\n", diags);
    EXPECT_TRUE(has(diags, "unknown top-level key 'nodez'")) << all(diags);
    EXPECT_TRUE(has(diags, "did you mean 'nodes'?")) << all(diags);
    EXPECT_TRUE(has(diags, "missing top-level 'nodes:'")) << all(diags);
    diags.clear();
    load_text("nodes:\n  a: {type: core.real, parms: {value: 1}}\n", diags);
    EXPECT_TRUE(has(diags, "unknown key 'parms'", 2)) << all(diags);
    EXPECT_TRUE(has(diags, "did you mean 'params'?")) << all(diags);
}

TEST(PipelineValidation, OverridesAreValidatedLikeTheFile) {
    std::vector<Diagnostic> diags;
    LoadOptions options;
    options.overrides.push_back(*parse_override("w.seconds=99", diags));
    options.overrides.push_back(*parse_override("a.value=2.5", diags));
    options.overrides.push_back(*parse_override("nosuchnode.value=1", diags));
    ASSERT_TRUE(diags.empty());
    Plan plan = load_text(R"(nodes:
  a: {type: core.real, params: {value: 1}}
  w: {type: core.wait, inputs: {value: a.value}}
)", diags, options);
    EXPECT_TRUE(has(diags, "parameter 'seconds' of node 'w' value 99 is outside the allowed range [0, 60]")) << all(diags);
    EXPECT_TRUE(has(diags, "override 'nosuchnode.value' names no node")) << all(diags);
    EXPECT_EQ(diags.size(), 2u) << all(diags);

    std::vector<Diagnostic> bad;
    EXPECT_FALSE(parse_override("novalue", bad).has_value());
    ASSERT_EQ(bad.size(), 1u);
    EXPECT_NE(bad[0].message.find("NODE.PARAM=VALUE"), std::string::npos);
}

TEST(PipelineValidation, FastOverridesApplyOnlyInFastMode) {
    const std::string text = R"(nodes:
  a: {type: core.real, params: {value: 1}}
fast:
  a.value: 7
)";
    std::vector<Diagnostic> diags;
    Plan normal = load_text(text, diags);
    LoadOptions fast;
    fast.fast = true;
    Plan quick = load_text(text, diags, fast);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_DOUBLE_EQ(std::get<double>(normal.nodes[0].params.at("value")), 1.0);
    EXPECT_DOUBLE_EQ(std::get<double>(quick.nodes[0].params.at("value")), 7.0);
}

// A node inside a loop body is overridden by its own name (names are global); the loop-qualified
// spelling LOOP.NODE.PARAM gets an error that says so.
TEST(PipelineValidation, FastOverridesReachLoopBodies) {
    const std::string body = R"(nodes:
  zero: {type: core.real}
  count:
    type: loop
    params: {max_iterations: 3}
    inputs: {n: zero.value}
    body:
      hold: {type: core.wait, inputs: {value: count.n}, params: {seconds: 0}}
      inc: {type: core.add, inputs: {a: hold.value, b: count.n}}
    next: {n: inc.sum}
fast:
)";
    LoadOptions fast;
    fast.fast = true;
    std::vector<Diagnostic> diags;
    const Plan quick = load_text(body + "  hold.seconds: 0.5\n", diags, fast);
    ASSERT_TRUE(diags.empty()) << all(diags);
    bool found = false;
    for (const auto& n : quick.nodes)
        if (n.name == "hold") {
            EXPECT_DOUBLE_EQ(std::get<double>(n.params.at("seconds")), 0.5);
            found = true;
        }
    EXPECT_TRUE(found);
    load_text(body + "  count.hold.seconds: 0.5\n", diags, fast);
    EXPECT_TRUE(has(diags, "override 'count.hold.seconds' names node 'hold' through 'count'")) << all(diags);
    EXPECT_TRUE(has(diags, "write hold.seconds:")) << all(diags);
}

TEST(PipelineValidation, LoopScopingRules) {
    std::vector<Diagnostic> diags;
    load_text(R"(nodes:
  zero: {type: core.real}
  one: {type: core.real, params: {value: 1}}
  count:
    type: loop
    inputs: {n: zero.value}
    body:
      inc: {type: core.add, inputs: {a: count.n, b: one.value}}
      lonely: {type: core.real}
    next: {n: inc.sum}
  outside: {type: core.add, inputs: {a: inc.sum, b: count.n}}
)", diags);
    EXPECT_TRUE(has(diags, "node 'lonely' is in the body of loop 'count' but uses no loop value")) << all(diags);
    EXPECT_TRUE(has(diags, "'inc' is inside the body of loop 'count'", 11)) << all(diags);
    EXPECT_TRUE(has(diags, "exists only inside the body of loop 'count'", 11)) << all(diags);
    EXPECT_EQ(diags.size(), 3u) << all(diags);
}

TEST(PipelineValidation, LoopNeedsNextForEveryVariableAndBoolWhile) {
    std::vector<Diagnostic> diags;
    load_text(R"(nodes:
  zero: {type: core.real}
  count:
    type: loop
    inputs: {n: zero.value, m: zero.value}
    body:
      inc: {type: core.add, inputs: {a: count.n, b: count.m}}
    next: {n: inc.sum}
    while: inc.sum
)", diags);
    EXPECT_TRUE(has(diags, "gives no next value for variable 'm'")) << all(diags);
    EXPECT_TRUE(has(diags, "'while' must be Bool, got Real")) << all(diags);
}

// `loop` is declared in the registry like every node type: its parameters are validated from
// that declaration (range, unknown names with a suggestion), and it is listed with the others.
TEST(PipelineValidation, LoopIsDeclaredLikeEveryNodeType) {
    const NodeType* loop = test_registry().find("loop");
    ASSERT_NE(loop, nullptr);
    EXPECT_TRUE(loop->is_executor_construct());
    const ParamDecl* max = loop->find_param("max_iterations");
    ASSERT_NE(max, nullptr);
    EXPECT_EQ(std::get<long long>(*max->default_value), 100);
    EXPECT_EQ(max->describe_range(), "[1, 1000000000]");
    EXPECT_NE(loop->find_output("final.VAR"), nullptr);
    const auto names = test_registry().names();
    EXPECT_NE(std::find(names.begin(), names.end(), "loop"), names.end());

    const std::string body = R"(nodes:
  zero: {type: core.real}
  count:
    type: loop
    params: {PARAMS}
    inputs: {n: zero.value}
    body:
      inc: {type: core.add, inputs: {a: count.n, b: count.n}}
    next: {n: inc.sum}
)";
    const auto with = [&](const std::string& params) {
        std::string text = body;
        text.replace(text.find("PARAMS"), 6, params);
        return text;
    };
    std::vector<Diagnostic> diags;
    const Plan plan = load_text(with("max_iterations: 7"), diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(plan.nodes[plan.find("count")].max_iterations, 7);
    EXPECT_TRUE(plan.nodes[plan.find("count")].params.empty());  // report.json writes max_iterations once

    diags.clear();
    const Plan defaults = load_text(with(""), diags);
    ASSERT_TRUE(diags.empty()) << all(diags);
    EXPECT_EQ(defaults.nodes[defaults.find("count")].max_iterations, 100);

    diags.clear();
    load_text(with("max_iterations: 0, max_iteration: 3"), diags);
    EXPECT_TRUE(has(diags, "value 0 is outside the allowed range [1, 1000000000]", 5)) << all(diags);
    EXPECT_TRUE(has(diags, "unknown parameter 'max_iteration' for node 'count' (loop)", 5)) << all(diags);
    EXPECT_TRUE(has(diags, "did you mean 'max_iterations'?")) << all(diags);
    EXPECT_EQ(diags.size(), 2u) << all(diags);
}

// A parameter value that needs an optional input is reported at the parameter's FILE:LINE by
// validation, not by the node at run time.
TEST(PipelineValidation, InputsNeededByParametersAreCheckedBeforeARun) {
    std::vector<Diagnostic> diags;
    load_text(R"(nodes:
  v: {type: core.real, params: {value: 1}}
  a: {type: test.sink, params: {mode: scaled}}
  b: {type: test.sink, inputs: {value: v.value}, params: {mode: plain, write: true}}
  c: {type: test.sink, params: {mode: off}}
  d: {type: test.sink,
      params: {write: true}}
  e: {type: test.sink, params: {mode: plain}, inputs: {value: v.valu}}
)", diags);
    const std::string text = all(diags);
    EXPECT_TRUE(has(diags, "test.yaml:3:", 3)) << text;
    EXPECT_TRUE(has(diags, "error: parameter 'mode' = scaled of node 'a' (test.sink) needs the input 'value' (Real), which is "
                           "not connected", 3)) << text;
    EXPECT_TRUE(has(diags, "hint: connect it: inputs: {value: NODE.PORT} (the value to write), or change 'mode'")) << text;
    EXPECT_TRUE(has(diags, "parameter 'write' = true of node 'd' (test.sink) needs the input 'value'", 7)) << text;
    EXPECT_TRUE(has(diags, "has no output 'valu'", 8)) << text;  // a mistyped input is one error, not two
    EXPECT_EQ(diags.size(), 3u) << text;

    // An override that turns the option on is reported at the override.
    LoadOptions set;
    set.overrides.push_back({"c", "mode", "plain", SourceLoc{"--set", 1, 1}});
    diags.clear();
    load_text(R"(nodes:
  c: {type: test.sink}
)", diags, set);
    EXPECT_EQ(diags.size(), 1u) << all(diags);
    EXPECT_TRUE(has(diags, "--set:1:1: error: parameter 'mode' = plain of node 'c'")) << all(diags);
}

TEST(NodeType, RulesNameRealInputsParametersAndValues) {
    const auto type = [] {
        NodeType t("test.rules", "A node type for rule declarations.");
        t.optional_input<double>("value", "optional");
        t.input<double>("needed", "required");
        t.param_choice("mode", "off", {"off", "on"}, "a choice");
        t.param_real("scale", 1, "", "a number");
        return t;
    };
    EXPECT_NO_THROW(type().input_needed_when("value", "mode", {"on"}, "why"));
    EXPECT_THROW(type().input_needed_when("needed", "mode", {"on"}, "why"), std::logic_error);  // not optional
    EXPECT_THROW(type().input_needed_when("nosuch", "mode", {"on"}, "why"), std::logic_error);
    EXPECT_THROW(type().input_needed_when("value", "nosuch", {"on"}, "why"), std::logic_error);
    EXPECT_THROW(type().input_needed_when("value", "mode", {"maybe"}, "why"), std::logic_error);
    EXPECT_THROW(type().input_needed_when("value", "scale", {"1"}, "why"), std::logic_error);
}
