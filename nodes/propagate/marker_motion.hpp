#pragma once
// One forward-Euler sub-step of a crack-front marker (thesis ch. 4.5.1-4.5.3): compressive rule,
// speed eq. (4.8), kink angle eq. (4.10) blended over the time step eq. (4.12), and steering
// towards lower toughness within the valid interval, eq. (4.13)-(4.14).
#include "nodes/fields/scalar_field.hpp"
#include "nodes/propagate/propagation_law.hpp"

namespace cf::propagate {

struct PropagationSettings {
    double E = 3.1e9;               // Young's modulus [Pa]
    double nu = 0.327;              // Poisson's ratio [-]
    double rho = 1200;              // density [kg/m^3]
    double r_c = 0;                 // BEM edge length [m]
    double r_f = 0;                 // marker spacing / level-set voxel size [m]
    double mu() const { return E / (2 * (1 + nu)); }
};

struct MarkerState {
    Vec3 position = Vec3::Zero();
    Vec3 n1 = Vec3::UnitZ(), n2 = Vec3::UnitX();  // surface normal, forward normal (orthonormal)
    Sifs K;                                       // interpolated from the current BEM step
    Sifs K_old;                                   // from the previous BEM step
    bool has_old = false;                         // false right after initiation: theta_old = 0
    // The marker's last propagation direction (unit; zero before its first move) and the angle
    // it was moved at, in the frame of that time. Eq. (4.12) blends from this direction: the
    // frames of the next BEM step already follow the kinked crack, so theta_old is this
    // direction measured in the new frame, not theta*(K_old) (which would kink twice).
    Vec3 last_direction = Vec3::Zero();
    double last_theta = 0;
    bool active = true;                           // false once the marker reached a surface
};

struct MarkerStep {
    Vec3 displacement = Vec3::Zero();  // [m], at most r_f
    double speed = 0;                  // [m/s]
    double theta = 0;                  // direction used [rad], in the marker's frame (n1, n2)
    bool compressive = false;
};

// Displacement of one marker over one sub-step of duration r_f / c_R. `w_t` is the blend weight
// of eq. (4.12) (blend_weight). `planar` forces theta = 0 (first sub-step after initiation).
// Toughness K_c and its gradient are read from `toughness` at the marker; its compressive factor
// is f_c of the compressive rule.
MarkerStep marker_substep(const MarkerState& m, const ScalarField& toughness, const PropagationSettings& s, double w_t,
                          bool planar);

}  // namespace cf::propagate
