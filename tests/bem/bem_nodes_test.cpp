// assemble.sgbem / solve.sgbem through the node harness: parameters, typed ports, reuse, errors.
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/harness/expect_error.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

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
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] {
            run_node("solve.sgbem", {{"boundary_conditions", std::string("z_max: traction 0 0 1")}},
                     {{"operators", a.outputs.at("operators")}});
        },
        {"regions without a boundary condition"}));
}

// A solve whose numbers overflow (issue 16: E = 1e300 gave NaN displacements and a run that said ok)
// fails naming the likely causes instead of passing NaN on. E is range-checked now, so the overflow
// comes from loads at the edge of double precision here.
TEST(BemNodes, ASolutionWithNonFiniteValuesFails) {
    const SurfaceMesh cube = bem::bem_cube_mesh(1, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 1e9}}, {{"mesh", value(cube)}});
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] {
            run_node("solve.sgbem",
                     {{"boundary_conditions", std::string("z_max: traction 0 0 1.7e308; z_min: traction 0 0 -1.7e308; *: traction 0 0 0")}},
                     {{"operators", a.outputs.at("operators")}});
        },
        {"non-finite values (NaN or infinity)", "physical range", "E = 1e+09 Pa"}));
}

TEST(BemNodes, PressureOnADirichletRegionIsAValidateErrorAtItsLine) {
    const std::string yaml = "nodes:\n"
                             "  box: {type: shape.box}\n"
                             "  assemble: {type: assemble.sgbem, inputs: {mesh: box.mesh}}\n"
                             "  solve:\n"
                             "    type: solve.sgbem\n"
                             "    inputs: {operators: assemble.operators}\n"
                             "    params: {boundary_conditions: 'z_min: displacement 0 0 0; z_min: pressure 1e5; *: traction 0 0 0'}\n";
    std::vector<graph::Diagnostic> diags;
    graph::load_pipeline_text(yaml, "case.yaml", node_registry(), {}, diags);
    ASSERT_EQ(diags.size(), 1u);
    const std::string text = graph::format(diags[0]);
    EXPECT_NE(text.find("case.yaml:7"), std::string::npos) << text;
    EXPECT_NE(text.find("region 'z_min'"), std::string::npos) << text;
    EXPECT_NE(text.find("Dirichlet"), std::string::npos) << text;
    // And through the node: a pressure on the sphere solves (pure Neumann, the verification case's load).
    const SurfaceMesh sphere = bem::bem_icosphere_mesh(1, 0.5);
    auto a = run_node("assemble.sgbem", {{"E", 1e9}, {"nu", 0.25}, {"single_layer", false}}, {{"mesh", value(sphere)}});
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("*: pressure 1e6")}}, {{"operators", a.outputs.at("operators")}});
    const auto& sol = s.outputs.at("solution").get<bem::BemSolution>();
    for (std::size_t v = 0; v < sphere.num_vertices(); ++v)  // u = -p (1 - 2 nu) / E x
        EXPECT_NEAR(sol.displacement[v].dot(sphere.vertices[v].normalized()), -1e6 * 0.5 * 0.5 / 1e9, 1e-3 * 2.5e-4) << v;
}

TEST(BemNodes, ValidateNamesARegionTheUpstreamMeshWillNotHave) {
    // The mesh file of the import case below does not exist: validated as a batch manifest does
    // (graph::LoadOptions::require_input_files), so that only the region check speaks.
    graph::LoadOptions options;
    options.require_input_files = false;
    auto diagnostics = [&](const std::string& yaml) {
        std::vector<graph::Diagnostic> diags;
        graph::load_pipeline_text(yaml, "case.yaml", node_registry(), options, diags);
        std::string text;
        for (const auto& d : diags) text += graph::format(d) + "\n";
        return text;
    };
    const std::string solve = "  assemble: {type: assemble.sgbem, inputs: {mesh: MESH}}\n"
                              "  solve:\n"
                              "    type: solve.sgbem\n"
                              "    inputs: {operators: assemble.operators}\n"
                              "    params: {boundary_conditions: 'BC'}\n";
    auto pipeline = [&](const std::string& nodes, const std::string& mesh, const std::string& bc) {
        std::string s = solve;
        s.replace(s.find("MESH"), 4, mesh);
        s.replace(s.find("BC"), 2, bc);
        return "nodes:\n" + nodes + s;
    };
    const std::string box = "  box: {type: shape.box}\n";
    // A procedural box has x_min .. z_max: 'zmax' is reported at its line, with the likely name.
    std::string text = diagnostics(pipeline(box, "box.mesh", "zmax: pressure 1e5; *: traction 0 0 0"));
    EXPECT_NE(text.find("case.yaml:7"), std::string::npos) << text;  // the params line
    EXPECT_NE(text.find("names region 'zmax'"), std::string::npos) << text;
    EXPECT_NE(text.find("'box' (shape.box)"), std::string::npos) << text;
    EXPECT_NE(text.find("z_max"), std::string::npos) << text;
    EXPECT_EQ(diagnostics(pipeline(box, "box.mesh", "z_max: pressure 1e5; z_min: displacement 0 0 0; *: traction 0 0 0")), "");
    // Half-space regions: the spec's names and 'default' (or, keeping unmatched, the box's).
    const std::string halfspace = box + "  label: {type: regions.halfspace, inputs: {mesh: box.mesh}, params: {regions: 'top: z >= 0.49'}}\n";
    EXPECT_EQ(diagnostics(pipeline(halfspace, "label.mesh", "top: pressure 1; default: traction 0 0 0")), "");
    EXPECT_NE(diagnostics(pipeline(halfspace, "label.mesh", "top: pressure 1; x_min: traction 0 0 0; *: traction 0 0 0")).find("'x_min'"),
              std::string::npos);
    // simplify.remesh: 'surface', or the regions carried from the box.
    const std::string remesh = box + "  ls: {type: levelset.from_mesh, inputs: {mesh: box.mesh}}\n"
                                     "  coarse: {type: simplify.remesh, inputs: {level_set: ls.level_set, regions_from: box.mesh}}\n"
                                     "  plain: {type: simplify.remesh, inputs: {level_set: ls.level_set}}\n";
    EXPECT_EQ(diagnostics(pipeline(remesh, "coarse.mesh", "z_min: displacement 0 0 0; *: pressure 1")), "");
    EXPECT_NE(diagnostics(pipeline(remesh, "plain.mesh", "z_min: displacement 0 0 0; *: pressure 1")).find("its regions: surface"),
              std::string::npos);
    // A mesh file that validate cannot read (here: none) is left to the assembly: the loader hands
    // the names to it, and it checks them against the mesh before assembling.
    const std::string file = pipeline("  file: {type: import.mesh, params: {path: nowhere.obj}}\n", "file.mesh",
                                      "lid: pressure 1; z_min: displacement 0 0 0; *: traction 0 0 0");
    EXPECT_EQ(diagnostics(file), "");
    std::vector<graph::Diagnostic> diags;
    const graph::Plan plan = graph::load_pipeline_text(file, "case.yaml", node_registry(), options, diags);
    ASSERT_GE(plan.find("assemble"), 0);
    EXPECT_EQ(std::get<std::string>(plan.nodes[std::size_t(plan.find("assemble"))].params.at("boundary_regions")),
              "solve:lid;solve:z_min");
    SurfaceMesh cube = bem::bem_cube_mesh(1, 1.0);
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] { run_node("assemble.sgbem", {{"boundary_regions", std::string("solve:z_min;solve:lid")}}, {{"mesh", value(cube)}}); },
        {"node 'solve' names region 'lid'", "does not have", "before assembling", "z_max"}));
    cube.region_names.push_back("lid");  // named, no triangles
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] { run_node("assemble.sgbem", {{"boundary_regions", std::string("solve:lid")}}, {{"mesh", value(cube)}}); },
        {"region 'lid'", "has no triangles"}));
    EXPECT_NO_THROW(run_node("assemble.sgbem", {{"boundary_regions", std::string("solve:z_min;solve:z_max")}}, {{"mesh", value(cube)}}));
}


// A mesh file's face groups are read by validate (the parser alone), so a region the file does not
// have is reported at the boundary conditions' line before any level set is computed; the file's
// names and 'default' (faces before any group) pass.
TEST(BemNodes, ValidateReadsTheRegionsOfAMeshFile) {
    const auto dir = cf::testing::temp_dir("validate-file-regions");
    {
        std::ofstream obj(dir / "lidded.obj");
        obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
               "f 1 3 2\n"                       // before any group: 'default'
               "g walls\nf 1 2 4\nf 1 4 3\n"
               "usemtl lid\nf 2 3 4\n";
    }
    auto diagnostics = [&](const std::string& bc) {
        const std::string yaml = "nodes:\n"
                                 "  file: {type: import.mesh, params: {path: lidded.obj}}\n"
                                 "  assemble: {type: assemble.sgbem, inputs: {mesh: file.mesh}}\n"
                                 "  solve:\n"
                                 "    type: solve.sgbem\n"
                                 "    inputs: {operators: assemble.operators}\n"
                                 "    params: {boundary_conditions: '" + bc + "'}\n";
        const auto path = dir / "case.yaml";
        std::ofstream(path) << yaml;
        std::vector<graph::Diagnostic> diags;
        graph::load_pipeline_file(path.string(), node_registry(), graph::LoadOptions{}, diags);
        std::string text;
        for (const auto& d : diags) text += graph::format(d) + "\n";
        return text;
    };
    EXPECT_EQ(diagnostics("lid: pressure 1; walls: displacement 0 0 0; default: traction 0 0 0"), "");
    const std::string text = diagnostics("lids: pressure 1; walls: displacement 0 0 0; *: traction 0 0 0");
    EXPECT_NE(text.find("case.yaml:7"), std::string::npos) << text;
    EXPECT_NE(text.find("names region 'lids'"), std::string::npos) << text;
    EXPECT_NE(text.find("'file' (import.mesh)"), std::string::npos) << text;
    EXPECT_NE(text.find("default, lid, walls"), std::string::npos) << text;
}

namespace {

// Reads the numbers of the DataArray named `name` of a .vtp file written by write_vtp.
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

TEST(BemNodes, VtkExportWritesFieldsThatParseBack) {
    // Penny crack (3 rings) inside a cube of side 10 (m = 2) under remote tension: surface and crack files.
    const SurfaceMesh cube = bem::bem_cube_mesh(2, 10.0);
    const SurfaceMesh crack = bem::bem_disk_mesh(3, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 1.0}, {"nu", 0.3}, {"single_layer", true}},
                      {{"mesh", value(cube)}, {"cracks", value(crack)}});
    auto s = run_node("solve.sgbem",
                      {{"boundary_conditions", std::string("z_max: traction 0 0 1; z_min: displacement 0 0 0; *: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    const graph::Value solv = s.outputs.at("solution");
    const auto& sol = solv.get<bem::BemSolution>();
    const auto dir = cf::testing::temp_dir("bem-vtk");
    run_node("export.bem_vtk", {{"path", (dir / "body.vtp").string()}}, {{"solution", solv}});
    ASSERT_TRUE(std::filesystem::exists(dir / "body_cracks.vtp"));
    const auto u = vtp_array(dir / "body.vtp", "u");
    const auto t = vtp_array(dir / "body.vtp", "traction");
    const auto d = vtp_array(dir / "body.vtp", "dirichlet");
    const auto reg = vtp_array(dir / "body.vtp", "region");
    ASSERT_EQ(u.size(), 3 * cube.num_vertices());
    ASSERT_EQ(t.size(), 3 * cube.num_triangles());
    ASSERT_EQ(reg.size(), cube.num_triangles());
    double worst = 0;
    for (std::size_t v = 0; v < cube.num_vertices(); ++v)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(u[3 * v + k] - sol.displacement[v][k]));
    for (std::size_t e = 0; e < cube.num_triangles(); ++e) {
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(t[3 * e + k] - sol.traction[e][k]));
        EXPECT_EQ(reg[e], cube.region[e]);
        EXPECT_EQ(d[e], cube.region[e] == 4 ? 1.0 : 0.0);  // z_min is the displacement region
    }
    EXPECT_EQ(worst, 0.0);  // full double precision round trip
    const auto du = vtp_array(dir / "body_cracks.vtp", "du");
    const auto ua = vtp_array(dir / "body_cracks.vtp", "u_average");
    ASSERT_EQ(du.size(), 3 * crack.num_vertices());
    ASSERT_EQ(ua.size(), 3 * crack.num_vertices());
    double worst_du = 0;
    for (std::size_t v = 0; v < crack.num_vertices(); ++v)
        for (int k = 0; k < 3; ++k) worst_du = std::max(worst_du, std::abs(du[3 * v + k] - sol.crack_opening[v][k]));
    EXPECT_EQ(worst_du, 0.0);
    EXPECT_GT(du[2], 0.0);  // the centre node opens along +z (tension)
    // The crack is 5 m above the clamped bottom: its average displacement is upward and smaller than the top's.
    EXPECT_GT(ua[2], 0.0);
}

TEST(BemNodes, VtkExportRejectsUnwritablePath) {
    const SurfaceMesh cube = bem::bem_cube_mesh(1, 1.0);
    auto a = run_node("assemble.sgbem", {{"E", 1.0}, {"single_layer", false}}, {{"mesh", value(cube)}});
    auto s = run_node("solve.sgbem", {{"boundary_conditions", std::string("*: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    const auto dir = cf::testing::temp_dir("bem-vtk-bad");
    {
        std::ofstream blocker(dir / "file");
        blocker << "x";
    }
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] {
            run_node("export.bem_vtk", {{"path", (dir / "file" / "out.vtp").string()}}, {{"solution", s.outputs.at("solution")}});
        },
        {"parameter 'path'"}));
}
