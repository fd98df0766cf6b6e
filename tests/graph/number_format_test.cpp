// Numbers in messages (graph/diagnostics.hpp): the shortest text that reads back as the same
// double, so values that differ never print alike (std::to_string's %f printed 2.9499e-4 and
// 2.95e-4 both as 0.000295, and 1e-7 as 0.000000).
#include "graph/diagnostics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

namespace cf::graph {
namespace {

TEST(NumberFormat, ShowsEveryDigitThatTellsValuesApart) {
    EXPECT_EQ(format_number(2.9499e-4), "0.00029499");
    EXPECT_EQ(format_number(2.95e-4), "0.000295");
    EXPECT_EQ(format_number(1e-7), "1e-07");
    EXPECT_EQ(format_number(0.1), "0.1");
    EXPECT_EQ(format_number(-3), "-3");
    EXPECT_EQ(format_number(7e10), "7e+10");  // the shorter of fixed and scientific
    EXPECT_EQ(format_number(1e300), "1e+300");
}

TEST(NumberFormat, ReadsBackAsTheSameDouble) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> mantissa(-10, 10);
    std::uniform_int_distribution<int> exponent(-300, 300);
    for (int i = 0; i < 20000; ++i) {
        const double x = mantissa(rng) * std::pow(10.0, exponent(rng));
        const std::string s = format_number(x);
        EXPECT_EQ(std::strtod(s.c_str(), nullptr), x) << s;  // (std::stod refuses subnormal values)
        EXPECT_LE(s.size(), 24u) << s;
    }
    const double tiny = std::numeric_limits<double>::denorm_min();
    EXPECT_EQ(std::strtod(format_number(tiny).c_str(), nullptr), tiny);
}

TEST(NumberFormat, NonFiniteValuesAreNamed) {
    EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN()), "nan");
    EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(NumberFormat, QuantityCarriesItsUnit) {
    EXPECT_EQ(format_quantity(2.9499e-4, "m"), "0.00029499 m");
    EXPECT_EQ(format_quantity(2e9, "Pa*sqrt(m)"), "2e+09 Pa*sqrt(m)");
    EXPECT_EQ(format_quantity(0.25, ""), "0.25");
}

}  // namespace
}  // namespace cf::graph
