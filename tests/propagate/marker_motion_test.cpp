// One marker sub-step (thesis ch. 4.5) with hand-computed displacements.
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/propagate/marker_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf::propagate {
namespace {

PropagationSettings pmma() {
    PropagationSettings s;
    s.E = 3.1e9;
    s.nu = 0.327;
    s.rho = 1200;
    s.r_c = 0.01;
    s.r_f = 0.0005;
    return s;
}

ScalarField homogeneous(double Kc, double fc = 2) {
    return make_field(std::make_shared<HomogeneousField>(Kc), FieldQuantity::toughness, fc);
}

TEST(MarkerSubstep, ModeIAtTwiceToughnessMovesThreeQuartersOfRf) {
    MarkerState m;
    m.n1 = Vec3::UnitZ();
    m.n2 = Vec3::UnitY();
    m.K = {2e6, 0, 0};
    const MarkerStep st = marker_substep(m, homogeneous(1e6), pmma(), 1.0, false);
    // v = c_R (1 - 1/4); dt = r_f / c_R -> displacement 0.75 r_f along n2.
    EXPECT_NEAR((st.displacement - 0.75 * 0.0005 * Vec3::UnitY()).norm(), 0, 1e-15);
    EXPECT_FALSE(st.compressive);
}

TEST(MarkerSubstep, BelowToughnessDoesNotMove) {
    MarkerState m;
    m.K = {0.9e6, 0.1e6, 0};
    const MarkerStep st = marker_substep(m, homogeneous(1e6), pmma(), 1.0, false);
    EXPECT_EQ(st.speed, 0.0);
    EXPECT_EQ(st.displacement, Vec3::Zero());
    m.K = {5e6, 0, 0};
    m.active = false;
    EXPECT_EQ(marker_substep(m, homogeneous(1e6), pmma(), 1.0, false).displacement, Vec3::Zero());
}

TEST(MarkerSubstep, MixedModeTurnsByTheKinkAngleBlendedFromZero) {
    MarkerState m;
    m.n1 = Vec3::UnitZ();
    m.n2 = Vec3::UnitX();
    m.K = {3e6, 3e6, 0};  // theta* = -53.13 deg
    const double th = std::atan(4.0 / 3);
    MarkerStep st = marker_substep(m, homogeneous(1e6), pmma(), 1.0, false);
    EXPECT_NEAR(st.theta, -th, 1e-12);
    const Vec3 d = st.displacement.normalized();
    EXPECT_NEAR(d.z(), -std::sin(th), 1e-12);
    EXPECT_NEAR(d.x(), std::cos(th), 1e-12);
    // New crack (no history): theta_old = 0, so half-way through the step theta = theta*/2.
    st = marker_substep(m, homogeneous(1e6), pmma(), 0.5, false);
    EXPECT_NEAR(st.theta, -th / 2, 1e-12);
    // History from a pure mode-I step: theta_old = 0 again; with history K_II: blend of both.
    m.has_old = true;
    m.K_old = {3e6, 0, 0};
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.25, false).theta, -0.25 * th, 1e-12);
    // Planar first sub-step after initiation.
    EXPECT_EQ(marker_substep(m, homogeneous(1e6), pmma(), 1.0, true).theta, 0.0);
}

// Eq. (4.12) blends from the marker's last propagation direction. After a kinked step the new
// frame follows the kinked crack, so that direction is along the new n2 (theta_old = 0) even
// though the previous SIFs alone would say theta*(K_old) = -70.5 deg: blending from
// theta*(K_old) in the new frame would kink a second time.
TEST(MarkerSubstep, BlendStartsFromTheLastDirectionInTheNewFrame) {
    MarkerState m;
    m.n1 = Vec3::UnitZ();
    m.n2 = Vec3::UnitX();
    m.K = {3e6, 3e6, 0};  // theta* = -atan(4/3) = -53.13 deg
    const double th = std::atan(4.0 / 3);
    m.has_old = true;
    m.K_old = {0, 3e6, 0};  // pure mode II: theta*(K_old) = -70.53 deg
    m.last_theta = -1.2309594173407747;
    m.last_direction = Vec3::UnitX();  // moved along today's n2
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.0, false).theta, 0.0, 1e-12);
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.25, false).theta, -0.25 * th, 1e-12);
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 1.0, false).theta, -th, 1e-12);
    // Last moved 30 deg towards +n1 in today's frame: the step starts there.
    const double a = M_PI / 6;
    m.last_direction = Vec3(std::cos(a), 0, std::sin(a));
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.0, false).theta, a, 1e-12);
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.5, false).theta, 0.5 * a - 0.5 * th, 1e-12);
    // Without a recorded direction (older state) theta*(K_old) is the fallback.
    m.last_direction = Vec3::Zero();
    EXPECT_NEAR(marker_substep(m, homogeneous(1e6), pmma(), 0.0, false).theta, -1.2309594173407747, 1e-9);
}

TEST(MarkerSubstep, CompressedFrontUsesTransformedSifs) {
    MarkerState m;
    m.K = {-5e6, 0, 0};  // compressive; with f_c = 2: K_I -> 2.5e6
    const MarkerStep st = marker_substep(m, homogeneous(1e6, 2), pmma(), 1.0, false);
    EXPECT_TRUE(st.compressive);
    const double cR = rayleigh_speed(pmma().mu(), 1200);
    EXPECT_NEAR(st.speed, cR * (1 - 1 / 6.25), 1e-9);
    EXPECT_EQ(st.theta, 0.0);
    // f_c = 10: -K_I / f_c = 0.5e6 < K_c: no motion.
    EXPECT_EQ(marker_substep(m, homogeneous(1e6, 10), pmma(), 1.0, false).speed, 0.0);
}

TEST(MarkerSubstep, ToughnessGradientSteersTowardsWeakerMaterial) {
    // Toughness falls towards +z (= n1): K_c = a - b cos(f z) near z = -pi/(2f) has gradient -b f e_z.
    const double a = 1e6, b = 2e5, f = 100;
    const ScalarField layered =
        make_field(std::make_shared<LayeredField>(a, b, f, Vec3::UnitZ()), FieldQuantity::toughness, 2);
    MarkerState m;
    m.position = Vec3(0, 0, -M_PI / (2 * f));  // K_c = a, gradient -b f e_z
    m.n1 = Vec3::UnitZ();
    m.n2 = Vec3::UnitX();
    m.K = {2e6, 0, 0};
    const PropagationSettings s = pmma();
    const MarkerStep st = marker_substep(m, layered, s, 1.0, false);
    // theta_grad = +pi/2, clamped to the valid interval end 2 acos(2^(-1/3)); w = 1/(1 + b f r_c / a).
    const double hi = 2 * std::acos(std::cbrt(0.5));
    const double w = 1 / (1 + b * f * s.r_c / a);
    EXPECT_NEAR(st.theta, (1 - w) * hi, 1e-9);
    EXPECT_GT(st.displacement.z(), 0);
}

}  // namespace
}  // namespace cf::propagate
