// assemble.sgbem / solve.sgbem through the node harness: parameters, typed ports, reuse, errors.
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

using namespace cf;
using cf::testing::run_node;
using cf::testing::value;

TEST(BemNodes, CubeTensionThroughNodesAndReuse) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 2e9}, {"nu", 0.25}, {"single_layer", false}}, {{"mesh", value(cube)}});
    const graph::Value ops = a.outputs.at("operators");
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1e6; z_min: traction 0 0 -1e6; *: traction 0 0 0")}},
                      {{"operators", ops}});
    const auto& sol = s.outputs.at("solution").get<bem::BemSolution>();
    double err = 0, ref = 0;
    for (std::size_t v = 0; v < cube.num_vertices(); ++v) {
        const Vec3 x = cube.vertices[v];
        const Vec3 ex = 1e6 / 2e9 * Vec3(-0.25 * x.x(), -0.25 * x.y(), x.z());
        err = std::max(err, (sol.displacement[v] - ex).norm());
        ref = std::max(ref, ex.norm());
    }
    EXPECT_LT(err, 1e-3 * ref);
    // Same mesh and settings with 'previous': surface blocks are shared, not recomputed.
    auto a2 = run_node("assemble.sgbem", {{"E", 2e9}, {"nu", 0.25}, {"single_layer", false}},
                       {{"mesh", value(cube)}, {"previous", ops}});
    EXPECT_EQ(a2.outputs.at("operators").get<bem::BemOperators>().surface, ops.get<bem::BemOperators>().surface);
}

TEST(BemNodes, UncoveredRegionFailsNamingIt) {
    const SurfaceMesh cube = bem::bem_cube_mesh(1, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 1e9}}, {{"mesh", value(cube)}});
    try {
        run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1")}},
                 {{"operators", a.outputs.at("operators")}});
        FAIL();
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("regions without a boundary condition"), std::string::npos) << e.what();
    }
}
