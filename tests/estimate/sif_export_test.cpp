// export.sifs writes one CSV row and one polyline point per front edge, with the values it was given.
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/estimate/estimate_verification.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

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
    run_node("export.sifs", {{"path", std::string("front.csv")}},
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
