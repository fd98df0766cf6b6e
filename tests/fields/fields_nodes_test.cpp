// fields.* node adapters through the per-node harness.
#include "nodes/fields/scalar_field.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

TEST(FieldsNodes, LayeredStrengthVaryingWithHeight) {
    // Fig. 18-like strength: minimum 7.6e6 Pa at z = 0, maximum 7.6e7 Pa at z = +-0.5 m.
    const double lo = 7.6e6, hi = 7.6e7;
    auto r = testing::run_node("fields.layered", {{"a", 0.5 * (lo + hi)},
                                                  {"b", 0.5 * (hi - lo)},
                                                  {"frequency", 2 * M_PI},
                                                  {"direction", std::vector<double>{0, 0, 1}},
                                                  {"quantity", std::string("strength")},
                                                  {"compressive_factor", 3.0}});
    const ScalarField& f = r.out<ScalarField>("field");
    EXPECT_EQ(f.quantity, FieldQuantity::strength);
    EXPECT_NEAR(f.value(Vec3(0.3, -0.2, 0.0)), lo, 1e-6 * hi);
    EXPECT_NEAR(f.value(Vec3(0.1, 0.1, 0.5)), hi, 1e-6 * hi);
    EXPECT_NEAR(f.compressive_value(Vec3(0, 0, -0.5)), 3 * hi, 1e-6 * hi);
}

TEST(FieldsNodes, NegativeToughnessFailsTheNode) {
    EXPECT_THROW(testing::run_node("fields.layered", {{"a", 1e5}, {"b", 2e5}}), graph::NodeError);
}

TEST(FieldsNodes, GranularAndHomogeneous) {
    auto g = testing::run_node("fields.granular", {{"grain_size", 0.01}, {"grains_per_tile", 8LL}, {"seed", 4LL}});
    const ScalarField& f = g.out<ScalarField>("field");
    EXPECT_GE(f.value(Vec3(0.001, 0.002, 0.003)), 1e6);
    EXPECT_LE(f.value(Vec3(0.001, 0.002, 0.003)), 1.1e6 + 1e-6);
    auto h = testing::run_node("fields.homogeneous", {{"value", 5e5}});
    EXPECT_EQ(h.out<ScalarField>("field").value(Vec3::Zero()), 5e5);
}

TEST(FieldsNodes, MissingVdbFileNamesTheFile) {
    EXPECT_TRUE(cf::testing::throws<graph::NodeError>(
        [&] { testing::run_node("fields.vdb", {{"file", std::string("/nonexistent/k.vdb")}}); },
        {"/nonexistent/k.vdb"}));
}

}  // namespace
}  // namespace cf
