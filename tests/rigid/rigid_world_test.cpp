// The Bullet world: contact with the ground, impulses, determinism, bad input.
#include "nodes/rigid/rigid_world.hpp"
#include "nodes/shape/box.hpp"
#include "tests/harness/expect_error.hpp"

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
