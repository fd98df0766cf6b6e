// The region text parser: what it accepts, and every error message it gives.
#include "nodes/regions/region_spec.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

void expect_half_space(const HalfSpace& h, Vec3 normal, double offset, bool strict) {
    EXPECT_TRUE(h.normal.isApprox(normal, 1e-15)) << h.normal.transpose();
    EXPECT_NEAR(h.offset, offset, 1e-15);
    EXPECT_EQ(h.strict, strict);
}

std::string error_of(const std::string& spec) {
    try {
        parse_region_spec(spec);
    } catch (const RegionSpecError& e) {
        return e.what();
    }
    return "no error";
}

TEST(RegionSpec, ParsesTheDocumentedExample) {
    const auto r = parse_region_spec(
        "top: z >= 0.49; bottom: z <= -0.49; left_upper: x <= -0.49 & y >= 0; slanted: 0.7071*x + 0.7071*z >= 0.3");
    ASSERT_EQ(r.size(), 4u);
    EXPECT_EQ(r[0].name, "top");
    ASSERT_EQ(r[0].conditions.size(), 1u);
    expect_half_space(r[0].conditions[0], Vec3(0, 0, 1), -0.49, false);
    EXPECT_EQ(r[1].name, "bottom");
    expect_half_space(r[1].conditions[0], Vec3(0, 0, -1), -0.49, false);
    EXPECT_EQ(r[2].name, "left_upper");
    ASSERT_EQ(r[2].conditions.size(), 2u);
    expect_half_space(r[2].conditions[0], Vec3(-1, 0, 0), -0.49, false);
    expect_half_space(r[2].conditions[1], Vec3(0, 1, 0), 0, false);
    EXPECT_EQ(r[3].name, "slanted");
    expect_half_space(r[3].conditions[0], Vec3(0.7071, 0, 0.7071), -0.3, false);
}

TEST(RegionSpec, LinearExpressionsOnBothSides) {
    const auto r = parse_region_spec("a: 2x - y/4 + 3 > z; b: -x + 1e-3 < .5*y - 2*x + 1.5E1");
    // 2x - y/4 + 3 - z > 0
    expect_half_space(r[0].conditions[0], Vec3(2, -0.25, -1), 3, true);
    // (0.5 y - 2 x + 15) - (-x + 0.001) > 0  ->  -x + 0.5 y + 14.999
    expect_half_space(r[1].conditions[0], Vec3(-1, 0.5, 0), 14.999, true);
}

TEST(RegionSpec, LayoutIsFree) {
    const auto r = parse_region_spec("\n  top :z>=1 &&  x<=2 ;\n\n bottom: z <= -1;;\n");
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].conditions.size(), 2u);
    EXPECT_EQ(r[1].name, "bottom");
}

TEST(RegionSpec, ContainmentFollowsTheInequalities) {
    const auto r = parse_region_spec("box: x >= 0 & x < 1 & y >= 0 & y <= 1 & z > -1 & z < 1");
    EXPECT_TRUE(r[0].contains(Vec3(0, 0, 0)));
    EXPECT_TRUE(r[0].contains(Vec3(0.5, 1, 0.9)));
    EXPECT_FALSE(r[0].contains(Vec3(1, 0.5, 0)));   // x < 1 is strict
    EXPECT_FALSE(r[0].contains(Vec3(-1e-12, 0.5, 0)));
    EXPECT_FALSE(r[0].contains(Vec3(0.5, 0.5, -1)));  // z > -1 is strict
}

TEST(RegionSpec, ErrorsNameTheRegionThePositionAndTheFix) {
    EXPECT_EQ(error_of(""), "the region list is empty; write regions like 'top: z >= 0.49; bottom: z <= -0.49'");
    EXPECT_EQ(error_of(" ; ;"), "the region list is empty; write regions like 'top: z >= 0.49; bottom: z <= -0.49'");
    EXPECT_EQ(error_of("top: z 0.49"),
              "region 'top', column 8: expected a comparison (>=, <=, >, <) after 'z', found '0.49'");
    EXPECT_EQ(error_of("top: z"),
              "region 'top', column 7: expected a comparison (>=, <=, >, <) after 'z', found the end of the text");
    EXPECT_EQ(error_of("top z >= 0.49"), "region 'top', column 5: expected ':' after the region name 'top', found 'z'");
    EXPECT_EQ(error_of("3top: z >= 1"),
              "column 1: expected a region name (a letter or '_', then letters, digits or '_'), found '3'");
    EXPECT_EQ(error_of("top: z = 0.49"),
              "region 'top', column 8: '=' cannot select triangles (no centroid lies exactly on a plane); use '>=' or "
              "'<='");
    EXPECT_EQ(error_of("top: z => 0.49"), "region 'top', column 8: write '>=' instead of '=>'");
    EXPECT_EQ(error_of("top: z =< 0.49"), "region 'top', column 8: write '<=' instead of '=<'");
    EXPECT_EQ(error_of("top: z >> 0.49"), "region 'top', column 8: '>>' is not a comparison; use >=, <=, > or <");
    EXPECT_EQ(error_of("top: w >= 1"), "region 'top', column 6: unknown variable 'w'; conditions use x, y and z (metres)");
    EXPECT_EQ(error_of("top: x*y >= 1"),
              "region 'top', column 8: 'x*y' is not linear; multiply a variable only by numbers");
    EXPECT_EQ(error_of("top: 1/x >= 1"), "region 'top', column 8: '/x' is not linear; only divide by numbers");
    EXPECT_EQ(error_of("top: x/0 >= 1"), "region 'top', column 8: division by zero");
    EXPECT_EQ(error_of("top: z >= 1e999"), "region 'top', column 11: the number '1e999' is too large");
    EXPECT_EQ(error_of("top: 1 >= 0"),
              "region 'top', column 6: the condition '1 >= 0' does not depend on x, y or z, so it would hold "
              "everywhere or nowhere");
    EXPECT_EQ(error_of("top: x + z >= z + 1 + x"),
              "region 'top', column 6: the condition 'x + z >= z + 1 + x' does not depend on x, y or z, so it would hold "
              "everywhere or nowhere");
    EXPECT_EQ(error_of("top: z >= "),
              "region 'top', column 11: expected a number or x, y, z after '>=', found the end of the text");
    EXPECT_EQ(error_of("top: z >= 0.49 bottom: z <= 0"),
              "region 'top', column 16: expected '&' (and), ';' (next region) or the end after the condition, found "
              "'bottom'; separate regions with ';'");
    EXPECT_EQ(error_of("top: z >= 1 # up"),
              "region 'top', column 13: unexpected character '#'; conditions use numbers, x, y, z, + - * /, >= <= > <, "
              "'&' and ';'");
    EXPECT_EQ(error_of("top: z >= 1 & "),
              "region 'top', column 15: expected a number or x, y, z after '&', found the end of the text");
    EXPECT_EQ(error_of("top: z >= 1; top: z <= 0"),
              "region 'top' is defined twice (at column 1 and column 14); give each region its own name");
}

TEST(RegionSpec, MultiLineErrorsGiveTheLine) {
    EXPECT_EQ(error_of("top: z >= 1;\nbottom: z <= q"),
              "region 'bottom', line 2, column 14: unknown variable 'q'; conditions use x, y and z (metres)");
    EXPECT_EQ(error_of("top: z >= 1\nbottom: z <= 0"),
              "region 'top', line 2, column 1: expected '&' (and), ';' (next region) or the end after the condition, "
              "found 'bottom'; separate regions with ';'");
    EXPECT_EQ(error_of("a: x > 0;\n  b: y > 0;\n  a: z > 0"),
              "region 'a' is defined twice (at line 1, column 1 and line 3, column 3); give each region its own name");
}

}  // namespace
}  // namespace cf
