// Torus (chain link): exact polyhedral volume and area, the smooth-torus limit, genus 1, and the
// two pulled outer faces.
#include "nodes/shape/torus.hpp"
#include "tests/shape/mesh_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

using testing::expect_closed_outward;
using testing::region_area;
using testing::region_triangles;

const double pi = std::acos(-1.0);

// The polyhedron is nu wedges; each grid quad is a planar isosceles trapezoid between the chords
// at profile points j and j+1 (half-angle alpha = pi/nu), and each wedge has volume
// sin(2 alpha) * (profile area) * (profile centroid radius = R).
double polyhedral_volume(const TorusSpec& s) {
    const double nu = s.major_segments, nv = s.minor_segments;
    return nu * std::sin(2 * pi / nu) * s.major_radius * 0.5 * nv * s.minor_radius * s.minor_radius * std::sin(2 * pi / nv);
}
double polyhedral_area(const TorusSpec& s) {
    const double alpha = pi / s.major_segments;
    double sum = 0;
    for (int j = 0; j < s.minor_segments; ++j) {
        const double t0 = 2 * pi * j / s.minor_segments, t1 = 2 * pi * (j + 1) / s.minor_segments;
        const double rho0 = s.major_radius + s.minor_radius * std::cos(t0), rho1 = s.major_radius + s.minor_radius * std::cos(t1);
        const double dz = s.minor_radius * (std::sin(t1) - std::sin(t0));
        sum += (rho0 + rho1) * std::sin(alpha) * std::hypot((rho1 - rho0) * std::cos(alpha), dz);
    }
    return s.major_segments * sum;
}

TEST(Torus, VolumeAndAreaMatchThePolyhedralFormulas) {
    TorusSpec s;
    s.major_radius = 0.05;
    s.minor_radius = 0.02;
    s.centre = Vec3(0.01, 0.02, 0.03);
    s.major_segments = 10;
    s.minor_segments = 5;
    s.pull_angle = 0.7;  // at least half a minor segment, pi/5
    const SurfaceMesh m = make_torus(s);
    EXPECT_EQ(m.num_triangles(), 100u);
    EXPECT_EQ(m.num_vertices(), 50u);
    expect_closed_outward(m, 0);  // genus 1
    EXPECT_NEAR(signed_volume(m), polyhedral_volume(s), 1e-13 * polyhedral_volume(s));
    EXPECT_NEAR(surface_area(m), polyhedral_area(s), 1e-13 * polyhedral_area(s));
}

TEST(Torus, ConvergesToTheSmoothTorus) {
    TorusSpec s;
    s.major_radius = 1;
    s.minor_radius = 0.3;
    s.major_segments = 200;
    s.minor_segments = 200;
    s.pull_angle = 0.3;
    const SurfaceMesh m = make_torus(s);
    const double v = 2 * pi * pi * 1 * 0.09, a = 4 * pi * pi * 1 * 0.3;
    // Volume ratio = sinc(2 pi/200)^2 = 1 - 2 (2 pi/200)^2 / 6 + ... = 1 - 3.3e-4.
    EXPECT_LT(signed_volume(m), v);
    EXPECT_NEAR(signed_volume(m) / v, 1, 4e-4);
    EXPECT_NEAR(surface_area(m) / a, 1, 4e-4);
}

TEST(Torus, PulledFacesAreMirrorImagesFacingOutAlongX) {
    const TorusSpec s;  // 24 x 12 segments, pull_angle 0.5 rad
    const SurfaceMesh m = make_torus(s);
    expect_closed_outward(m, 0);
    EXPECT_EQ(m.region_names, (std::vector<std::string>{"rest", "pull_left", "pull_right"}));
    // Quad centres within 0.5 rad: phi = pi -/+ pi/24, -/+ 3 pi/24 (4 of them) times theta = -/+ pi/12 (2):
    // 8 quads, 16 triangles per side.
    EXPECT_EQ(region_triangles(m, "pull_left"), 16u);
    EXPECT_EQ(region_triangles(m, "pull_right"), 16u);
    EXPECT_NEAR(region_area(m, "pull_left"), region_area(m, "pull_right"), 1e-15);
    Vec3 left = Vec3::Zero(), right = Vec3::Zero();
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Vec3 c = triangle_centroid(m, t) - s.centre;
        if (m.region_of(t) == 1) {
            left += triangle_normal_unnormalised(m, t);
            EXPECT_LT(c.x(), 0);
            EXPECT_GT(std::hypot(c.x(), c.y()), s.major_radius);  // on the outer side of the tube
        } else if (m.region_of(t) == 2) {
            right += triangle_normal_unnormalised(m, t);
            EXPECT_GT(c.x(), 0);
            EXPECT_GT(std::hypot(c.x(), c.y()), s.major_radius);
        }
    }
    EXPECT_GT(left.normalized().dot(Vec3(-1, 0, 0)), std::cos(s.pull_angle));
    EXPECT_TRUE(left.normalized().isApprox(-right.normalized(), 1e-12));
    // The whole mesh is its own mirror image in x.
    for (const Vec3& p : m.vertices) {
        const Vec3 q(2 * s.centre.x() - p.x(), p.y(), p.z());
        double nearest = 1e300;
        for (const Vec3& o : m.vertices) nearest = std::min(nearest, (o - q).norm());
        EXPECT_LT(nearest, 1e-15);
    }
}

TEST(Torus, BadSpecsAreRejected) {
    auto message = [](const TorusSpec& s) {
        try {
            make_torus(s);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    TorusSpec s;
    s.major_segments = 25;
    EXPECT_EQ(message(s), "parameter 'major_segments' must be even and >= 4 (so the left and right pulled faces are "
                          "mirror images), got 25");
    s = TorusSpec{};
    s.minor_radius = 0.05;
    EXPECT_EQ(message(s), "parameter 'major_radius' (0.04 m) must exceed 'minor_radius' (0.05 m), otherwise "
                          "the tube intersects itself");
    s = TorusSpec{};
    s.pull_angle = 0.1;  // below pi/12 = half a minor segment
    EXPECT_EQ(message(s), "parameter 'pull_angle' must be in [0.2617993877991494, pi/2) rad for these segment counts (a "
                          "smaller angle selects no quad centre), got 0.1 rad");
}

}  // namespace
}  // namespace cf
