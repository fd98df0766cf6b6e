#pragma once
// A deterministic Bullet 3.24 (double precision) rigid-body world for the scenes of thesis ch. 7:
// single-threaded, one fixed step per call (stepSimulation(dt, 0, dt)), bodies inserted in the
// order they are added, no randomised solver order, deterministic overlapping pairs, the world
// transform read directly (never the interpolated motion state). Bullet stays inside
// rigid_world.cpp; this header shows only crackflow types. SI units: m, s, kg.
#include "nodes/rigid/mass_properties.hpp"

#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cf::rigid {

struct WorldSettings {
    Vec3 gravity = Vec3(0, 0, -9.81);  // [m/s^2]
    double time_step = 1.0 / 250;      // [s] one rigid-body step
    int solver_iterations = 20;
};

enum class BodyKind { dynamic, kinematic, fixed };
// Collision shape: the convex hull of the mesh, or the (non-convex) triangle mesh itself (Bullet's
// GImpact, thesis ch. 7.3 class (b) and (c) fragments, tori, bowls).
enum class CollisionShape { hull, mesh };

struct BodySpec {
    std::string name;
    BodyKind kind = BodyKind::dynamic;
    SurfaceMesh mesh;                  // closed surface in world coordinates at the start (convex hull collides)
    double density = 1000;             // [kg/m^3] (dynamic bodies)
    Vec3 velocity = Vec3::Zero();      // of the centre of mass [m/s]
    Vec3 angular_velocity = Vec3::Zero();  // [rad/s], world axes
    double friction = 0.5;
    double restitution = 0.0;
    // Bullet keeps convex shapes this far apart (it adds the margin outside the hull); 0: 1 % of the
    // body's smallest bounding-box extent (Bullet's default 0.04 m would float a 10 cm brick 4 cm high).
    double collision_margin = 0;  // [m]
    CollisionShape collision = CollisionShape::hull;
    SurfaceMesh collision_mesh;   // world coordinates; empty: `mesh` (for CollisionShape::mesh)
    // Given mass properties (world axes, as mass_properties() returns) instead of those of `mesh`:
    // a fragment's mass comes from its level-set volume, its centre and inertia from its mesh.
    std::optional<MassProperties> mass;
};

// A body's pose: world position of its centre of mass and the rotation from body axes (the
// principal axes of inertia at the start) to world axes; x_world = position + rotation * x_body.
struct BodyState {
    Vec3 position = Vec3::Zero();
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
    Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();
};

struct Contact {
    int body_a = -1, body_b = -1;      // body ids; -1 for the ground plane
    Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  // world points on each body [m]
    Vec3 normal_on_b = Vec3::Zero();   // unit, from b towards a (Bullet's m_normalWorldOnB)
    double distance = 0;               // signed separation [m] (negative: penetration)
    double impulse = 0;                // normal impulse of the step [N s]
};

class RigidWorld {
public:
    explicit RigidWorld(const WorldSettings& settings);
    ~RigidWorld();
    RigidWorld(const RigidWorld&) = delete;
    RigidWorld& operator=(const RigidWorld&) = delete;

    // Adds a body; returns its id (0, 1, ...). The body frame is the centre of mass with the principal
    // axes of inertia. Throws std::invalid_argument naming the body for an open or inward mesh, a
    // non-positive density, or non-finite velocities.
    int add_body(const BodySpec& spec);
    // An infinite static plane n . x = offset (n normalised).
    void add_ground_plane(const Vec3& normal, double offset, double friction = 0.5, double restitution = 0.0);

    // Takes a body out of the world (a broken parent); its id is not reused and state() still
    // returns its last state.
    void remove_body(int id);
    bool active(int id) const;

    // The state of every body (removed ones included), and setting it back: a rigid step that broke
    // a body is repeated from the state before it (ch. 7.3). restore() also drops the contact
    // manifolds, so the repeated step starts as the first did (no warm start from its impulses).
    std::vector<BodyState> snapshot() const;
    void restore(const std::vector<BodyState>& states);

    // Pairs of bodies (ids, -1 for the ground) that overlap deeper than `depth` [m] now (a scene
    // whose bodies start inside one another).
    std::vector<std::pair<int, int>> overlaps(double depth);

    void step();                        // one fixed time step; throws Cancelled when the run is cancelled
    double time() const;                // simulated time [s]
    std::size_t num_bodies() const;
    BodyState state(int id) const;
    const MassProperties& mass_properties_of(int id) const;
    std::vector<Contact> contacts() const;  // of the last step, with positive impulse

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace cf::rigid
