// export.probes against closed forms, read back from the files it writes: a solid sphere under
// pressure (u = -p (1 - 2 nu) / E x, sigma = -p I) at user points, a bar in tension
// (u = s/E (-nu x, -nu y, z), sigma = s e_z e_z) on a grid slice; and its errors.
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "tests/harness/expect_error.hpp"
#include "tests/harness/node_harness.hpp"
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>

using namespace cf;
using cf::testing::run_node;
using cf::testing::value;

namespace {

graph::Value solve(const SurfaceMesh& mesh, double E, double nu, const std::string& bc) {
    auto a = run_node("assemble.sgbem", {{"E", E}, {"nu", nu}, {"single_layer", false}}, {{"mesh", value(mesh)}});
    return run_node("solve.sgbem", {{"boundary_conditions", bc}}, {{"operators", a.outputs.at("operators")}}).outputs.at("solution");
}

// Rows of numbers of a CSV file after its header (which is returned in `header`).
std::vector<std::vector<double>> read_csv(const std::filesystem::path& file, std::string& header) {
    std::ifstream in(file);
    std::getline(in, header);
    std::vector<std::vector<double>> rows;
    for (std::string line; std::getline(in, line);) {
        std::stringstream ss(line);
        std::vector<double> v;
        for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
        rows.push_back(v);
    }
    return rows;
}

// The numbers of the DataArray named `name` of a .vtp file.
std::vector<double> vtp_array(const std::filesystem::path& file, const std::string& name) {
    std::ifstream in(file);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    const std::size_t tag = text.find("Name=\"" + name + "\"");
    if (tag == std::string::npos) throw std::runtime_error("no array " + name + " in " + file.string());
    const std::size_t begin = text.find('>', tag) + 1, end = text.find("</DataArray>", begin);
    std::istringstream values(text.substr(begin, end - begin));
    std::vector<double> out;
    for (double x; values >> x;) out.push_back(x);
    return out;
}

}  // namespace

TEST(Probes, PressureSphereAtUserPointsMatchesTheClosedForm) {
    const double E = 3.1e9, nu = 0.327, p = 2e6, R = 0.1;
    const graph::Value sol = solve(bem::bem_icosphere_mesh(2, R), E, nu, "*: pressure 2e6");
    const std::vector<double> pts = {0, 0, 0, 0.03, 0.01, -0.02, 0.06, 0, 0, 0, -0.045, 0.045};
    const auto dir = cf::testing::temp_dir("probes-sphere");
    auto r = run_node("export.probes", {{"points", pts}, {"path", std::string("probes.csv")}}, {{"solution", sol}}, dir);
    EXPECT_EQ(r.counts.at("points"), 4);
    std::string header;
    const auto rows = read_csv(dir / "probes.csv", header);
    EXPECT_EQ(header, "point,x,y,z,ux,uy,uz,sxx,syy,szz,syz,sxz,sxy,s1,s2,s3");
    ASSERT_EQ(rows.size(), 4u);
    const double u_scale = p * R * (1 - 2 * nu) / E;  // |u| on the surface [m]
    double worst_u = 0, worst_s = 0;
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const auto& v = rows[k];
        ASSERT_EQ(v.size(), 16u);
        EXPECT_EQ(v[0], double(k));
        const Vec3 x(v[1], v[2], v[3]);
        EXPECT_EQ(x, Vec3(pts[3 * k], pts[3 * k + 1], pts[3 * k + 2]));
        const Vec3 exact = -p * (1 - 2 * nu) / E * x;
        EXPECT_LT((Vec3(v[4], v[5], v[6]) - exact).norm(), 1e-5 * u_scale) << k;  // measured 1.1e-7
        worst_u = std::max(worst_u, (Vec3(v[4], v[5], v[6]) - exact).norm() / u_scale);
        for (int c = 7; c <= 15; ++c) worst_s = std::max(worst_s, std::abs(v[c] - (c <= 9 || c >= 13 ? -p : 0)) / p);
        for (int c = 7; c <= 9; ++c) EXPECT_NEAR(v[c], -p, 1e-5 * p) << k << " column " << c;     // normal stresses
        for (int c = 10; c <= 12; ++c) EXPECT_NEAR(v[c], 0, 1e-5 * p) << k << " column " << c;    // shear
        for (int c = 13; c <= 15; ++c) EXPECT_NEAR(v[c], -p, 1e-5 * p) << k << " column " << c;   // principal
        EXPECT_GE(v[13], v[14]);
        EXPECT_GE(v[14], v[15]);
    }
    std::cout << "pressure sphere probes: worst |u - u_exact| / u(R) " << worst_u << ", worst stress error / p " << worst_s << "\n";
}

TEST(Probes, BarInTensionOnAGridSliceMatchesTheClosedForm) {
    const double E = 2e9, nu = 0.25, s = 1e6;
    const graph::Value sol = solve(bem::bem_cube_mesh(3, 1.0), E, nu, "z_max: traction 0 0 1e6; z_min: traction 0 0 -1e6; *: traction 0 0 0");
    const auto dir = cf::testing::temp_dir("probes-slice");
    // The plane x = 0.1 from y, z = -0.6 to 0.6 in 7 x 7 points: the 5 x 5 with |y|, |z| <= 0.4 are inside.
    auto r = run_node("export.probes",
                      {{"slice_origin", std::vector<double>{0.1, -0.6, -0.6}}, {"slice_u", std::vector<double>{0, 1.2, 0}},
                       {"slice_v", std::vector<double>{0, 0, 1.2}}, {"slice_u_points", 7LL}, {"slice_v_points", 7LL},
                       {"path", std::string("slice_{iteration}.csv")}},
                      {{"solution", sol}}, dir);
    EXPECT_EQ(r.counts.at("points"), 25);
    EXPECT_EQ(r.counts.at("points_outside"), 24);
    std::string header;
    const auto rows = read_csv(dir / "slice_0000.csv", header);  // outside a loop: iteration 0
    EXPECT_EQ(header, "i,j,x,y,z,ux,uy,uz,sxx,syy,szz,syz,sxz,sxy,s1,s2,s3");
    ASSERT_EQ(rows.size(), 25u);
    double worst_u = 0, worst_s = 0;
    for (const auto& v : rows) {
        ASSERT_EQ(v.size(), 17u);
        EXPECT_GE(v[0], 1);  // i, j in 1 .. 5
        EXPECT_LE(v[1], 5);
        const Vec3 x(v[2], v[3], v[4]);
        EXPECT_NEAR(x.y(), -0.6 + 0.2 * v[0], 1e-15);
        const Vec3 exact = s / E * Vec3(-nu * x.x(), -nu * x.y(), x.z());
        EXPECT_LT((Vec3(v[5], v[6], v[7]) - exact).norm(), 1e-3 * s / E * 0.5) << v[0] << "," << v[1];
        const double sig[6] = {0, 0, s, 0, 0, 0};
        for (int c = 0; c < 6; ++c) EXPECT_NEAR(v[8 + c], sig[c], 1e-3 * s) << c;
        worst_u = std::max(worst_u, (Vec3(v[5], v[6], v[7]) - exact).norm() / (s / E * 0.5));
        for (int c = 0; c < 6; ++c) worst_s = std::max(worst_s, std::abs(v[8 + c] - sig[c]) / s);
        EXPECT_NEAR(v[14], s, 1e-3 * s);
        EXPECT_NEAR(v[15], 0, 1e-3 * s);
        EXPECT_NEAR(v[16], 0, 1e-3 * s);
    }
    std::cout << "bar slice probes: worst |u - u_exact| / u(0.5) " << worst_u << ", worst stress error / s " << worst_s << "\n";
    // The .vtp: the 25 inside points and the 4 x 4 cells between them (two triangles each).
    std::ifstream vtp(dir / "slice_0000.vtp");
    const std::string text((std::istreambuf_iterator<char>(vtp)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("NumberOfPoints=\"25\""), std::string::npos);
    EXPECT_NE(text.find("NumberOfPolys=\"32\""), std::string::npos);
    const auto s1 = vtp_array(dir / "slice_0000.vtp", "sigma_1");
    ASSERT_EQ(s1.size(), 25u);
    for (std::size_t k = 0; k < s1.size(); ++k) EXPECT_DOUBLE_EQ(s1[k], rows[k][14]);  // same doubles as the CSV
    EXPECT_EQ(vtp_array(dir / "slice_0000.vtp", "u").size(), 75u);
}

TEST(Probes, BadPointsAndSlicesAreErrorsNamingThem) {
    const graph::Value sol = solve(bem::bem_cube_mesh(1, 1.0), 1e9, 0.3, "*: pressure 1e5");
    const auto dir = cf::testing::temp_dir("probes-errors");
    auto probe = [&](const cf::testing::Params& extra) {
        cf::testing::Params p{{"path", std::string("p.csv")}};
        for (const auto& kv : extra) p[kv.first] = kv.second;
        run_node("export.probes", p, {{"solution", sol}}, dir);
    };
    EXPECT_TRUE(cf::testing::throws<std::exception>([&] { probe({{"points", std::vector<double>{0, 0, 0, 0.2, 0.7, 0}}}); },
                                                    {"probe point 1", "(0.2, 0.7, 0)", "not inside the object"}));
    EXPECT_TRUE(cf::testing::throws<std::exception>([&] { probe({{"points", std::vector<double>{0, 0, 0.5}}}); },
                                                    {"probe point 0", "not inside"}));  // on the surface
    EXPECT_TRUE(cf::testing::throws<std::exception>([&] { probe({{"points", std::vector<double>{0, 0}}}); }, {"x y z triples"}));
    EXPECT_TRUE(cf::testing::throws<std::exception>([&] { probe({}); }, {"give either 'points' or a grid slice"}));
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] { probe({{"points", std::vector<double>{0, 0, 0}}, {"slice_u_points", 3LL}, {"slice_v_points", 3LL}}); }, {"not both"}));
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] { probe({{"slice_origin", std::vector<double>{2, 2, 2}}, {"slice_u_points", 3LL}, {"slice_v_points", 3LL}}); },
        {"no point of the grid slice lies inside"}));
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] { probe({{"slice_v", std::vector<double>{2, 0, 0}}, {"slice_u_points", 3LL}, {"slice_v_points", 3LL}}); }, {"parallel"}));
    EXPECT_FALSE(std::filesystem::exists(dir / "p.csv"));
}

TEST(Probes, ASliceThroughACrackPlaneLeavesOutThePointsOnTheCrack) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, 4.0);
    auto a = run_node("assemble.sgbem", {{"E", 1.0}, {"nu", 0.3}, {"single_layer", false}},
                      {{"mesh", value(cube)}, {"cracks", value(bem::bem_disk_mesh(3, 1.0))}});
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1; z_min: traction 0 0 -1; *: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    const auto dir = cf::testing::temp_dir("probes-crack-plane");
    run_node("export.probes",
             {{"slice_origin", std::vector<double>{-1.5, -1.5, 0}}, {"slice_u", std::vector<double>{3, 0, 0}},
              {"slice_v", std::vector<double>{0, 3, 0}}, {"slice_u_points", 7LL}, {"slice_v_points", 7LL},
              {"path", std::string("plane.csv")}, {"vtp_path", std::string("none")}},
             {{"solution", s.outputs.at("solution")}}, dir);
    std::string header;
    const auto rows = read_csv(dir / "plane.csv", header);
    std::set<std::pair<int, int>> present;
    for (const auto& v : rows) present.insert({int(v[0]), int(v[1])});
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 7; ++i) {
            const double r = std::hypot(-1.5 + 0.5 * i, -1.5 + 0.5 * j);
            if (r < 0.9) {
                EXPECT_FALSE(present.count({i, j})) << i << "," << j;  // on the crack (radius 1)
            } else if (r > 1.1) {
                EXPECT_TRUE(present.count({i, j})) << i << "," << j;  // beside it: evaluated
            }
        }
    EXPECT_FALSE(std::filesystem::exists(dir / "plane.vtp"));
}

// Inside a fracture loop, per BEM step: the shipped edge_crack_mode1 (fast) with a slice across
// the crack and a point above it added to the loop body next to its export.sifs. Every step writes
// its own files ({iteration}) with the inside points less those on the crack, principal stresses
// in order, and the point above the crack in vertical tension (the cube is pulled apart along z).
TEST(Probes, WriteEveryStepOfAFractureLoop) {
    // The loop is pipelines/lib/fracture.yaml: a copy of it with the probes, beside a copy of the case.
    auto read = [](const std::string& rel) {
        std::ifstream in(std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/" + rel);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    std::string text = read("lib/fracture.yaml");
    const std::string anchor = "        params: {path: \"sifs_{iteration}.csv\"}\n";
    const std::size_t at = text.find(anchor);
    ASSERT_NE(at, std::string::npos);
    text.insert(at + anchor.size(),
                "      stress_slice:\n"
                "        type: export.probes\n"
                "        inputs: {solution: steps.solution}\n"
                "        params: {slice_origin: [-0.05, 0, -0.05], slice_u: [0.1, 0, 0], slice_v: [0, 0, 0.1],\n"
                "                 slice_u_points: 9, slice_v_points: 9, path: \"slice_{iteration}.csv\"}\n"
                "      stress_point:\n"
                "        type: export.probes\n"
                "        inputs: {solution: steps.solution}\n"
                "        params: {points: [0.02, 0.01, 0.03], path: \"point_{iteration}.csv\"}\n");
    const std::filesystem::path files = cf::testing::temp_dir("probes-loop-pipeline");
    std::filesystem::create_directories(files / "lib");
    std::ofstream(files / "lib" / "fracture.yaml") << text;
    std::ofstream(files / "edge_crack_probes.yaml") << read("edge_crack_mode1.yaml");
    std::vector<graph::Diagnostic> diags;
    graph::LoadOptions options;
    options.fast = true;
    const graph::Plan plan = graph::load_pipeline_file((files / "edge_crack_probes.yaml").string(), node_registry(), options, diags);
    ASSERT_TRUE(diags.empty()) << graph::format(diags.front());
    graph::RunOptions run;
    run.fast = true;
    run.output_dir = cf::testing::temp_dir("probes-loop");
    const graph::ExecutionResult res = graph::execute(plan, run);
    ASSERT_TRUE(res.ok) << res.error;
    int steps = 0;
    for (; std::filesystem::exists(run.output_dir / ("sifs_000" + std::to_string(steps) + ".csv")); ++steps) {
        const std::string k = "000" + std::to_string(steps);
        std::string header;
        const auto slice = read_csv(run.output_dir / ("slice_" + k + ".csv"), header);
        EXPECT_EQ(header.rfind("i,j,x,y,z", 0), 0u);
        EXPECT_GT(slice.size(), 30u) << k;  // 7 x 7 inside, less the points on the crack
        EXPECT_LE(slice.size(), 49u) << k;
        EXPECT_TRUE(std::filesystem::exists(run.output_dir / ("slice_" + k + ".vtp"))) << k;
        const auto point = read_csv(run.output_dir / ("point_" + k + ".csv"), header);
        ASSERT_EQ(point.size(), 1u) << k;
        for (const auto& rows : {slice, point})
            for (const auto& v : rows) {
                const std::size_t s1 = v.size() - 3;
                EXPECT_GE(v[s1], v[s1 + 1]);
                EXPECT_GE(v[s1 + 1], v[s1 + 2]);
            }
        EXPECT_GT(point[0][9], 0) << k;  // szz: the cube is pulled apart along z
    }
    EXPECT_GE(steps, 2);
}
