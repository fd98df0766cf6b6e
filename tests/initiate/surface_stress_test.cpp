// Surface stress eq. (4.4)-(4.6) against exact linear-elastic fields.
#include "nodes/initiate/initiate_verification.hpp"
#include "nodes/initiate/surface_stress.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

namespace cf::initiate {
namespace {

// Exact 3D stress of the homogeneous strain eps: sigma = lambda tr(eps) I + 2 mu eps.
Mat3 hooke(const Mat3& eps, double E, double nu) {
    const double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    return lam * eps.trace() * Mat3::Identity() + 2 * mu * eps;
}

TEST(SurfaceStress, UniaxialCubeSidesAndEnds) {
    // Verification case 4, and its convergence: the field is linear, so the error is the
    // geometric nonlinearity of the co-rotated frame only, O(strain) ~ 3e-4, on any mesh.
    for (int m : {1, 2, 4, 8}) {
        EXPECT_LT(uniaxial_surface_stress_error(m, 0.1, 1e6, 3.1e9, 0.327, true), 1e-3) << m;
        EXPECT_LT(uniaxial_surface_stress_error(m, 0.1, 1e6, 3.1e9, 0.327, false), 1e-3) << m;
    }
}

TEST(SurfaceStress, AnyHomogeneousStrainOnAnyTriangle) {
    // For a general small strain the surface stress must equal the exact 3D stress whenever
    // the traction is consistent (q = sigma n) and the stress is plane on the triangle
    // (sigma n = q carries all out-of-plane parts) -- true for arbitrary eps only if the
    // in-plane stress obeys plane stress with the out-of-plane normal traction: we build eps
    // from a stress with sigma_nn != 0 and check reproduction.
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    const double E = 2e9, nu = 0.3;
    for (int n = 0; n < 50; ++n) {
        Mat3 s;
        s << u(rng), u(rng), u(rng), 0, u(rng), u(rng), 0, 0, u(rng);
        s = 1e6 * (s + s.transpose()).eval();
        // Strain of that stress: eps = ((1+nu) s - nu tr(s) I) / E.
        const Mat3 eps = ((1 + nu) * s - nu * s.trace() * Mat3::Identity()) / E;
        ASSERT_LT((hooke(eps, E, nu) - s).norm(), 1e-6 * s.norm());
        const Vec3 a(u(rng), u(rng), u(rng)), b = a + Vec3(u(rng), u(rng), u(rng)), c = a + Vec3(u(rng), u(rng), u(rng));
        const Vec3 nrm = (b - a).cross(c - a).normalized();
        const std::array<Vec3, 3> x = {a, b, c};
        const std::array<Vec3, 3> disp = {eps * a, eps * b, eps * c};
        const Mat3 got = surface_stress(x, disp, s * nrm, E, nu);
        EXPECT_LT((got - got.transpose()).norm(), 1e-9 * s.norm());
        EXPECT_LT((got * nrm - s * nrm).norm(), 1e-9 * s.norm());
        // Strains ~1e-3: the co-rotated frame is first-order accurate.
        EXPECT_LT((got - s).norm(), 2e-2 * s.norm()) << "sample " << n;
    }
}

TEST(SurfaceStress, RigidRotationGivesNoStress) {
    const std::array<Vec3, 3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.3, 0.8, 0)};
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    const Vec3 t(0.1, -0.2, 0.3);
    const std::array<Vec3, 3> u = {R * x[0] + t - x[0], R * x[1] + t - x[1], R * x[2] + t - x[2]};
    EXPECT_LT(surface_stress(x, u, Vec3::Zero(), 1e9, 0.3).norm(), 1e-3);  // Pa, against E = 1e9
}

TEST(SurfaceStress, DegenerateTriangleIsAnError) {
    const std::array<Vec3, 3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
    EXPECT_THROW(surface_stress(x, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, Vec3::Zero(), 1e9, 0.3), std::invalid_argument);
}

TEST(PrincipalStress, SignedAscending) {
    Mat3 s = Mat3::Zero();
    s(0, 0) = 3;
    s(1, 1) = -5;
    s(2, 2) = 1;
    const PrincipalStress p = principal_stresses(s);
    EXPECT_NEAR(p.min(), -5, 1e-12);
    EXPECT_NEAR(p.values[1], 1, 1e-12);
    EXPECT_NEAR(p.max(), 3, 1e-12);
    EXPECT_NEAR(std::abs(p.max_direction().x()), 1, 1e-12);
    EXPECT_NEAR(std::abs(p.min_direction().y()), 1, 1e-12);
}

}  // namespace
}  // namespace cf::initiate
