#pragma once
// From the contacts of one rigid-body step to the loads of a breakable body's fracture run
// (thesis ch. 7.2): every contact point, mapped into the body's material frame, adds the traction
// J n / (t_c A_e) to its closest BEM element e, with J the normal impulse of the step, n the
// direction the impulse pushes the body (into it), A_e the element's area and t_c the Hertzian
// contact duration of the two bodies at that point. A run starts when the summed impulse or the
// summed contact force sum J / t_c reaches the body's thresholds.
//
// One deviation from the thesis, for resting contacts: when t_c exceeds the rigid step dt, the
// step's impulse was delivered over dt, not t_c (a bar lying on supports receives m g dt each
// step); the duration used is min(t_c, dt), so the contact force of a resting body is its weight
// share rather than a fraction of it. SI units: N s, N, Pa, s, m.
#include "nodes/domain/material.hpp"
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/rigid/contact_duration.hpp"

#include <vector>

namespace cf::rigid {

struct BodyContact {
    Vec3 point = Vec3::Zero();      // contact point on the body, material frame [m]
    Vec3 direction = Vec3::Zero();  // unit direction of the impulse on the body, material frame
    double impulse = 0;             // normal impulse of the step [N s]
    double approach_speed = 0;      // relative normal speed before the step [m/s]
    ContactBody partner;            // the other body (mass 0: static, kinematic or the ground)
};

struct ImpactLoads {
    std::vector<Vec3> traction;     // per BEM element [Pa], before balancing
    double impulse = 0;             // sum of J [N s]
    double force = 0;               // sum of J / duration [N]
    double contact_duration = 0;    // largest duration used [s] (bounds the fracture time)
    double shortest_duration = 0;   // smallest [s]
    int contacts = 0;
};

// `curvature`: |H| per BEM triangle [1/m] (triangle_mean_curvature). `body`: the body's E, nu and
// mass (mean_curvature is taken per contact from `curvature`). Throws std::invalid_argument for
// sizes that do not match or a contact that is not finite.
ImpactLoads impact_loads(const SurfaceMesh& bem_mesh, const std::vector<double>& curvature, const ContactBody& body,
                         const std::vector<BodyContact>& contacts, double rigid_step,
                         const ContactDurationLimits& limits = {});

// Index of the triangle of `mesh` closest to p (brute force; BEM meshes are coarse).
int closest_triangle(const SurfaceMesh& mesh, const Vec3& p);

}  // namespace cf::rigid
