// The SIF estimator of thesis ch. 5.1 against hand-derived values.
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/estimate/estimate_verification.hpp"
#include "nodes/estimate/sif_estimator.hpp"
#include "nodes/propagate/propagation_law.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace cf;
using Mat3 = bem::Mat3;

namespace {
const Vec3 e1(1, 0, 0), e2(0, 0, 1), e3(0, -1, 0);  // forward x, normal z, e3 = e1 x e2
const double nu = 0.3, f = 0.5;                      // f = scale (pi A)^(1/4) lumped (scale 1, sqrt_pi_a 0.5)
}  // namespace

// Eq. (5.2) inverts eq. (4.10): the kink angle of (K, eta K) is the theta eta was made for.
TEST(SifEstimator, EtaInvertsTheKinkAngle) {
    for (double deg : {-65.0, -40.0, -10.0, -1.0, 1.0, 10.0, 40.0, 65.0}) {
        const double th = deg * M_PI / 180;
        const double eta = estimate::eta_for_kink(th);
        EXPECT_NEAR(propagate::kink_angle(1.0, eta), th, 1e-12) << deg;
    }
    EXPECT_EQ(estimate::eta_for_kink(0.0), 0.0);
}

// Principal tension along the crack normal: pure mode I of magnitude scale lambda (pi A)^(1/4).
TEST(SifEstimator, AlignedTensionIsPureModeOne) {
    const Mat3 s = 2e6 * e2 * e2.transpose() + 0.5e6 * e1 * e1.transpose();
    int choice = -1;
    const Vec3 K = estimate::aligned_estimate(s, e1, e2, e3, nu, 1.0, f, 2, &choice);
    EXPECT_NEAR(K[0], 2e6 * f, 1e-6);
    EXPECT_NEAR(K[1], 0, 1e-6);
    EXPECT_NEAR(K[2], 0, 1e-6);
    EXPECT_EQ(choice, 0);
    const Vec3 B = estimate::basic_estimate(s, e1, e2, e3, 1.0, f);
    EXPECT_NEAR(B[0], 2e6 * f, 1e-6);
}

// A principal direction tilted by beta towards e1 (forward): the estimate kinks the crack so its
// normal turns onto it (theta* = -beta), with K_I,III^2 + K_II^2 = (scale lambda (pi A)^(1/4))^2.
TEST(SifEstimator, TiltedPrincipalDirectionSetsTheKink) {
    for (double deg : {5.0, 20.0, 45.0, -30.0}) {
        const double b = deg * M_PI / 180;
        const Vec3 v = std::cos(b) * e2 + std::sin(b) * e1;
        const Mat3 s = 3e6 * v * v.transpose();
        const Vec3 K = estimate::aligned_estimate(s, e1, e2, e3, nu, 1.0, f, 1);
        EXPECT_NEAR(propagate::kink_angle(K[0], K[1]), -b, 1e-9) << deg;
        EXPECT_NEAR(std::hypot(K[0], K[1]), 3e6 * f, 1e-3) << deg;
        EXPECT_NEAR(K[2], 0, 1e-6);
        // The basic estimator's K_II has the same sign (e1^T sigma e2 = lambda sin b cos b).
        const Vec3 B = estimate::basic_estimate(s, e1, e2, e3, 1.0, f);
        EXPECT_GT(B[1] * K[1], 0) << deg;
    }
}

// Tilted towards the front tangent: mode I and III share K_I,III (eq. 5.4), K_III signed as the
// basic estimator's e3^T sigma e2.
TEST(SifEstimator, TangentTiltSplitsModesOneAndThree) {
    const double b = 30 * M_PI / 180;
    const Vec3 v = std::cos(b) * e2 + std::sin(b) * e3;
    const Mat3 s = 1e6 * v * v.transpose();
    const Vec3 K = estimate::aligned_estimate(s, e1, e2, e3, nu, 1.0, f, 1);
    const double cos_alpha = std::sin(b);
    EXPECT_NEAR(K[0], 1e6 * f * std::sqrt(1 - cos_alpha), 1e-6);
    EXPECT_NEAR(std::abs(K[2]), 1e6 * f * std::sqrt(cos_alpha * (1 - nu)), 1e-6);
    EXPECT_NEAR(propagate::mode_i_iii_sif({K[0], K[1], K[2]}, nu), 1e6 * f, 1e-6);
    EXPECT_GT(K[2] * estimate::basic_estimate(s, e1, e2, e3, 1.0, f)[2], 0);
}

// Largest principal direction in the crack plane (cos theta* < 1/3): the second largest, or the
// most negative one when |lambda_min| / f_c exceeds it.
TEST(SifEstimator, PrincipalDirectionChoiceAndTheCompressiveFactor) {
    const Mat3 s = 5e6 * e1 * e1.transpose() + 1e6 * e2 * e2.transpose() - 4e6 * e3 * e3.transpose();
    // lambda: -4e6 along e3 (|cos theta| undefined: in-plane), 1e6 along e2, 5e6 along e1 (in-plane).
    int choice = -1;
    Vec3 K = estimate::aligned_estimate(s, e1, e2, e3, nu, 1.0, f, 2, &choice);
    EXPECT_EQ(choice, 3);  // 4e6 / 2 > 1e6, but e3 lies in the crack plane (cos theta* = 0): the remaining e2
    EXPECT_NEAR(K[0], 1e6 * f, 1e-6);
    const Mat3 c = 5e6 * e1 * e1.transpose() + 1e6 * e3 * e3.transpose() - 4e6 * e2 * e2.transpose();
    K = estimate::aligned_estimate(c, e1, e2, e3, nu, 1.0, f, 2, &choice);
    EXPECT_EQ(choice, 2);  // 4e6 / f_c = 2e6 > 1e6: the compressive direction, normal to the crack
    EXPECT_NEAR(K[0], -4e6 * f, 1e-6);
    K = estimate::aligned_estimate(c, e1, e2, e3, nu, 1.0, f, 8, &choice);
    EXPECT_EQ(choice, 3);  // f_c = 8: 0.5e6 < 1e6, so the second largest (in-plane) fails and the last one is taken
}

namespace {
// A pure Neumann cube under uniaxial tension sigma along z and a sheet inside it.
struct UniaxialCube {
    std::shared_ptr<const bem::BemSolution> sol;
    SurfaceMesh sheet;
    UniaxialCube(const Vec3& origin, const Vec3& u, const Vec3& v) {
        const SurfaceMesh cube = bem::bem_cube_mesh(4, 1.0);
        Material m;
        bem::AssemblyOptions o;
        o.single_layer = false;
        const auto ops = bem::assemble_surface_operators(cube, m, o);
        const auto bc = bem::resolve(bem::parse_boundary_conditions("z_max: traction 0 0 1e6; z_min: traction 0 0 -1e6; *: traction 0 0 0"), cube);
        sol = bem::solve_sgbem(ops, nullptr, bc, {}, nullptr);
        sheet = estimate::rectangle_sheet(origin, u, v, 3, 3);
    }
};
}  // namespace

// A horizontal sheet in the middle of a cube under uniform tension: every front edge gets
// K_I = (2/pi) sigma sqrt(pi a), a = sqrt(A / pi) (the default circular-crack factor).
TEST(SifEstimator, UniformTensionGivesTheCircularCrackValueOnEveryEdge) {
    const UniaxialCube c(Vec3(-0.1, -0.1, 0.01), Vec3(0.2, 0, 0), Vec3(0, 0.2, 0));
    const double A = 0.04, K = 2 / M_PI * 1e6 * std::sqrt(M_PI * std::sqrt(A / M_PI));
    const auto sifs = estimate::estimate_sifs(*c.sol, c.sheet, {});
    ASSERT_EQ(sifs.size(), 12u);
    for (const auto& s : sifs) {
        EXPECT_NEAR(s.KI / K, 1, 1e-3);
        EXPECT_NEAR(s.KII / K, 0, 1e-3);
        // Eq. (5.4) takes K_III from sqrt(|cos alpha|): a direction error eps of the evaluated stress
        // (about 1e-6 here) becomes K_III ~ sqrt(eps) K.
        EXPECT_NEAR(s.KIII / K, 0, 5e-3);
        EXPECT_NEAR(s.e2.dot(Vec3(0, 0, 1)), 1, 1e-12);  // the frame of displacement correlation
        EXPECT_LT(s.v0, s.v1);
    }
}

// Same results with one thread and with two (the stress evaluation runs in parallel).
TEST(SifEstimator, SameResultForAnyThreadCount) {
    const UniaxialCube c(Vec3(-0.1, -0.1, 0.01), Vec3(0.2, 0, 0.05), Vec3(0, 0.2, 0));
    std::vector<bem::FrontEdgeSif> one, two;
    {
        tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
        one = estimate::estimate_sifs(*c.sol, c.sheet, {});
    }
    {
        tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
        two = estimate::estimate_sifs(*c.sol, c.sheet, {});
    }
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
        EXPECT_EQ(one[i].KI, two[i].KI);
        EXPECT_EQ(one[i].KII, two[i].KII);
        EXPECT_EQ(one[i].KIII, two[i].KIII);
    }
}

TEST(SifEstimator, ZeroAreaCrackAndNoCrackAreErrors) {
    const UniaxialCube c(Vec3(-0.1, -0.1, 0.01), Vec3(0.2, 0, 0), Vec3(0, 0.2, 0));
    SurfaceMesh flat = c.sheet;
    for (Vec3& v : flat.vertices) v.y() = 0.0;  // every triangle collapses onto a line
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { estimate::estimate_sifs(*c.sol, flat, {}); },
        {"zero area", "'crack'"}));
    EXPECT_THROW(estimate::estimate_sifs(*c.sol, SurfaceMesh{}, {}), std::invalid_argument);
}
