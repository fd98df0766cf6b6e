#pragma once
// Initial motion of the fragments of a broken body (thesis ch. 7.3): every fragment moves as the
// parent did before the collision, so a fragment whose centre of mass is at c (world) gets the
// parent's velocity at that point, v + omega x (c - p) with p the parent's centre of mass, and the
// parent's angular velocity. (The reference implementation evaluated the lever arm in body axes
// against a world-frame omega, which is wrong for a rotated parent.) When the fragments partition
// the parent, their total linear and angular momentum equal the parent's. SI units.
#include "nodes/rigid/mass_properties.hpp"

#include <vector>

namespace cf::rigid {

struct RigidMotion {
    Vec3 centre = Vec3::Zero();            // centre of mass [m]
    Vec3 velocity = Vec3::Zero();          // [m/s]
    Vec3 angular_velocity = Vec3::Zero();  // [rad/s], world axes
};

RigidMotion fragment_motion(const RigidMotion& parent, const Vec3& fragment_centre);

// Linear momentum [kg m/s] and angular momentum about `origin` [kg m^2/s] of bodies with the given
// mass properties (inertia about their centres, world axes) and motions.
void total_momentum(const std::vector<MassProperties>& bodies, const std::vector<RigidMotion>& motion, const Vec3& origin,
                    Vec3& linear, Vec3& angular);

}  // namespace cf::rigid
