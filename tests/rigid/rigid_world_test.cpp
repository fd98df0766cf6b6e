// The Bullet world: contact with the ground, impulses, determinism, bad input.
#include "nodes/rigid/rigid_world.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"
#include "graph/cancel_token.hpp"
#include "tests/harness/expect_error.hpp"

#include <atomic>

#include <gtest/gtest.h>

using namespace cf;

namespace {
rigid::BodySpec dropped_box(double height) {
    rigid::BodySpec b;
    b.name = "box";
    BoxSpec s;
    s.size = Vec3(0.2, 0.2, 0.2);
    s.centre = Vec3(0, 0, height);
    s.subdivisions = 1;
    b.mesh = make_box(s);
    b.density = 1000;
    return b;
}
}  // namespace

// A box dropped on the ground comes to rest on it; at rest the ground's normal impulses per step
// carry its weight (m g dt).
TEST(RigidWorld, BoxComesToRestAndContactsCarryItsWeight) {
    rigid::RigidWorld w({});
    w.add_ground_plane(Vec3(0, 0, 1), 0);
    const int id = w.add_body(dropped_box(0.5));
    for (int k = 0; k < 1000; ++k) w.step();
    const auto s = w.state(id);
    EXPECT_NEAR(s.position.z(), 0.1, 5e-3);  // resting on its face (Bullet's collision margin ~ mm)
    EXPECT_LT(s.velocity.norm(), 1e-3);
    double J = 0;
    for (const auto& c : w.contacts()) {
        EXPECT_TRUE(c.body_a == id || c.body_b == id);
        J += c.impulse;
    }
    const double m = w.mass_properties_of(id).mass;
    EXPECT_NEAR(J, m * 9.81 / 250, 0.05 * m * 9.81 / 250);
}

TEST(RigidWorld, SameSceneSameStates) {
    auto run = [] {
        rigid::RigidWorld w({});
        w.add_ground_plane(Vec3(0, 0, 1), 0);
        auto a = dropped_box(0.5), b = dropped_box(0.9);
        b.velocity = Vec3(0.1, 0, 0);
        b.angular_velocity = Vec3(0, 3, 1);
        w.add_body(a);
        w.add_body(b);
        for (int k = 0; k < 400; ++k) w.step();
        return std::make_pair(w.state(0), w.state(1));
    };
    const auto r1 = run(), r2 = run();
    EXPECT_EQ(r1.first.position, r2.first.position);
    EXPECT_EQ(r1.second.position, r2.second.position);
    EXPECT_EQ(r1.second.rotation.coeffs(), r2.second.rotation.coeffs());
}

TEST(RigidWorld, BadBodiesAreNamed) {
    rigid::RigidWorld w({});
    auto b = dropped_box(1);
    b.name = "brick_3";
    b.density = -5;
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { w.add_body(b); }, {"brick_3", "density"}));
    rigid::WorldSettings zero;
    zero.time_step = 0;
    EXPECT_THROW(rigid::RigidWorld{zero}, std::invalid_argument);
}

// A hull body keeps only the vertices of its convex hull (GJK visits every point in every query):
// a box whose faces carry a 16 x 16 grid of vertices each comes to rest as the 8-corner box does.
// (Lateral motion is not compared: which four points Bullet keeps for a face-on-face contact depends
// on the order of the hull's points, and a sliding box yaws with them.)
TEST(RigidWorld, DenseHullCollidesAsItsCorners) {
    auto run = [](int subdivisions) {
        rigid::RigidWorld w({});
        w.add_ground_plane(Vec3(0, 0, 1), 0);
        auto b = dropped_box(0.5);
        BoxSpec s;
        s.size = Vec3(0.2, 0.3, 0.4);  // distinct principal moments: the same body frame for both
        s.centre = Vec3(0, 0, 0.5);
        s.subdivisions = subdivisions;
        b.mesh = make_box(s);
        const int id = w.add_body(b);
        for (int k = 0; k < 300; ++k) w.step();
        return w.state(id);
    };
    const auto coarse = run(1), dense = run(16);
    EXPECT_NEAR(dense.position.z(), coarse.position.z(), 1e-6);
    EXPECT_NEAR(dense.position.z(), 0.2, 5e-3);  // on its 0.2 x 0.3 face (Bullet's margin ~ mm)
    // Upright: the box's long axis (its body frame's smallest moment, 0.4 m) stays vertical.
    for (const auto& s : {coarse, dense}) EXPECT_NEAR(std::abs((s.rotation * Vec3::UnitX()).z()), 1.0, 1e-6);
}

// A hull of more points than the bound keeps one support vertex per direction of an even spread
// (every direction within 13.5 degrees of one): an inner hull within 1 - cos(13.5 deg) = 2.8 % of the
// radius. A 2562-vertex sphere of radius 0.1 m comes to rest with its centre at r (1 - 0.028) .. r
// plus Bullet's margin (1 % of 0.2 m).
TEST(RigidWorld, ReducedHullOfARoundPieceStaysWithinItsBound) {
    rigid::RigidWorld w({});
    w.add_ground_plane(Vec3(0, 0, 1), 0);
    rigid::BodySpec b;
    b.name = "ball";
    SphereSpec s;
    s.radius = 0.1;
    s.centre = Vec3(0, 0, 0.3);
    s.level = 4;
    b.mesh = make_icosphere(s);
    ASSERT_EQ(b.mesh.vertices.size(), 2562u);
    const int id = w.add_body(b);
    for (int k = 0; k < 500; ++k) w.step();
    const double z = w.state(id).position.z();
    EXPECT_GT(z, 0.1 * (1 - 0.028) - 1e-4);
    EXPECT_LT(z, 0.1 + 0.002 + 1e-4);
}

// Ctrl-C inside a rigid step: the step skips its remaining narrow phase and throws Cancelled, so a
// heap of fragments cannot hold a cancelled run for seconds; without a request it steps normally.
TEST(RigidWorld, ACancelledStepThrowsCancelled) {
    rigid::RigidWorld w({});
    w.add_ground_plane(Vec3(0, 0, 1), 0);
    const int id = w.add_body(dropped_box(0.5));
    std::atomic<bool> flag{false};
    const CancelScope scope{CancelToken(&flag)};
    w.step();
    const double z = w.state(id).position.z();
    EXPECT_LT(z, 0.5);
    flag = true;
    EXPECT_THROW(w.step(), Cancelled);
    EXPECT_EQ(w.state(id).position.z(), z) << "a cancelled step does not advance";
}
