#pragma once
// Crack-front motion laws of thesis ch. 4.5 for one point of the front.
//
// Frame and sign conventions (thesis fig. 6): n1 = crack-surface normal, n2 = crack-front normal
// pointing forward in the crack plane, n3 = crack-front tangent, right-handed (n1 x n2 = n3).
// A propagation angle theta rotates about n3: the direction is sin(theta) n1 + cos(theta) n2, so
// theta > 0 turns towards +n1. With K_II > 0 the kink angle is negative (eq. 2.36/4.10).
// SIFs in Pa*sqrt(m); angles in radians; speeds in m/s.
// (The BEM's displacement correlation names the same frame e1 = n2, e2 = n1, e3 = n3.)
#include "nodes/domain/surface_mesh.hpp"

namespace cf::propagate {

struct Sifs {
    double KI = 0, KII = 0, KIII = 0;
};

// Rotated (local) SIFs for a kink by theta, eq. (2.35).
struct LocalSifs {
    double Ktheta = 0, Kr = 0, K3 = 0;
};
LocalSifs local_sifs(const Sifs& K, double theta);

// Energy release rate for a kink by theta, eq. (4.9) [J/m^2]: ((Kt^2 + Kr^2)(1 - nu^2) + K3^2 (1 + nu)) / E.
double energy_release_rate(const Sifs& K, double theta, double E, double nu);

// Overall effective SIF, eq. (4.7): K_eff^2 = K_I^2 + K_II^2 + K_III^2 / (1 - nu).
double effective_sif(const Sifs& K, double nu);
// Effective mode-I-III SIF (ch. 4.5.1): K_I,III^2 = K_I^2 + K_III^2 / (1 - nu); always >= 0.
double mode_i_iii_sif(const Sifs& K, double nu);

// Kink angle maximising the energy release rate for mode I-II loading, eq. (2.36) with the
// root of eq. (4.10): theta* = 2 atan((K - sqrt(K^2 + 8 K_II^2)) / (4 K_II)), 0 when K_II = 0.
// Evaluated as 2 atan(-2 K_II / (K + sqrt(K^2 + 8 K_II^2))) (same value, no cancellation).
// K >= 0 is the (mode-I or mode-I-III) opening SIF. Pure mode II: -70.53 deg (K_II > 0);
// K = K_II: -53.13 deg; pure mode I: 0.
double kink_angle(double K, double KII);

// Extremes of K_theta(theta) over theta in [-pi, pi] (eq. 2.35): at the two stationary points
// of eq. (2.36) and at +-pi, where K_theta = 0.
struct KthetaRange {
    double max = 0, min = 0;
};
KthetaRange ktheta_range(double KI, double KII);

// Compressive rule (ch. 4.5.1): the front propagates under compression when
// max K_theta < -min K_theta / f_c; then every SIF is replaced by -K_i / f_c and the tensile
// formulas apply unchanged.
bool is_compressive(const Sifs& K, double compressive_factor);
struct TipLoading {
    Sifs K;                   // after the compressive rule
    bool compressive = false;
};
TipLoading apply_compressive_rule(const Sifs& K, double compressive_factor);

// Rayleigh wave speed c_R = 0.9 sqrt(mu / rho) (ch. 2.4) [m/s].
double rayleigh_speed(double mu, double rho);
// Propagation speed, eq. (4.8): c_R (1 - K_c^2 / K_eff^2) if K_eff > K_c, else 0.
double propagation_speed(double K_eff, double K_c, double c_R);
// Sub-step duration with c_R dt_s = r_f (ch. 4.5.2) [s].
double substep_duration(double r_f, double c_R);

// Valid directions (ch. 4.5.3, eq. 4.13): the interval around theta* where
// K_theta = K_I,III cos^3(theta/2) - 3 K_II cos^2(theta/2) sin(theta/2) > K_c, within +-90
// degrees: otherwise (K > 3.8 K_c in pure mode I, less in mixed mode) a toughness gradient could
// steer a front backwards through its own faces. Empty when K_theta(theta*) <= K_c (then lo = hi = theta*).
struct AngleInterval {
    double lo = 0, hi = 0;
    bool empty = true;
};
AngleInterval valid_interval(double K_I_III, double KII, double K_c);

// Direction blending over a time step, eq. (4.12): w_t theta_new + (1 - w_t) theta_old.
double blend_angle(double theta_old, double theta_new, double w_t);
// w_t for sub-step k = 0..n-1: 0 in the first sub-step after a BEM update, 1 in the last
// (1 when n == 1).
double blend_weight(int k, int n);

// Toughness gradient projected into the (n1, n2) plane, in polar form (ch. 4.5.3): theta_grad
// points along the steepest toughness DECREASE, measured like every theta here
// (atan2(-grad.n1, -grad.n2)); r_grad is the projected magnitude [Pa*sqrt(m)/m]. (The thesis
// writes tan^-1[(grad.n2)/(grad.n1)]; with its own convention sin(theta) n1 + cos(theta) n2 the
// consistent form has the n1 component in the numerator.)
struct GradientDirection {
    double theta = 0, r = 0;
};
GradientDirection gradient_direction(const Vec3& grad_Kc, const Vec3& n1, const Vec3& n2);

// Final direction in an inhomogeneous material, eq. (4.14): the valid direction closest to
// theta_grad, blended with the smoothed optimum by w = 1 / (1 + r_grad r_c / K_c).
// With an empty interval or K_c <= 0 the optimum is returned unchanged.
double steered_angle(double theta_opt, const AngleInterval& valid, const GradientDirection& g, double r_c, double K_c);

// valid_interval with each end's bisection (~10 evaluations of K_theta after the bracket) left
// until the end is asked for; until then bounds certified around it are known. Eq. (4.14) clamps
// the gradient's direction to the interval and so needs at most one end, and none where the
// direction lies clearly inside: steered_blended_angle asks only for those.
class LazyAngleInterval {
public:
    LazyAngleInterval() = default;  // empty
    LazyAngleInterval(double K_I_III, double KII, double K_c);
    bool empty() const { return empty_; }
    // End i (0: lo, 1: hi) lies in [lower(i), upper(i)]; end(i) is valid_interval's, to the bit.
    double lower(int i) const { return ends_[i].lower; }
    double upper(int i) const { return ends_[i].upper; }
    double end(int i);

private:
    struct End {
        bool known = true;
        double value = 0, lower = 0, upper = 0;
        double inside = 0, outside = 0, a = 0, b = 0;  // the bisection still to run
    };
    double KI_ = 0, KII_ = 0, Kc_ = 0;
    bool empty_ = true;
    End ends_[2];
};

// steered_angle of eq. (4.14) over eq. (4.12)'s blended valid interval, the same double as
// computing both intervals in full: the interval is cur's when old is empty, else
// blend_angle(old end (+ turn when `turned`), cur end, w_t) per end. `old` may be `cur` itself
// (no old interval: the current one stands in for it, as marker_substep does).
double steered_blended_angle(double theta_opt, LazyAngleInterval& cur, LazyAngleInterval& old, bool turned, double turn,
                             double w_t, const GradientDirection& g, double r_c, double K_c);

// Velocity of a front point, eq. (4.11): v (sin(theta) n1 + cos(theta) n2).
Vec3 front_velocity(double speed, double theta, const Vec3& n1, const Vec3& n2);

}  // namespace cf::propagate
