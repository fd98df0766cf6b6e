#include "nodes/propagate/marker_motion.hpp"

#include <cmath>

namespace cf::propagate {

namespace {

struct Direction {
    double theta = 0;
    LazyAngleInterval valid;
};

// theta* of eq. (4.10) and, only where a toughness gradient will steer (`with_interval`), the
// valid interval of eq. (4.13), its ends bisected only if eq. (4.14) needs them (in a homogeneous
// material steered_angle never reads it).
Direction optimal_direction(const Sifs& raw, double fc, double nu, double Kc, bool with_interval) {
    const TipLoading t = apply_compressive_rule(raw, fc);
    const double K13 = mode_i_iii_sif(t.K, nu);
    Direction d;
    d.theta = kink_angle(K13, t.K.KII);
    if (with_interval) d.valid = LazyAngleInterval(K13, t.K.KII, Kc);
    return d;
}

}  // namespace

MarkerStep marker_substep(const MarkerState& m, const ScalarField& toughness, const PropagationSettings& s, double w_t,
                          bool planar) {
    MarkerStep out;
    if (!m.active) return out;
    const double fc = toughness.compressive_factor;
    const double Kc = toughness.value(m.position);
    const TipLoading now = apply_compressive_rule(m.K, fc);
    out.compressive = now.compressive;
    const double cR = rayleigh_speed(s.mu(), s.rho);
    out.speed = propagation_speed(effective_sif(now.K, s.nu), Kc, cR);  // eq. (4.7)-(4.8)
    if (out.speed == 0) return out;
    if (!planar) {
        const GradientDirection g = gradient_direction(toughness.gradient(m.position), m.n1, m.n2);
        const bool steer = g.r > 0;
        Direction cur = optimal_direction(m.K, fc, s.nu, Kc, steer);
        // theta_old = 0 for a new crack; its interval is unknown, so the current one stands in.
        Direction old;
        LazyAngleInterval* old_valid = &cur.valid;
        bool turned = false;
        double turn = 0;
        if (m.has_old) {
            old = optimal_direction(m.K_old, fc, s.nu, Kc, steer);
            old_valid = &old.valid;
            if (m.last_direction.squaredNorm() > 0) {
                // The last direction in today's frame; the old valid interval turns with it.
                const double theta_last = std::atan2(m.last_direction.dot(m.n1), m.last_direction.dot(m.n2));
                turn = theta_last - m.last_theta;
                old.theta = theta_last;
                turned = !old.valid.empty();
            }
        }
        const double theta_opt = blend_angle(old.theta, cur.theta, w_t);  // eq. (4.12)
        out.theta = steered_blended_angle(theta_opt, cur.valid, *old_valid, turned, turn, w_t, g, s.r_c, Kc);  // eq. (4.14)
    }
    const double dt = substep_duration(s.r_f, cR);
    out.displacement = dt * front_velocity(out.speed, out.theta, m.n1, m.n2);  // eq. (4.11), forward Euler
    return out;
}

}  // namespace cf::propagate
