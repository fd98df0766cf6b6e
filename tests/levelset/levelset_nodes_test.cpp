// The level-set, segment and simplify nodes run alone through the per-node harness: typed
// ports, parameter checks, counts, files written, and errors that name the problem.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragments.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace cf {
namespace {

using testing::run_node;
using testing::value;

SurfaceMesh box_mesh() {
    return run_node("shape.box", {{"size", std::vector<double>{1, 0.6, 0.4}}, {"subdivisions", 2LL}})
        .out<SurfaceMesh>("mesh");
}

LevelSet box_level_set(double r_f = 0.02) {
    return run_node("levelset.from_mesh", {{"voxel_size", r_f}}, {{"mesh", value(box_mesh())}}).out<LevelSet>("level_set");
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

TEST(LevelSetNodes, FromMeshReportsVolume) {
    const auto r = run_node("levelset.from_mesh", {{"voxel_size", 0.02}}, {{"mesh", value(box_mesh())}});
    EXPECT_NEAR(r.counts.at("volume_m3"), 0.24, 0.01 * 0.24);
    EXPECT_GT(r.counts.at("active_voxels"), 1000);
}

TEST(LevelSetNodes, FromMeshOpenMeshErrorNamesThePort) {
    SurfaceMesh open = box_mesh();
    open.triangles.pop_back();
    const std::string e = error_of([&] { run_node("levelset.from_mesh", {{"voxel_size", 0.02}}, {{"mesh", value(open)}}); });
    EXPECT_NE(e.find("input 'mesh'"), std::string::npos) << e;
    EXPECT_NE(e.find("boundary edges"), std::string::npos) << e;
}

TEST(LevelSetNodes, PlanarCrackOutsideTheObjectIsAnEmptyCrackError) {
    const std::string e = error_of([&] {
        run_node("levelset.crack_planar",
                 {{"centre", std::vector<double>{5, 0, 0}}, {"normal", std::vector<double>{1, 0, 0}}, {"radius", 0.5}},
                 {{"object", value(box_level_set())}});
    });
    EXPECT_NE(e.find("does not meet the object"), std::string::npos) << e;
}

TEST(LevelSetNodes, CutSegmentExportChain) {
    const LevelSet obj = box_level_set();
    const auto crack = run_node("levelset.crack_planar", {{"normal", std::vector<double>{1, 0, 0}}, {"radius", 2.0}},
                                {{"object", value(obj)}});
    ASSERT_EQ(crack.out<CrackLevelSets>("cracks").cracks.size(), 1u);
    const auto dir = testing::temp_dir("cut_segment_export");
    // s out of range: the node error explains it.
    const std::string e = error_of([&] {
        run_node("segment.fragments", {{"s", 0.05}}, {{"object", value(obj)}, {"cracks", crack.outputs.at("cracks")}}, dir);
    });
    EXPECT_NE(e.find("[0, r_f]"), std::string::npos) << e;
    const auto seg = run_node("segment.fragments", {}, {{"object", value(obj)}, {"cracks", crack.outputs.at("cracks")}}, dir);
    EXPECT_EQ(seg.counts.at("fragments"), 2);
    // Two halves of 0.5 x 0.6 x 0.4 minus half the gap each.
    const double half = 0.5 * 0.6 * 0.4 - 0.6 * 0.4 * std::sqrt(3.0) * 0.02 / 2;
    EXPECT_NEAR(seg.out<Fragments>("fragments").fragments[1].volume, half, 0.6 * 0.4 * 0.02);
    EXPECT_TRUE(std::filesystem::exists(dir / "fragments.csv"));
    EXPECT_TRUE(std::filesystem::exists(dir / "fragments.json"));
    const auto ex = run_node("export.fragments", {{"width", 160LL}, {"height", 120LL}},
                             {{"fragments", seg.outputs.at("fragments")}}, dir);
    EXPECT_EQ(ex.counts.at("files"), 5);  // 2 meshes, their .mtl, 1 vdb, 1 png
    for (const char* f : {"fragment_000.obj", "fragment_001.obj", "fragments.vdb", "fragments_preview.png"})
        EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
    std::ifstream png(dir / "fragments_preview.png", std::ios::binary);
    char sig[8] = {};
    png.read(sig, 8);
    EXPECT_EQ(std::string(sig + 1, 3), "PNG");
    // The VDB holds both fragment grids.
    const auto grids = read_vdb(dir / "fragments.vdb");
    ASSERT_EQ(grids.size(), 2u);
    EXPECT_EQ(grids[0].first, "fragment0");
}

TEST(LevelSetNodes, RemeshHitsTheTarget) {
    const auto r = run_node("simplify.remesh", {{"target_triangles", 600LL}, {"offset_voxels", 0.5}},
                            {{"level_set", value(box_level_set(0.01))}});
    EXPECT_NEAR(r.out<SurfaceMesh>("mesh").num_triangles(), 600.0, 30.0);
    EXPECT_EQ(r.counts.at("triangles"), double(r.out<SurfaceMesh>("mesh").num_triangles()));
}

TEST(LevelSetNodes, RecordCracksReportsHitsAndChecksFrontCount) {
    const LevelSet obj = box_level_set();
    const auto crack = run_node("levelset.crack_planar", {{"normal", std::vector<double>{0, 0, 1}}, {"radius", 0.1}},
                                {{"object", value(obj)}});
    std::vector<FrontMotion> fronts{FrontMotion{{Vec3(0.1, 0, 0), Vec3(0.1, 0.05, 0)}, {Vec3(0.12, 0, 0), Vec3(0.12, 0.05, 0)}, false}};
    const auto r = run_node("record.cracks", {},
                            {{"cracks", crack.outputs.at("cracks")}, {"fronts", value(fronts)}, {"object", value(obj)}});
    EXPECT_GT(r.counts.at("voxels_written"), 0);
    EXPECT_EQ(r.counts.at("hits_left_object"), 0);
    std::vector<FrontMotion> two(2, fronts[0]);
    const std::string e = error_of([&] {
        run_node("record.cracks", {}, {{"cracks", crack.outputs.at("cracks")}, {"fronts", value(two)}});
    });
    EXPECT_NE(e.find("2 front motions for 1 cracks"), std::string::npos) << e;
}

}  // namespace
}  // namespace cf
