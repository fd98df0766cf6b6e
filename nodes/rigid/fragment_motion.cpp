#include "nodes/rigid/fragment_motion.hpp"

#include <stdexcept>

namespace cf::rigid {

RigidMotion fragment_motion(const RigidMotion& parent, const Vec3& c) {
    RigidMotion m;
    m.centre = c;
    m.velocity = parent.velocity + parent.angular_velocity.cross(c - parent.centre);
    m.angular_velocity = parent.angular_velocity;
    return m;
}

void total_momentum(const std::vector<MassProperties>& bodies, const std::vector<RigidMotion>& motion, const Vec3& origin,
                    Vec3& linear, Vec3& angular) {
    if (bodies.size() != motion.size()) throw std::invalid_argument("total_momentum: one motion per body");
    linear.setZero();
    angular.setZero();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Vec3 p = bodies[i].mass * motion[i].velocity;
        linear += p;
        angular += (motion[i].centre - origin).cross(p) + bodies[i].inertia * motion[i].angular_velocity;
    }
}

}  // namespace cf::rigid
