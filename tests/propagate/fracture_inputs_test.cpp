// Bad inputs of a fracture simulation give clear errors naming the file and line, the node and
// the parameter, and how to fix it (issue #5): a missing material parameter, nu outside
// (0, 0.5), r_f >= r_c, a negative toughness field, an initial crack outside the object, and a
// strength field connected where toughness is expected.
#include "graph/pipeline.hpp"
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_state.hpp"
#include "nodes/shape/box.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

using namespace cf;
using cf::testing::run_node;
using cf::testing::value;

namespace {

std::string load_errors(const std::string& yaml) {
    std::vector<graph::Diagnostic> diags;
    graph::load_pipeline_text(yaml, "case.yaml", node_registry(), {}, diags);
    std::string text;
    for (const auto& d : diags) text += graph::format(d) + "\n";
    return text;
}

std::string node_error(const std::string& type, const cf::testing::Params& p, const cf::testing::Inputs& in = {}) {
    try {
        run_node(type, p, in);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

const char* material_header = "nodes:\n  material:\n    type: material.brittle\n";

SurfaceMesh unit_box() {
    auto r = run_node("shape.box", {{"size", std::vector<double>{0.1, 0.1, 0.1}}, {"subdivisions", 4LL}});
    return r.out<SurfaceMesh>("mesh");
}

}  // namespace

TEST(FractureInputs, MissingMaterialParameterNamesItAndTheLine) {
    const std::string e = load_errors(std::string(material_header) +
                                      "    params: {E: 3.1e9, nu: 0.327, rho: 1200, tensile_strength: 7.6e7, compressive_factor: 2}\n");
    EXPECT_NE(e.find("case.yaml:"), std::string::npos) << e;
    EXPECT_NE(e.find("toughness"), std::string::npos) << e;
    EXPECT_NE(e.find("material"), std::string::npos) << e;
}

TEST(FractureInputs, PoissonRatioOutsideTheOpenIntervalIsRejected) {
    for (const char* nu : {"0.5", "0", "-0.1", "0.7"}) {
        const std::string e = load_errors(std::string(material_header) + "    params: {E: 3.1e9, nu: " + nu +
                                          ", rho: 1200, tensile_strength: 7.6e7, toughness: 1e6, compressive_factor: 2}\n");
        EXPECT_NE(e.find("nu"), std::string::npos) << nu << ": " << e;
        EXPECT_NE(e.find("(0, 0.5)"), std::string::npos) << nu << ": " << e;
    }
    // In range: no error.
    EXPECT_EQ(load_errors(std::string(material_header) +
                          "    params: {E: 3.1e9, nu: 0.3, rho: 1200, tensile_strength: 7.6e7, toughness: 1e6, compressive_factor: 2}\n"),
              "");
}

TEST(FractureInputs, CoarseResolutionMustExceedTheLevelSetVoxel) {
    const SurfaceMesh box = unit_box();
    const LevelSet object = level_set_from_mesh(box, 0.005);
    const std::string e = node_error("fracture.start", {{"r_c", 0.004}}, {{"mesh", value(box)}, {"object", value(object)}});
    EXPECT_NE(e.find("r_c"), std::string::npos) << e;
    EXPECT_NE(e.find("r_f"), std::string::npos) << e;
    EXPECT_NE(e.find("larger than"), std::string::npos) << e;
    EXPECT_EQ(node_error("fracture.start", {{"r_c", 0.02}}, {{"mesh", value(box)}, {"object", value(object)}}), "");
}

TEST(FractureInputs, NegativeToughnessFieldIsRejected) {
    // A constant below zero fails validation; a layered field dipping below zero fails when built.
    EXPECT_NE(load_errors("nodes:\n  k: {type: fields.homogeneous, params: {value: -1e6}}\n").find("value"), std::string::npos);
    const std::string e = node_error("fields.layered", {{"a", 1e5}, {"b", 2e5}, {"quantity", std::string("toughness")}});
    EXPECT_NE(e.find("toughness"), std::string::npos) << e;
    EXPECT_NE(e.find("reaches -100000"), std::string::npos) << e;
    EXPECT_NE(e.find("must be >= 0 everywhere"), std::string::npos) << e;
}

TEST(FractureInputs, InitialCrackOutsideTheObjectIsRejected) {
    const SurfaceMesh box = unit_box();
    const LevelSet object = level_set_from_mesh(box, 0.005);
    const propagate::FractureState state = propagate::start_fracture_state(0.02, 0.005, 3, box.num_triangles());
    const std::string e = node_error("initiate.user_crack",
                                     {{"centre", std::vector<double>{1, 1, 1}}, {"normal", std::vector<double>{0, 0, 1}},
                                      {"radius", 0.03}},
                                     {{"state", value(state)}, {"mesh", value(box)}, {"object", value(object)}});
    EXPECT_NE(e.find("outside the object"), std::string::npos) << e;
    EXPECT_NE(e.find("centre"), std::string::npos) << e;
}

TEST(FractureInputs, StrengthFieldOnTheToughnessPortIsRejected) {
    const SurfaceMesh box = unit_box();
    const LevelSet object = level_set_from_mesh(box, 0.005);
    const propagate::FractureState state = propagate::start_fracture_state(0.02, 0.005, 3, box.num_triangles());
    auto strength = run_node("fields.homogeneous", {{"value", 7.6e7}, {"quantity", std::string("strength")}});
    auto material = run_node("material.brittle", {{"E", 3.1e9}, {"nu", 0.327}, {"rho", 1200.0}, {"tensile_strength", 7.6e7},
                                                  {"toughness", 1e6}, {"compressive_factor", 2.0}});
    const std::string e = node_error("propagate.fronts", {},
                                     {{"state", value(state)},
                                      {"sifs", value(std::vector<cf::bem::FrontEdgeSif>{})},
                                      {"toughness", strength.outputs.at("field")},
                                      {"material", material.outputs.at("material")},
                                      {"object", value(object)}});
    EXPECT_NE(e.find("toughness"), std::string::npos) << e;
    EXPECT_NE(e.find("strength"), std::string::npos) << e;
}

// Inside a merely positive range, E = 1e300 overflowed the BEM into K = 1e297 and a run that
// reported ok; the material's ranges are physical ones, and the message gives the unit.
TEST(FractureInputs, UnphysicalMaterialValuesAreRejectedWithTheirUnit) {
    const std::string e = load_errors(std::string(material_header) +
                                      "    params: {E: 1e300, nu: 0.3, rho: 1200, tensile_strength: 7.6e7, toughness: 1e6, compressive_factor: 2}\n");
    EXPECT_NE(e.find("'E'"), std::string::npos) << e;
    EXPECT_NE(e.find("Pa"), std::string::npos) << e;
    const std::string r = load_errors(std::string(material_header) +
                                      "    params: {E: 3e9, nu: 0.3, rho: 1e9, tensile_strength: 7.6e7, toughness: 1e6, compressive_factor: 2}\n");
    EXPECT_NE(r.find("'rho'"), std::string::npos) << r;
}

TEST(FractureInputs, MessagesShowTheDigitsOfTheGivenNumbers) {
    // r_c = 2.9499e-4 m below r_f = 2.95e-4 m: %f printed both as 0.000295, which read as equal.
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { propagate::start_fracture_state(2.9499e-4, 2.95e-4, 3, 12); },
        {"r_c (0.00029499 m) must be larger than r_f (0.000295 m)"}));
}
