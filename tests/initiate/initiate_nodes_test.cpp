// initiate.cracks and initiate.user_crack through the node harness (parameters, ports, counts,
// error messages as a pipeline shows them).
#include "initiation_fixtures.hpp"
#include "nodes/levelset/level_set.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

using cf::testing::run_node;
using cf::testing::value;

constexpr double L = 1.0;

std::string failure(const std::string& type, const cf::testing::Params& p, const cf::testing::Inputs& in) {
    try {
        run_node(type, p, in);
    } catch (const std::exception& e) {
        return e.what();
    }
    return "no error";
}

TEST(InitiateNodes, CracksNodeUnderTensionReportsCounts) {
    const SurfaceMesh cube = bem::bem_cube_mesh(3, L);
    const auto sol = initiate::testing::solve_uniaxial(cube, 1e6);
    const auto state = propagate::start_fracture_state(0.2, 0.02, 3, cube.num_triangles());
    const cf::testing::Inputs in{{"solution", graph::Value::shared<bem::BemSolution>(sol)},
                                 {"state", value(state)},
                                 {"strength", value(initiate::testing::strength_field(5e5, 2))}};
    const auto r = run_node("initiate.cracks", {{"max_cracks", 2LL}}, in);
    const auto& out = r.out<propagate::FractureState>("state");
    EXPECT_EQ(out.num_cracks(), 2);
    EXPECT_EQ(out.cracks_initiated, 2);
    EXPECT_EQ(r.counts.at("cracks_added"), 2);
    EXPECT_EQ(r.counts.at("candidates_over_strength"), 108);  // every element: sigma_zz ~ 1 MPa > 0.5 MPa
    EXPECT_EQ(r.counts.at("triangles_added"), 12);
    // max_cracks = 0 disables initiation.
    EXPECT_EQ(run_node("initiate.cracks", {{"max_cracks", 0LL}}, in).out<propagate::FractureState>("state").num_cracks(), 0);
    // A toughness field on the strength port is refused.
    cf::testing::Inputs bad = in;
    bad["strength"] = value(make_field(std::make_shared<HomogeneousField>(1e6), FieldQuantity::toughness, 1));
    EXPECT_NE(failure("initiate.cracks", {}, bad).find("input 'strength' is a toughness field"), std::string::npos)
        << failure("initiate.cracks", {}, bad);
}

TEST(InitiateNodes, UserCrackNodeAddsAPennyAndAnEdgeCrack) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const double r_c = 0.05, r_f = 0.01;
    const LevelSet object = level_set_from_mesh(cube, r_f);
    const auto state = propagate::start_fracture_state(r_c, r_f, 3, cube.num_triangles());
    const cf::testing::Inputs in{{"state", value(state)}, {"mesh", value(cube)}, {"object", value(object)}};
    const auto r = run_node("initiate.user_crack",
                            {{"centre", std::vector<double>{0, 0, -0.2}},
                             {"normal", std::vector<double>{0, 0, 1}},
                             {"radius", 0.25}},
                            in);
    const auto& s1 = r.out<propagate::FractureState>("state");
    ASSERT_EQ(s1.num_cracks(), 1);
    EXPECT_EQ(s1.fronts.size(), 1u);
    EXPECT_EQ(s1.cracks_initiated, 0);  // user cracks are not counted against max_cracks
    EXPECT_NEAR(surface_area(s1.cracks) / (M_PI * 0.25 * 0.25), 1, 0.01);
    EXPECT_LT(sample(s1.grids.cracks[0], Vec3(0.1, 0.1, -0.2)), 0);   // recorded inside the disk
    EXPECT_GT(sample(s1.grids.cracks[0], Vec3(0.1, 0.1, -0.17)), 0);  // not 3 r_f off its plane

    // An edge crack on the face y = +L/2, growing into -y: the recorded grid reaches the face,
    // the BEM sheet stays the margin inside.
    cf::testing::Inputs in2 = in;
    in2["state"] = value(s1);
    const auto r2 = run_node("initiate.user_crack",
                             {{"centre", std::vector<double>{0, L / 2, 0.2}},
                              {"normal", std::vector<double>{0, 0, 1}},
                              {"front_direction", std::vector<double>{0, -1, 0}},
                              {"radius", 0.2}},
                             in2);
    const auto& s2 = r2.out<propagate::FractureState>("state");
    ASSERT_EQ(s2.num_cracks(), 2);
    for (double x : {-0.15, 0.0, 0.15}) EXPECT_LT(sample(s2.grids.cracks[1], Vec3(x, L / 2, 0.2)), 0) << x;
    double max_y = -1;
    for (std::size_t t = 0; t < s2.cracks.num_triangles(); ++t)
        if (s2.cracks.region_of(t) == 1)
            for (int v : s2.cracks.triangles[t]) max_y = std::max(max_y, s2.cracks.vertices[v].y());
    EXPECT_LE(max_y, L / 2 - r2.counts.at("margin") * (1 - 1e-9));
    EXPECT_GT(max_y, L / 2 - r2.counts.at("margin") - 1e-6);

    // A second crack crossing the first one is refused.
    cf::testing::Inputs in3 = in;
    in3["state"] = value(s1);
    const std::string crossing = failure("initiate.user_crack",
                                         {{"centre", std::vector<double>{0, 0, -0.2}},
                                          {"normal", std::vector<double>{1, 0, 0}},
                                          {"radius", 0.2}},
                                         in3);
    EXPECT_NE(crossing.find("touches or crosses a crack already in the state"), std::string::npos) << crossing;
}

TEST(InitiateNodes, UserCrackErrorsNameTheParameter) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, L);
    const double r_c = 0.05, r_f = 0.02;
    const cf::testing::Inputs in{{"state", value(propagate::start_fracture_state(r_c, r_f, 3, cube.num_triangles()))},
                                 {"mesh", value(cube)},
                                 {"object", value(level_set_from_mesh(cube, r_f))}};
    auto params = [](std::vector<double> c, std::vector<double> n, std::vector<double> d, double R) {
        return cf::testing::Params{{"centre", c}, {"normal", n}, {"front_direction", d}, {"radius", R}};
    };
    const std::string zero = failure("initiate.user_crack", params({0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 0.2), in);
    EXPECT_NE(zero.find("parameter 'normal' (0 0 0) is zero"), std::string::npos) << zero;
    const std::string parallel = failure("initiate.user_crack", params({0, 0, 0}, {0, 1, 0}, {0, 3, 0}, 0.2), in);
    EXPECT_NE(parallel.find("'front_direction' (0 3 0) is parallel to 'normal'"), std::string::npos) << parallel;
    const std::string outside = failure("initiate.user_crack", params({3, 0, 0}, {0, 0, 1}, {0, 0, 0}, 0.2), in);
    EXPECT_NE(outside.find("lies outside the object"), std::string::npos) << outside;
    const std::string small = failure("initiate.user_crack", params({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 0.01), in);
    EXPECT_NE(small.find("parameter 'radius' (0.01 m) is too small"), std::string::npos) << small;
    EXPECT_NE(small.find("radius >= 0.025 m"), std::string::npos) << small;
    const std::string mesh = failure("initiate.user_crack", params({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 0.2),
                                     {{"state", value(propagate::start_fracture_state(r_c, r_f, 3, 5))},
                                      {"mesh", value(cube)},
                                      {"object", in.at("object")}});
    EXPECT_NE(mesh.find("input 'mesh' has 48 triangles but input 'state' was started for 5"), std::string::npos) << mesh;
}

}  // namespace
}  // namespace cf
