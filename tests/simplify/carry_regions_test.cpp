// Regions carried from a fine mesh to a remeshed coarse one (issue 13): each coarse triangle takes
// the region of the nearest fine triangle. Truth for a box: the face a coarse triangle lies on is
// known from its normal (x_min has -e_x, ...), whatever the two meshes' triangulations.
#include "nodes/levelset/level_set.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"
#include "nodes/simplify/carry_regions.hpp"
#include "tests/harness/expect_error.hpp"
#include "tests/harness/node_harness.hpp"
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/bem/bem_types.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>
#include <utility>

using namespace cf;
using cf::testing::run_node;
using cf::testing::value;

namespace {

// The box face a triangle with unit normal n lies on (make_box's names), or "" for a slanted one
// (the remesh bevels edges and corners; a bevel triangle's centroid may lie beyond both faces).
std::string face_of(const Vec3& n) {
    static const char* names[3][2] = {{"x_min", "x_max"}, {"y_min", "y_max"}, {"z_min", "z_max"}};
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    return std::abs(n[axis]) > 0.999 ? names[axis][n[axis] > 0] : "";
}

// The fine box with triangle `spot` put into a region of its own.
SurfaceMesh box_with_spot(int subdivisions, std::size_t spot) {
    SurfaceMesh fine = make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), subdivisions, 0});
    fine.region_names.push_back("spot");
    fine.region[spot] = static_cast<int>(fine.region_names.size() - 1);
    return fine;
}

// A fine triangle that is no coarse triangle's nearest: every fine triangle its own region, carried.
std::size_t unclaimed_triangle(const SurfaceMesh& coarse, SurfaceMesh fine) {
    fine.region_names.clear();
    for (std::size_t t = 0; t < fine.num_triangles(); ++t) {
        fine.region[t] = static_cast<int>(t);
        fine.region_names.push_back("t" + std::to_string(t));
    }
    const CarriedRegions c = carry_regions(coarse, fine);
    if (c.empty_regions.empty()) throw std::runtime_error("every fine triangle is some coarse triangle's nearest");
    return std::stoul(c.empty_regions.front().substr(1));
}

}  // namespace

TEST(CarryRegions, CoarseBoxTrianglesTakeTheirFacesRegion) {
    const SurfaceMesh fine = make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 9, 0});
    SurfaceMesh coarse = make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 2, 0});
    for (Vec3& v : coarse.vertices) v *= 1.02;  // stands off the fine surface, as the remesh offset does
    coarse.region.clear();
    coarse.region_names = {"surface"};
    const CarriedRegions c = carry_regions(coarse, fine);
    EXPECT_TRUE(c.empty_regions.empty());
    EXPECT_EQ(c.mesh.region_names, fine.region_names);
    ASSERT_EQ(c.mesh.region.size(), coarse.num_triangles());
    for (std::size_t t = 0; t < coarse.num_triangles(); ++t)
        EXPECT_EQ(c.mesh.region_name(c.mesh.region_of(t)), face_of(triangle_normal(coarse, t))) << t;
    EXPECT_EQ(c.mesh.vertices, coarse.vertices);
    EXPECT_EQ(c.mesh.triangles, coarse.triangles);
}

TEST(CarryRegions, ARegionNoCoarseTriangleTakesIsReported) {
    const SurfaceMesh coarse = make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 1, 0});
    const SurfaceMesh fine = box_with_spot(6, unclaimed_triangle(coarse, make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 6, 0})));
    const CarriedRegions c = carry_regions(coarse, fine);
    EXPECT_EQ(c.empty_regions, std::vector<std::string>{"spot"});
    EXPECT_THROW(carry_regions(fine, SurfaceMesh{}), std::invalid_argument);
}

TEST(CarryRegions, RemeshNodeCarriesRegionsAndRefusesAnEmptyOne) {
    const SurfaceMesh fine = make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 6, 0});
    auto ls = run_node("levelset.from_mesh", {{"voxel_size", 0.025}}, {{"mesh", value(fine)}});
    auto r = run_node("simplify.remesh", {{"target_triangles", 400LL}},
                      {{"level_set", ls.outputs.at("level_set")}, {"regions_from", value(fine)}});
    const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
    EXPECT_EQ(m.region_names, fine.region_names);
    std::size_t agree = 0, flat = 0;
    double area = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const std::string face = face_of(triangle_normal(m, t));
        if (face.empty()) continue;  // on a rounded edge or corner of the remeshed box
        ++flat;
        agree += m.region_name(m.region_of(t)) == face;

    }
    for (const std::string& name : fine.region_names) {
        EXPECT_GT(r.counts.at("region." + name + ".triangles"), 0) << name;
        area += r.counts.at("region." + name + ".area");
    }
    EXPECT_NEAR(area, surface_area(m), 1e-9 * area);  // the report's areas cover the mesh
    EXPECT_GT(flat, m.num_triangles() / 2);
    EXPECT_EQ(agree, flat);  // every flat triangle took its own face's region
    // A half-space spec on top keeps the carried regions where it does not match.
    auto h = run_node("simplify.remesh", {{"target_triangles", 400LL}, {"regions", std::string("top: z >= 0.45")}},
                      {{"level_set", ls.outputs.at("level_set")}, {"regions_from", value(fine)}});
    EXPECT_GT(h.counts.at("region.top.triangles"), 0);
    EXPECT_GT(h.counts.at("region.x_min.triangles"), 0);
    // A region too small for the coarse mesh is an error naming it: a fine triangle that the same
    // remesh (deterministic) leaves without a coarse triangle.
    const std::size_t spot = unclaimed_triangle(m, fine);
    EXPECT_TRUE(cf::testing::throws<std::exception>(
        [&] {
            run_node("simplify.remesh", {{"target_triangles", 400LL}},
                     {{"level_set", ls.outputs.at("level_set")}, {"regions_from", value(box_with_spot(6, spot))}});
        },
        {"'spot'", "got no triangle", "raise target_triangles"}));
}

namespace {

// A ball of radius 0.05 m in an OBJ file (written in millimetres): the faces below z = -40 mm in
// group 'clamp', those above z = 40 mm with material 'lid', the rest unnamed. (A ball, not a box:
// a box remeshed from its level set gives an indefinite single layer under any displacement
// condition, on main too; see the report of issue 13.)
std::string grouped_ball_obj() {
    SphereSpec spec;
    spec.radius = 50;
    spec.level = 3;
    const SurfaceMesh m = make_icosphere(spec);
    std::string v, unnamed, clamp = "g clamp\n", lid = "usemtl lid\n";
    char line[128];
    for (const Vec3& p : m.vertices) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
        v += line;
    }
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Tri& f = m.triangles[t];
        std::snprintf(line, sizeof line, "f %d %d %d\n", f[0] + 1, f[1] + 1, f[2] + 1);
        const double z = triangle_centroid(m, t).z();
        (z <= -40 ? clamp : z >= 40 ? lid : unnamed) += line;
    }
    return v + unnamed + clamp + lid;
}

std::string grouped_ball_pipeline(const std::filesystem::path& obj, const std::string& bc) {
    return "nodes:\n"
           "  part: {type: import.mesh, params: {path: '" + obj.string() + "', scale: 0.001}}\n"
           "  object: {type: levelset.from_mesh, inputs: {mesh: part.mesh}, params: {voxel_size: 0.002}}\n"
           "  bem: {type: simplify.remesh, inputs: {level_set: object.level_set, regions_from: part.mesh}, params: {target_triangles: 300}}\n"
           "  assemble: {type: assemble.sgbem, inputs: {mesh: bem.mesh}}\n"
           "  solve:\n"
           "    type: solve.sgbem\n"
           "    inputs: {operators: assemble.operators}\n"
           "    params: {boundary_conditions: '" + bc + "'}\n";
}

graph::ExecutionResult run_text(const std::string& text, const std::string& tag) {
    std::vector<graph::Diagnostic> diags;
    const graph::Plan plan = graph::load_pipeline_text(text, tag + ".yaml", node_registry(), {}, diags);
    if (!diags.empty()) throw std::runtime_error(graph::format(diags.front()));
    graph::RunOptions run;
    run.output_dir = cf::testing::temp_dir(tag);
    return graph::execute(plan, run);
}

}  // namespace

// End to end through the executor: face groups of an OBJ file carried to the remeshed BEM mesh load
// it. Independent checks: the pressure on the lid cap adds up to p times the area its rim encloses
// (pi (R^2 - 0.04^2) projected on z; the cap's own shape does not matter), the load is along z by
// symmetry, and the clamp's reaction balances it. That balance is only as good as the P0 reaction
// of a clamp whose rim carries a singular traction: 6.1 % off at 300 triangles, 4.0 % at 1200
// (cube_tension's clamped bottom: 1.3 % at 216), so its bar is 10 %.
TEST(CarryRegions, GroupsOfAnObjFileLoadTheRemeshedMesh) {
    const auto dir = cf::testing::temp_dir("grouped-ball-file");
    const auto obj = dir / "part.obj";
    std::ofstream(obj) << grouped_ball_obj();
    const double p = 1e5;
    const graph::ExecutionResult res =
        run_text(grouped_ball_pipeline(obj, "clamp: displacement 0 0 0; lid: pressure 1e5; *: traction 0 0 0"), "grouped-ball");
    ASSERT_TRUE(res.ok) << res.error;
    const auto& sol = res.outputs.at("solve").at("solution").get<bem::BemSolution>();
    const SurfaceMesh& m = sol.surface->mesh;
    Vec3 load = Vec3::Zero(), reaction = Vec3::Zero();
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const std::string r = m.region_name(m.region_of(t));
        if (r == "lid") load += -p * triangle_normal(m, t) * triangle_area(m, t);
        if (r == "clamp") reaction += sol.traction[t] * triangle_area(m, t);
    }
    // The BEM mesh stands one voxel (2 mm) outside the ball, and a coarse triangle takes the region
    // of the fine triangle nearest it, i.e. radially below it: the rim lies on the sphere of radius
    // R_c = 52 mm at height 40 R_c / 50 mm.
    const double R_c = 0.052, z_rim = 0.04 * R_c / 0.05;
    const double rim_area = M_PI * (R_c * R_c - z_rim * z_rim);
    std::cout << "grouped ball: load " << load.transpose() << " N (p x rim area " << p * rim_area << " N), clamp reaction "
              << reaction.transpose() << " N, |sum| / |load| " << (load + reaction).norm() / load.norm() << "\n";
    EXPECT_NEAR(-load.z(), p * rim_area, 0.05 * p * rim_area);  // measured +4.3 %
    // The lateral part of the load. By Stokes, sum over the lid of n A = 1/2 sum over its rim edges
    // (p, q) of p x q, whose horizontal part is z^ x sum_e (z_e - c) (q - p)_h for any constant c
    // (z_e the edge's mid height; the sum of (q - p)_h over a closed rim vanishes). So the lateral
    // load is bounded by p sum_e |z_e - z_rim| |(q - p)_h|: it vanishes only for a rim in the plane
    // z = z_rim, and a rim made of coarse triangles' edges departs from it by up to about an edge.
    // The 1e-3 bar before issue 13 held for the QEM mesh, whose rim happened to be near-planar; it
    // is not a property of carried regions. Checked instead: the lateral load is the rim's own
    // (within that bound), and the rim stays within one coarse edge of the fine rim's plane (a
    // coarse triangle takes the region of the fine triangle nearest it, so it cannot stray further).
    std::set<std::pair<int, int>> lid_edges;
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        if (m.region_name(m.region_of(t)) == "lid")
            for (int k = 0; k < 3; ++k) lid_edges.insert({m.triangles[t][k], m.triangles[t][(k + 1) % 3]});
    double bound = 0, rim_offset = 0, longest_edge = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k)
            longest_edge = std::max(longest_edge, (m.vertices[m.triangles[t][k]] - m.vertices[m.triangles[t][(k + 1) % 3]]).norm());
    for (const auto& [i, j] : lid_edges) {
        if (lid_edges.count({j, i})) continue;  // interior edge of the lid
        const Vec3 a = m.vertices[i], b = m.vertices[j];
        bound += p * std::abs(0.5 * (a.z() + b.z()) - z_rim) * (b - a).head<2>().norm();
        rim_offset = std::max(rim_offset, std::abs(a.z() - z_rim));
    }
    std::cout << "grouped ball: lateral load " << load.head<2>().norm() << " N (" << load.head<2>().norm() / load.norm()
              << " of the load), rim bound " << bound << " N, rim off its plane by up to " << rim_offset
              << " m (longest coarse edge " << longest_edge << " m)\n";
    EXPECT_LE(load.head<2>().norm(), bound * (1 + 1e-9));
    EXPECT_LE(rim_offset, longest_edge);
    EXPECT_LT((load + reaction).norm(), 0.1 * load.norm());  // measured 6.1 %
    // A condition naming a region the file does not have is refused by validate, at the condition's
    // line, naming the file's groups (the regions simplify.remesh carries from it).
    std::vector<graph::Diagnostic> diags;
    graph::load_pipeline_text(grouped_ball_pipeline(obj, "clamp: displacement 0 0 0; lids: pressure 1e5; *: traction 0 0 0"),
                              "grouped-ball-bad.yaml", node_registry(), {}, diags);
    ASSERT_EQ(diags.size(), 1u);
    const std::string text = graph::format(diags.front());
    EXPECT_NE(text.find("grouped-ball-bad.yaml:"), std::string::npos) << text;
    EXPECT_NE(text.find("names region 'lids'"), std::string::npos) << text;
    EXPECT_NE(text.find("its regions: clamp, default, lid)"), std::string::npos) << text;
}
