#pragma once
// Per-node test harness: instantiate any registered node alone, feed typed inputs, run it,
// get typed outputs back. Parameters are checked exactly as in a pipeline.
//
//   auto r = cf::testing::run_node("shape.box", {{"size", std::vector<double>{1, 2, 3}}});
//   const cf::SurfaceMesh& m = r.out<cf::SurfaceMesh>("mesh");
#include "graph/run_node.hpp"
#include "nodes/register_all.hpp"

#include <filesystem>
#include <map>
#include <string>

namespace cf::testing {

using Params = std::map<std::string, graph::ParamValue>;
using Inputs = std::map<std::string, graph::Value>;

// Runs the named node type; throws graph::NodeError on bad parameters/inputs or node failure.
graph::NodeResult run_node(const std::string& type, const Params& params = {}, const Inputs& inputs = {},
                           const std::filesystem::path& output_dir = {});

// Runs the registered verification case `name` (as `crackflow verify --case name` does) and
// expects it to pass within its tolerance; prints its details. Fails the test if no such case.
void expect_verification_case_passes(const std::string& name);

// A fresh, empty temporary directory unique to the calling test.
std::filesystem::path temp_dir(const std::string& tag);

template <class T>
graph::Value value(T v) { return graph::Value::of<T>(std::move(v)); }

}  // namespace cf::testing
