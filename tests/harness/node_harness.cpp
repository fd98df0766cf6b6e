#include "tests/harness/node_harness.hpp"

#include "nodes/domain/verification_case.hpp"

#include <gtest/gtest.h>

#include <iostream>

namespace cf::testing {

graph::NodeResult run_node(const std::string& type, const Params& params, const Inputs& inputs,
                           const std::filesystem::path& output_dir) {
    const graph::NodeType* t = node_registry().find(type);
    if (!t) throw std::logic_error("no node type '" + type + "' registered");
    graph::RunOptions options;
    options.output_dir = output_dir.empty() ? temp_dir(type) : output_dir;
    return graph::run_node(*t, params, inputs, options, type);
}

void expect_verification_case_passes(const std::string& name) {
    for (const auto& c : verification_cases())
        if (c.name == name) {
            const VerificationResult r = c.run();
            EXPECT_TRUE(r.passed) << r.details;
            EXPECT_LE(r.error, r.tolerance) << r.details;
            std::cout << r.details << "\n";
            return;
        }
    ADD_FAILURE() << "verification case " << name << " is not registered";
}

std::filesystem::path temp_dir(const std::string& tag) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = tag;
    if (info) name += std::string("-") + info->test_suite_name() + "-" + info->name();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
    auto dir = std::filesystem::temp_directory_path() / "crackflow-tests" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace cf::testing
