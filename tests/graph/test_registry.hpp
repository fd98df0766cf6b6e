#pragma once
// A registry of the generic core nodes plus two test-only types: one that always fails and
// one that produces a mesh-like typed value, to check type mismatches.
#include "graph/node_context.hpp"
#include "graph/pipeline.hpp"
#include "nodes/registration.hpp"

#include <fstream>

struct TestBlob {
    int n = 0;
};
CF_GRAPH_TYPE(TestBlob, "TestBlob");

inline const cf::graph::NodeRegistry& test_registry() {
    static const cf::graph::NodeRegistry reg = [] {
        cf::graph::NodeRegistry r;
        cf::register_core_nodes(r);
        {
            cf::graph::NodeType t("test.fail", "Always throws.");
            t.input<double>("value", "ignored");
            t.output<double>("value", "never set");
            t.run([](cf::graph::NodeContext& c) { c.fail("deliberate failure for the test"); });
            r.add(std::move(t));
        }
        {
            cf::graph::NodeType t("test.blob", "Makes a TestBlob.");
            t.output<TestBlob>("blob", "a blob");
            t.param_int("n", 1, "blob size").range(0, 10);
            t.run([](cf::graph::NodeContext& c) { c.out("blob", TestBlob{static_cast<int>(c.integer("n"))}); });
            r.add(std::move(t));
        }
        {
            cf::graph::NodeType t("test.sink", "Writes a value when 'write' is true (a parameter/input rule).");
            t.optional_input<double>("value", "what is written");
            t.param_choice("mode", "off", {"off", "plain", "scaled"}, "what to write");
            t.param_bool("write", false, "write the value");
            t.input_needed_when("value", "mode", {"plain", "scaled"}, "the value to write");
            t.input_needed_when("value", "write", {"true"}, "the value to write");
            t.run([](cf::graph::NodeContext&) {});
            r.add(std::move(t));
        }
        {
            cf::graph::NodeType t("test.read", "Reads a number from a text file (an input path the loader resolves).");
            t.output<double>("value", "the first number in the file");
            t.param_string("path", "", "file to read").required().reads_file();
            t.run([](cf::graph::NodeContext& c) {
                std::ifstream in(c.string("path"));
                double v = 0;
                if (!(in >> v)) c.fail("cannot read a number from " + c.string("path"));
                c.out("value", v);
            });
            r.add(std::move(t));
        }
        return r;
    }();
    return reg;
}

inline cf::graph::Plan load_text(const std::string& text, std::vector<cf::graph::Diagnostic>& diags,
                                 const cf::graph::LoadOptions& options = {}) {
    return cf::graph::load_pipeline_text(text, "test.yaml", test_registry(), options, diags);
}
