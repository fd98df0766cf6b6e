// Mass properties, contact duration and balanced tractions against closed forms.
#include "nodes/rigid/balanced_tractions.hpp"
#include "nodes/rigid/contact_duration.hpp"
#include "nodes/rigid/fragment_motion.hpp"
#include "nodes/rigid/mass_properties.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace cf;
using rigid::Mat3;

TEST(MassProperties, BoxMatchesTheClosedForm) {
    BoxSpec b;
    b.size = Vec3(0.4, 0.2, 0.1);
    b.centre = Vec3(3, -2, 5);
    b.subdivisions = 3;
    const auto mp = rigid::mass_properties(make_box(b), 2500);
    const double m = 2500 * 0.4 * 0.2 * 0.1;
    EXPECT_NEAR(mp.volume, 0.008, 1e-15);
    EXPECT_NEAR(mp.mass, m, 1e-12);
    EXPECT_NEAR((mp.centre - b.centre).norm(), 0, 1e-13);
    const Mat3 I = Vec3(m * (0.04 + 0.01) / 12, m * (0.16 + 0.01) / 12, m * (0.16 + 0.04) / 12).asDiagonal();
    EXPECT_LT((mp.inertia - I).norm(), 1e-12 * I.norm());
    EXPECT_NEAR(mp.principal_moments[0], I(0, 0), 1e-12);  // smallest: about the long x axis
    EXPECT_NEAR(std::abs(mp.principal_axes.col(0).x()), 1, 1e-12);
    EXPECT_NEAR(mp.principal_axes.determinant(), 1, 1e-12);
}

// A rotated box: the inertia tensor rotates as R I R^T (independent of where the body sits).
TEST(MassProperties, RotatedBoxInertiaRotates) {
    BoxSpec b;
    b.size = Vec3(0.4, 0.2, 0.1);
    SurfaceMesh box = make_box(b);
    const auto ref = rigid::mass_properties(box, 1000);
    const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()).toRotationMatrix();
    for (Vec3& v : box.vertices) v = R * v + Vec3(10, 20, -5);
    const auto mp = rigid::mass_properties(box, 1000);
    EXPECT_LT((mp.inertia - R * ref.inertia * R.transpose()).norm(), 1e-11 * ref.inertia.norm());
    EXPECT_NEAR((mp.centre - Vec3(10, 20, -5)).norm(), 0, 1e-12);
}

// Regular tetrahedron of edge L: I = m L^2 / 20 about every axis through the centre.
TEST(MassProperties, RegularTetrahedron) {
    const double L = 0.3;
    SurfaceMesh t;
    t.vertices = {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)};
    for (Vec3& v : t.vertices) v *= L / (2 * std::sqrt(2.0));  // edge 2 sqrt(2) scaled to L
    t.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    const auto mp = rigid::mass_properties(t, 1200);
    const double V = L * L * L / (6 * std::sqrt(2.0)), m = 1200 * V;
    EXPECT_NEAR(mp.volume, V, 1e-15);
    EXPECT_LT((mp.inertia - m * L * L / 20 * Mat3::Identity()).norm(), 1e-12 * m * L * L);
}

TEST(MassProperties, InwardMeshAndBadDensityAreErrors) {
    SurfaceMesh box = make_box({});
    EXPECT_THROW(rigid::mass_properties(box, 0), std::invalid_argument);
    for (Tri& t : box.triangles) std::swap(t[1], t[2]);
    EXPECT_THROW(rigid::mass_properties(box, 1000), std::invalid_argument);
}

// t_c scales as v^(-1/5) and m^(2/5); the effective quantities combine both bodies.
TEST(ContactDuration, ScalingLawsAndEffectiveQuantities) {
    const rigid::ContactBody a{3.1e9, 0.327, 0.6, 20}, b{2.5e10, 0.2, 1.8, 10};
    const auto d1 = rigid::hertz_contact_duration(a, b, 1.0), d32 = rigid::hertz_contact_duration(a, b, 32.0);
    EXPECT_NEAR(d1.seconds / d32.seconds, 2.0, 1e-12);  // 32^(1/5)
    EXPECT_NEAR(d1.m, 0.6 * 1.8 / 2.4, 1e-15);
    EXPECT_NEAR(d1.R, 1.0 / 30, 1e-15);
    EXPECT_DOUBLE_EQ(d1.seconds, rigid::hertz_contact_duration(b, a, 1.0).seconds);
    EXPECT_THROW(rigid::hertz_contact_duration({3e9, 0.3, 0, 0}, {3e9, 0.3, 0, 0}, 1.0), std::invalid_argument);
    EXPECT_THROW(rigid::hertz_contact_duration({-1, 0.3, 1, 0}, a, 1.0), std::invalid_argument);
}

// Mean curvature: 1/R on a sphere, 0 inside a flat face.
TEST(ContactDuration, MeanCurvatureOfSphereAndPlane) {
    SphereSpec s;
    s.radius = 0.2;
    s.level = 4;
    const auto H = rigid::vertex_mean_curvature(make_icosphere(s));
    for (double h : H) EXPECT_NEAR(h * 0.2, 1, 0.02);
    BoxSpec b;
    b.subdivisions = 4;
    const SurfaceMesh box = make_box(b);
    const auto Hb = rigid::vertex_mean_curvature(box);
    for (std::size_t v = 0; v < box.num_vertices(); ++v) {
        const Vec3 p = box.vertices[v];
        const int on_faces = (std::abs(std::abs(p.x()) - 0.5) < 1e-12) + (std::abs(std::abs(p.y()) - 0.5) < 1e-12) +
                             (std::abs(std::abs(p.z()) - 0.5) < 1e-12);
        if (on_faces == 1) EXPECT_NEAR(Hb[v], 0, 1e-9);  // inside a face
    }
}

// A field without net force and torque is its own projection.
TEST(BalancedTractions, BalancedInputIsUnchanged) {
    BoxSpec b;
    b.subdivisions = 2;
    const SurfaceMesh box = make_box(b);
    std::vector<Vec3> q(box.num_triangles());
    for (std::size_t t = 0; t < q.size(); ++t) {  // uniform pressure: balanced on a closed surface
        const Tri& tr = box.triangles[t];
        q[t] = -1e5 * (box.vertices[tr[1]] - box.vertices[tr[0]]).cross(box.vertices[tr[2]] - box.vertices[tr[0]]).normalized();
    }
    const auto out = rigid::balance_tractions(box, q);
    for (std::size_t t = 0; t < q.size(); ++t) EXPECT_LT((out.traction[t] - q[t]).norm(), 1e-9);
    EXPECT_LT(out.removed_force.norm(), 1e-8);
    EXPECT_THROW(rigid::balance_tractions(box, std::vector<Vec3>(3)), std::invalid_argument);
}

// A spinning, translating box cut into three slabs: the slabs' motions from fragment_motion carry
// the parent's linear and angular momentum exactly (the slabs partition the box).
TEST(FragmentMotion, FragmentsCarryTheParentsMomentum) {
    const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(0.3, -1, 0.5).normalized()).toRotationMatrix();
    const Vec3 shift(4, -1, 2);
    auto place = [&](SurfaceMesh m) {
        for (Vec3& v : m.vertices) v = R * v + shift;
        return m;
    };
    BoxSpec whole;
    whole.size = Vec3(0.6, 0.2, 0.1);
    const auto parent = rigid::mass_properties(place(make_box(whole)), 2000);
    rigid::RigidMotion pm;
    pm.centre = parent.centre;
    pm.velocity = Vec3(1, 2, -3);
    pm.angular_velocity = Vec3(4, -2, 7);
    std::vector<rigid::MassProperties> parts;
    std::vector<rigid::RigidMotion> motion;
    for (double x0 : {-0.3, -0.1, 0.2}) {  // slabs [-0.3, -0.1], [-0.1, 0.2], [0.2, 0.3]
        const double x1 = x0 == -0.3 ? -0.1 : (x0 == -0.1 ? 0.2 : 0.3);
        BoxSpec s;
        s.size = Vec3(x1 - x0, 0.2, 0.1);
        s.centre = Vec3(0.5 * (x0 + x1), 0, 0);
        parts.push_back(rigid::mass_properties(place(make_box(s)), 2000));
        motion.push_back(rigid::fragment_motion(pm, parts.back().centre));
    }
    Vec3 L, H, L0, H0;
    rigid::total_momentum(parts, motion, Vec3::Zero(), L, H);
    rigid::total_momentum({parent}, {pm}, Vec3::Zero(), L0, H0);
    EXPECT_LT((L - L0).norm(), 1e-12 * L0.norm());
    EXPECT_LT((H - H0).norm(), 1e-12 * H0.norm());
}
