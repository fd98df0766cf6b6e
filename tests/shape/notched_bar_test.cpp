// Notched bar: exact volume and region areas for both notch shapes, mirror symmetry, edge length.
#include "nodes/shape/notched_bar.hpp"
#include "tests/shape/mesh_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

using testing::expect_closed_outward;
using testing::longest_edge;
using testing::region_area;
using testing::region_triangles;

NotchedBarSpec spec(NotchShape notch) {
    NotchedBarSpec s;
    s.length = 0.4;
    s.height = 0.1;
    s.depth = 0.05;
    s.centre = Vec3(1, 2, 3);
    s.notch = notch;
    s.notch_width = 0.012;
    s.notch_depth = 0.03;
    s.support_span = 0.3;
    s.strip_width = 0.02;
    s.resolution = 0.01;
    return s;
}

// Volume about the bar's own centre: the divergence-theorem sum about a far origin would lose
// digits to cancellation.
double volume_about_centre(SurfaceMesh m, const Vec3& centre) {
    for (Vec3& p : m.vertices) p -= centre;
    return signed_volume(m);
}

void expect_common(const SurfaceMesh& m, const NotchedBarSpec& s) {
    expect_closed_outward(m, 2);
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"rest", "support_left", "support_right", "load", "notch"}));
    const double strip = s.strip_width * s.depth;
    EXPECT_NEAR(region_area(m, "support_left"), strip, 1e-15);
    EXPECT_NEAR(region_area(m, "support_right"), strip, 1e-15);
    EXPECT_NEAR(region_area(m, "load"), strip, 1e-15);
    EXPECT_EQ(region_triangles(m, "support_left"), region_triangles(m, "support_right"));
    // Cells are at most resolution on a side, so no edge (a cell diagonal at worst) exceeds twice that.
    EXPECT_LE(longest_edge(m), 2 * s.resolution);
    // No slivers: the V-notch lattice leans into the notch instead of squeezing columns under it.
    EXPECT_GE(testing::smallest_angle_degrees(m), 20.0);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Vec3 c = triangle_centroid(m, t) - s.centre, n = triangle_normal(m, t);
        switch (m.region_of(t)) {
            case 1:
            case 2:
                EXPECT_NEAR(c.z(), -0.5 * s.height, 1e-15);
                EXPECT_TRUE(n.isApprox(Vec3(0, 0, -1), 1e-14));
                EXPECT_LE(std::abs(std::abs(c.x()) - 0.5 * s.support_span), 0.5 * s.strip_width);
                EXPECT_EQ(m.region_of(t), c.x() < 0 ? 1 : 2);
                break;
            case 3:
                EXPECT_NEAR(c.z(), 0.5 * s.height, 1e-15);
                EXPECT_TRUE(n.isApprox(Vec3(0, 0, 1), 1e-14));
                EXPECT_LE(std::abs(c.x()), 0.5 * s.strip_width);
                break;
            case 4:
                EXPECT_LE(std::abs(c.x()), 0.5 * s.notch_width + 1e-15);
                EXPECT_LE(c.z(), -0.5 * s.height + s.notch_depth + 1e-15);
                break;
            default: break;
        }
    }
    // Mirror symmetry in x about the centre (the 3-point-bending test is symmetric).
    for (const Vec3& p : m.vertices) {
        const Vec3 q(2 * s.centre.x() - p.x(), p.y(), p.z());
        double nearest = 1e300;
        for (const Vec3& o : m.vertices) nearest = std::min(nearest, (o - q).norm());
        ASSERT_LT(nearest, 1e-12);
    }
}

TEST(NotchedBar, VNotchVolumeAndAreasAreExact) {
    const NotchedBarSpec s = spec(NotchShape::V);
    const SurfaceMesh m = make_notched_bar(s);
    expect_common(m, s);
    const double L = s.length, H = s.height, D = s.depth, w = s.notch_width, d = s.notch_depth;
    const double profile = L * H - 0.5 * w * d;
    EXPECT_NEAR(volume_about_centre(m, s.centre), profile * D, 1e-13 * profile * D);
    const double wall = 2 * std::hypot(0.5 * w, d) * D;
    EXPECT_NEAR(region_area(m, "notch"), wall, 1e-15);
    EXPECT_NEAR(surface_area(m), 2 * profile + (L + (L - w) + 2 * H) * D + wall, 1e-14);
}

TEST(NotchedBar, RectangularNotchVolumeAndAreasAreExact) {
    const NotchedBarSpec s = spec(NotchShape::Rectangular);
    const SurfaceMesh m = make_notched_bar(s);
    expect_common(m, s);
    const double L = s.length, H = s.height, D = s.depth, w = s.notch_width, d = s.notch_depth;
    const double profile = L * H - w * d;
    EXPECT_NEAR(volume_about_centre(m, s.centre), profile * D, 1e-13 * profile * D);
    EXPECT_NEAR(region_area(m, "notch"), (2 * d + w) * D, 1e-15);
    EXPECT_NEAR(surface_area(m), 2 * profile + (L + (L - w) + 2 * H) * D + (2 * d + w) * D, 1e-14);
}

TEST(NotchedBar, ResolutionControlsTheElementCount) {
    NotchedBarSpec s = spec(NotchShape::V);
    s.resolution = 0.02;
    const std::size_t coarse = make_notched_bar(s).num_triangles();
    s.resolution = 0.01;
    const std::size_t fine = make_notched_bar(s).num_triangles();
    // Surface elements scale like 1/h^2; the fixed breakpoints (strips, notch) keep it from being exactly 4.
    EXPECT_GT(static_cast<double>(fine) / coarse, 3.0);
    EXPECT_LT(static_cast<double>(fine) / coarse, 4.5);
}

TEST(NotchedBar, DimensionsThatDoNotFitAreRejectedNamingTheParameter) {
    auto message = [](const NotchedBarSpec& s) {
        try {
            make_notched_bar(s);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    NotchedBarSpec s = spec(NotchShape::V);
    s.notch_depth = 0.1;
    EXPECT_EQ(message(s), "parameter 'notch_depth' must be in (0, height = 0.1 m), got 0.1 m");
    s = spec(NotchShape::V);
    s.support_span = 0.39;
    EXPECT_EQ(message(s), "the support strips stick out of the bar: support_span + strip_width = 0.41 m exceeds length "
                          "= 0.4 m; reduce 'support_span' or 'strip_width'");
    s = spec(NotchShape::V);
    s.support_span = 0.02;
    EXPECT_EQ(message(s), "the support strips reach the notch: support_span - strip_width = 0 m must exceed "
                          "notch_width = 0.012 m; increase 'support_span' or reduce 'strip_width' or 'notch_width'");
    s = spec(NotchShape::V);
    s.strip_width = 1e-12;  // the load strip's edges would merge with the notch apex
    EXPECT_EQ(message(s), "parameter 'strip_width' = 1e-12 m is too small next to the bar's size; widen the load strip");
    s = spec(NotchShape::V);
    s.resolution = 1e-5;
    EXPECT_EQ(message(s).rfind("parameter 'resolution' = 1e-05 m would make about ", 0), 0u) << message(s);
}

}  // namespace
}  // namespace cf
