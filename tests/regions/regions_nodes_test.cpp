// regions.halfspace through the per-node harness.
#include "nodes/shape/box.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

using testing::run_node;
using testing::value;

graph::Value cube() { return value(make_box(BoxSpec{Vec3(1, 1, 1), Vec3::Zero(), 4})); }

std::string error_of(const testing::Params& p) {
    try {
        run_node("regions.halfspace", p, {{"mesh", cube()}});
    } catch (const graph::NodeError& e) {
        return e.what();
    }
    return "no error";
}

TEST(RegionsNode, LabelsAndReportsEachRegion) {
    auto r = run_node("regions.halfspace",
                      {{"regions", std::string("top: z >= 0.49; bottom: z <= -0.49; left_upper: x <= -0.49 & y >= 0")}},
                      {{"mesh", cube()}});
    const SurfaceMesh& m = r.out<SurfaceMesh>("mesh");
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"default", "top", "bottom", "left_upper"}));
    EXPECT_EQ(r.counts.at("region.top.triangles"), 32);
    EXPECT_NEAR(r.counts.at("region.top.area"), 1.0, 1e-15);
    EXPECT_EQ(r.counts.at("region.left_upper.triangles"), 16);
    EXPECT_NEAR(r.counts.at("region.left_upper.area"), 0.5, 1e-15);
    EXPECT_EQ(r.counts.at("region.default.triangles"), 192 - 32 - 32 - 16);
    EXPECT_EQ(r.counts.at("unmatched_triangles"), 112);
}

TEST(RegionsNode, KeepUnmatched) {
    auto r = run_node("regions.halfspace", {{"regions", std::string("top_left: z >= 0.49 & x <= 0")}, {"keep_unmatched", true}},
                      {{"mesh", cube()}});
    EXPECT_EQ(r.counts.at("region.z_max.triangles"), 16);
    EXPECT_EQ(r.counts.at("region.top_left.triangles"), 16);
    EXPECT_EQ(r.counts.at("region.x_min.triangles"), 32);
}

TEST(RegionsNode, ErrorsNameTheParameterAndRegion) {
    EXPECT_EQ(error_of({{"regions", std::string("top: z 0.49")}}),
              "parameter 'regions': region 'top', column 8: expected a comparison (>=, <=, >, <) after 'z', found "
              "'0.49'");
    EXPECT_EQ(error_of({{"regions", std::string("top: z >= 0.49; high: z >= 2")}}),
              "parameter 'regions': region 'high' holds no triangle centroid (an earlier region may have taken them, "
              "or the inequalities miss the mesh, whose bounding box is x in [-0.5, 0.5], y in [-0.5, 0.5], z in "
              "[-0.5, 0.5]); fix the inequalities or set allow_empty: true");
    EXPECT_EQ(error_of({}), "missing required parameter 'regions' (regions in order, e.g. 'top: z >= 0.49; bottom: z <= "
                            "-0.49; corner: x <= -0.4 & y >= 0' (coordinates in m; earlier regions win))");
    auto r = run_node("regions.halfspace", {{"regions", std::string("high: z >= 2")}, {"allow_empty", true}},
                      {{"mesh", cube()}});
    EXPECT_EQ(r.counts.at("region.high.triangles"), 0);
    EXPECT_EQ(r.counts.at("region.default.triangles"), 192);
}

}  // namespace
}  // namespace cf
