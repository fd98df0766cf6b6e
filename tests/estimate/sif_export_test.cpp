// export.sifs writes one CSV row and one polyline point per front edge, with the values it was given.
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/estimate/estimate_verification.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace cf;
using cf::testing::run_node;
using cf::testing::value;

TEST(SifExport, CsvAndPolylinesCarryEveryFrontEdge) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, 1.0);
    const SurfaceMesh sheet = estimate::rectangle_sheet(Vec3(-0.1, -0.1, 0.02), Vec3(0.2, 0, 0), Vec3(0, 0.2, 0), 2, 2);
    auto a = run_node("assemble.sgbem", {}, {{"mesh", value(cube)}, {"cracks", value(sheet)}});
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1e6; z_min: displacement 0 0 0; *: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    auto k = run_node("sif.fronts", {}, {{"solution", s.outputs.at("solution")}});
    const auto& sifs = k.out<std::vector<bem::FrontEdgeSif>>("sifs");
    ASSERT_EQ(sifs.size(), 8u);
    auto f = run_node("fields.homogeneous", {{"value", 1.5e6}});
    const auto dir = cf::testing::temp_dir("sif-export");
    run_node("export.sifs", {{"path", std::string("front.csv")}, {"at", std::string("edges")}},
             {{"sifs", k.outputs.at("sifs")}, {"solution", s.outputs.at("solution")}, {"toughness", f.outputs.at("field")}}, dir);
    std::ifstream csv(dir / "front.csv");
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line.rfind("front,edge,crack,v0,v1,x,y,z", 0), 0u) << line;
    int rows = 0;
    double sum_csv = 0, sum_ref = 0;
    while (std::getline(csv, line)) {
        std::stringstream ss(line);
        std::string cell;
        std::vector<double> v;
        while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
        ASSERT_EQ(v.size(), 22u) << line;
        EXPECT_DOUBLE_EQ(v[21], 1.5e6);  // K_c
        EXPECT_GE(v[20], std::abs(v[17]));  // K_eff >= |K_I|
        sum_csv += v[17];
        ++rows;
    }
    for (const auto& r : sifs) sum_ref += r.KI;
    EXPECT_EQ(rows, 8);
    EXPECT_DOUBLE_EQ(sum_csv, sum_ref);  // shortest round-trip text: the same doubles
    std::ifstream vtp(dir / "front.vtp");
    const std::string text((std::istreambuf_iterator<char>(vtp)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("NumberOfPoints=\"8\" NumberOfVerts=\"0\" NumberOfLines=\"1\""), std::string::npos) << text.substr(0, 400);
    EXPECT_NE(text.find("Name=\"K_I\""), std::string::npos);
    EXPECT_NE(text.find("<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n9\n"), std::string::npos);  // closed loop
}

// Per front node, read back from the CSV: the penny crack (a = 1, remote tension 1 in a cube of side
// 20a) against K_I = 2 sigma sqrt(a / pi), with penny_crack_sif's bars (front average 1 %, worst
// node 3 %); the frame: e2 the crack normal (+-z), e1 radially outwards, e3 = e1 x e2.
TEST(SifExport, PennyCrackNodeRowsMatchTheClosedForm) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, 20.0);
    const SurfaceMesh disk = bem::bem_disk_mesh(7, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 1.0}, {"nu", 0.3}, {"single_layer", false}, {"front_elements", std::string("square_root")}},
                      {{"mesh", value(cube)}, {"cracks", value(disk)}});
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1; z_min: traction 0 0 -1; *: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    auto k = run_node("sif.fronts", {}, {{"solution", s.outputs.at("solution")}});
    const auto dir = cf::testing::temp_dir("sif-export-penny");
    auto e = run_node("export.sifs", {{"path", std::string("sifs_{iteration}.csv")}},
                      {{"sifs", k.outputs.at("sifs")}, {"solution", s.outputs.at("solution")}}, dir);
    const double exact = 2 / std::sqrt(M_PI);
    std::ifstream csv(dir / "sifs_0000.csv");
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "front,node,crack,vertex,x,y,z,e1x,e1y,e1z,e2x,e2y,e2z,e3x,e3y,e3z,KI,KII,KIII,K_eff,K_c");
    int rows = 0;
    double mean = 0, worst = 0;
    while (std::getline(csv, line)) {
        std::stringstream ss(line);
        std::vector<double> v;
        for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
        ASSERT_EQ(v.size(), 21u) << line;
        const Vec3 x(v[4], v[5], v[6]), e1(v[7], v[8], v[9]), e2(v[10], v[11], v[12]), e3(v[13], v[14], v[15]);
        EXPECT_NEAR(x.norm(), 1.0, 1e-12);  // front nodes lie on the circle r = a
        EXPECT_NEAR(std::abs(e2.z()), 1, 1e-12);
        EXPECT_NEAR(e1.dot(x.normalized()), 1, 1e-2);  // forward = radially outwards (front polygon's edge normals)
        EXPECT_NEAR((e1.cross(e2) - e3).norm(), 0, 1e-12);
        EXPECT_EQ(v[20], -1);  // no toughness field
        mean += v[16];
        worst = std::max(worst, std::abs(v[16] - exact) / exact);
        EXPECT_NEAR(v[19], std::abs(v[16]), 0.05 * exact);  // K_eff: mode I dominates
        ++rows;
    }
    EXPECT_EQ(rows, e.counts.at("front_nodes"));
    EXPECT_EQ(rows, 42);  // 7 rings: 6 x 7 front nodes
    mean /= rows;
    std::cout << "penny crack through export.sifs: front-average K_I error " << (mean - exact) / exact << ", worst node " << worst
              << "\n";
    EXPECT_LT(std::abs(mean - exact) / exact, 0.01);
    EXPECT_LT(worst, 0.03);
    // The polyline: one closed loop over the 42 nodes.
    std::ifstream vtp(dir / "sifs_0000.vtp");
    const std::string text((std::istreambuf_iterator<char>(vtp)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("NumberOfPoints=\"42\" NumberOfVerts=\"0\" NumberOfLines=\"1\""), std::string::npos);
    EXPECT_NE(text.find("<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n43\n"), std::string::npos);
}
