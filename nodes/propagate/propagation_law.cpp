#include "nodes/propagate/propagation_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cf::propagate {

namespace {
constexpr double kPi = 3.14159265358979323846;

double ktheta(double KI, double KII, double theta) {  // eq. (2.35), first line
    const double c = std::cos(theta / 2), s = std::sin(theta / 2);
    return KI * c * c * c - 3 * KII * c * c * s;
}
}  // namespace

LocalSifs local_sifs(const Sifs& K, double theta) {
    const double c = std::cos(theta / 2), s = std::sin(theta / 2);
    LocalSifs L;
    L.Ktheta = K.KI * c * c * c - 3 * K.KII * c * c * s;
    L.Kr = K.KI * c * c * s + 3 * K.KII * c * c * c - 2 * K.KII * c;
    L.K3 = K.KIII * c;
    return L;
}

double energy_release_rate(const Sifs& K, double theta, double E, double nu) {
    const LocalSifs L = local_sifs(K, theta);
    return ((L.Ktheta * L.Ktheta + L.Kr * L.Kr) * (1 - nu * nu) + L.K3 * L.K3 * (1 + nu)) / E;
}

double effective_sif(const Sifs& K, double nu) {
    return std::sqrt(K.KI * K.KI + K.KII * K.KII + K.KIII * K.KIII / (1 - nu));
}

double mode_i_iii_sif(const Sifs& K, double nu) { return std::sqrt(K.KI * K.KI + K.KIII * K.KIII / (1 - nu)); }

double kink_angle(double K, double KII) {
    if (K < 0) throw std::invalid_argument("kink_angle: the opening SIF must be >= 0 (apply the compressive rule first)");
    const double root = std::sqrt(K * K + 8 * KII * KII);
    if (root == 0) return 0;
    return 2 * std::atan(-2 * KII / (K + root));
}

KthetaRange ktheta_range(double KI, double KII) {
    KthetaRange r;  // +-pi: K_theta = 0
    if (KII == 0) {
        r.max = std::max(0.0, KI);
        r.min = std::min(0.0, KI);
        return r;
    }
    const double root = std::sqrt(KI * KI + 8 * KII * KII);
    for (const double t : {2 * std::atan((KI - root) / (4 * KII)), 2 * std::atan((KI + root) / (4 * KII))}) {
        const double v = ktheta(KI, KII, t);
        r.max = std::max(r.max, v);
        r.min = std::min(r.min, v);
    }
    return r;
}

bool is_compressive(const Sifs& K, double compressive_factor) {
    const KthetaRange r = ktheta_range(K.KI, K.KII);
    return r.max < -r.min / compressive_factor;
}

TipLoading apply_compressive_rule(const Sifs& K, double compressive_factor) {
    if (!(compressive_factor > 0)) throw std::invalid_argument("compressive factor f_c must be > 0");
    TipLoading t;
    t.K = K;
    if (is_compressive(K, compressive_factor)) {
        t.compressive = true;
        t.K.KI = -K.KI / compressive_factor;
        t.K.KII = -K.KII / compressive_factor;
        t.K.KIII = -K.KIII / compressive_factor;
    }
    return t;
}

double rayleigh_speed(double mu, double rho) { return 0.9 * std::sqrt(mu / rho); }

double propagation_speed(double K_eff, double K_c, double c_R) {
    if (!(std::abs(K_eff) > K_c)) return 0;
    return c_R * (1 - K_c * K_c / (K_eff * K_eff));
}

double substep_duration(double r_f, double c_R) { return r_f / c_R; }

namespace {

// The angle in (outside, inside) where K_theta falls to K_c, by bisection to 1e-14 rad: inside holds
// K_theta > K_c, and K_theta falls monotonically from inside towards outside down to its minimum (<= 0),
// beyond which it stays <= 0 (valid_interval). Each halving compares K_theta at the midpoint with K_c; the
// result's bits steer the markers (eq. 4.14), so they are kept, but the comparison is made only where
// its outcome is in doubt. A safeguarded Newton iteration first locates the crossing, then two evaluations
// certify a bracket [a, b] around it: K_theta(a) above K_c and K_theta(b) below K_c, each by more than
// four times the evaluation's rounding error. By monotonicity the comparison at any midpoint on a's far
// side (towards inside) then comes out "above", and on b's far side "below": those halvings take their
// side without evaluating K_theta (about 35 of 47; a marker's sub-step evaluated K_theta ~190 times).
// certify finds the bracket (K_theta(a) > K_c and K_theta(b) < K_c beyond rounding, or the interval's
// own ends where that fails), bisect runs the halvings.
struct Bracket {
    double a, b;
};
Bracket certify(double KI, double KII, double K_c, double inside, double outside) {
    const double dir = inside > outside ? 1.0 : -1.0;  // from the crossing towards inside
    // |fl(K_theta) - K_theta|: sine and cosine within an ulp, then up to seven roundings (generous).
    const double err = 64 * std::numeric_limits<double>::epsilon() * (std::abs(KI) + 3 * std::abs(KII));
    double a = inside, b = outside;  // certified ends (none yet: the interval's own ends)
    if (std::isfinite(err) && K_c - 4 * err > 0) {
        // Newton on K_theta - K_c, kept inside the bracket it narrows.
        double in = inside, out = outside, x = 0.5 * (inside + outside);
        for (int it = 0; it < 12; ++it) {
            const double c = std::cos(x / 2), s = std::sin(x / 2);
            const double g = KI * c * c * c - 3 * KII * c * c * s - K_c;
            (g > 0 ? in : out) = x;
            const double slope = -1.5 * KI * c * c * s + 3 * KII * c * s * s - 1.5 * KII * c * c * c;
            double next = x - g / slope;
            if (!((next - out) * dir > 0 && (in - next) * dir > 0)) next = 0.5 * (in + out);
            // A step below 1e-9 leaves an error of its square's order: far inside the smallest bracket.
            // (Iterating on to 1e-13 cost a quarter more evaluations and certified fewer crossings: the
            // last steps wander at the rounding level.)
            const bool done = std::abs(next - x) < 1e-9;
            x = next;
            if (done) break;
        }
        for (const double delta : {2e-13, 1e-11, 1e-8, 1e-5}) {
            const double ta = x + dir * delta, tb = x - dir * delta;
            // Both strictly between outside and inside (monotonicity holds there).
            if (!((inside - ta) * dir > 0 && (tb - outside) * dir > 0)) continue;
            if (ktheta(KI, KII, ta) > K_c + 4 * err && ktheta(KI, KII, tb) < K_c - 4 * err) {
                a = ta;
                b = tb;
                break;
            }
        }
    }
    return {a, b};
}

// The halvings, each taking the certified side where the bracket decides it. The result lies
// strictly beyond b (mids at or beyond b are "below") and within 1e-14 of a or short of it (mids at
// or beyond a are "above", and the halvings stop at a width of 1e-14).
double bisect(double KI, double KII, double K_c, double inside, double outside, const Bracket& br) {
    const double dir = inside > outside ? 1.0 : -1.0;
    const double a = br.a, b = br.b;
    for (int it = 0; it < 200 && std::abs(outside - inside) > 1e-14; ++it) {
        const double mid = 0.5 * (inside + outside);
        bool above;
        if ((mid - a) * dir >= 0) above = true;        // at or beyond a, towards inside
        else if ((b - mid) * dir >= 0) above = false;  // at or beyond b, towards outside
        else above = ktheta(KI, KII, mid) > K_c;
        (above ? inside : outside) = mid;
    }
    return inside;
}

// w theta_opt + (1 - w) toward_weaker, w = 1 / (1 + r_grad r_c / K_c): eq. (4.14)'s last step.
double steered_towards(double theta_opt, double toward_weaker, const GradientDirection& g, double r_c, double K_c) {
    const double w = 1 / (1 + g.r * r_c / K_c);
    return w * theta_opt + (1 - w) * toward_weaker;
}

}  // namespace

AngleInterval valid_interval(double K_I_III, double KII, double K_c) {
    LazyAngleInterval lazy(K_I_III, KII, K_c);
    AngleInterval I;
    I.empty = lazy.empty();
    I.lo = lazy.end(0);
    I.hi = lazy.end(1);
    return I;
}

LazyAngleInterval::LazyAngleInterval(double K_I_III, double KII, double K_c) : KI_(K_I_III), KII_(KII), Kc_(K_c) {
    const double opt = kink_angle(K_I_III, KII);
    for (End& e : ends_) e.value = e.lower = e.upper = opt;  // empty: lo = hi = theta*
    if (!(ktheta(K_I_III, KII, opt) > K_c)) return;
    empty_ = false;
    // On each side of the maximum, K_theta falls monotonically to its minimum (<= 0) or to 0 at
    // +-pi and never climbs back above 0 < K_c: one crossing per side, bracketed now and bisected
    // when asked for. Never backwards: K_theta > K_c reaches past 90 degrees once K > 3.8 K_c (pure
    // mode I), and a front steered that far would run back through its own faces; an end stays at
    // +-90 degrees where K_theta still exceeds K_c there.
    const double limit = 0.5 * kPi;
    for (int i = 0; i < 2; ++i) {
        End& e = ends_[i];
        const double outside = i == 0 ? -limit : limit;
        if (ktheta(K_I_III, KII, outside) > K_c) {
            e.value = e.lower = e.upper = outside;
            continue;
        }
        e.known = false;
        e.inside = opt;
        e.outside = outside;
        const Bracket br = certify(K_I_III, KII, K_c, opt, outside);
        e.a = br.a;
        e.b = br.b;
        // bisect's result lies between b and a (within 1e-14 beyond a): 1e-13 of slack.
        e.lower = std::min(br.a, br.b) - 1e-13;
        e.upper = std::max(br.a, br.b) + 1e-13;
    }
}

double LazyAngleInterval::end(int i) {
    End& e = ends_[i];
    if (!e.known) {
        e.value = bisect(KI_, KII_, Kc_, e.inside, e.outside, Bracket{e.a, e.b});
        e.known = true;
    }
    return e.value;
}

double steered_blended_angle(double theta_opt, LazyAngleInterval& cur, LazyAngleInterval& old, bool turned, double turn,
                             double w_t, const GradientDirection& g, double r_c, double K_c) {
    if (cur.empty() || !(K_c > 0) || g.r == 0) return theta_opt;
    // An end of the blended interval, eq. (4.12), from the ends of the two: nondecreasing in both
    // (w_t in [0, 1]; rounding is monotone), so bounds on theirs bound it.
    const bool both = !old.empty();
    auto blended = [&](double c, double o) { return both ? blend_angle(turned ? o + turn : o, c, w_t) : c; };
    auto exact = [&](int i) { return blended(cur.end(i), both ? old.end(i) : 0.0); };
    const double lo_min = blended(cur.lower(0), both ? old.lower(0) : 0.0);
    const double lo_max = blended(cur.upper(0), both ? old.upper(0) : 0.0);
    const double hi_min = blended(cur.lower(1), both ? old.lower(1) : 0.0);
    const double hi_max = blended(cur.upper(1), both ? old.upper(1) : 0.0);
    // std::clamp(v, lo, hi) as steered_angle takes it, with only the ends it returns computed.
    const double v = g.theta;
    double toward;
    if (v < lo_min) toward = exact(0);
    else if (v > hi_max) toward = exact(1);
    else if (v >= lo_max && v <= hi_min) toward = v;
    else toward = std::clamp(v, exact(0), exact(1));
    return steered_towards(theta_opt, toward, g, r_c, K_c);
}

double blend_angle(double theta_old, double theta_new, double w_t) { return w_t * theta_new + (1 - w_t) * theta_old; }

double blend_weight(int k, int n) {
    if (n <= 1) return 1;
    return std::clamp(static_cast<double>(k) / (n - 1), 0.0, 1.0);
}

GradientDirection gradient_direction(const Vec3& grad_Kc, const Vec3& n1, const Vec3& n2) {
    const double g1 = grad_Kc.dot(n1), g2 = grad_Kc.dot(n2);
    GradientDirection g;
    g.r = std::sqrt(g1 * g1 + g2 * g2);
    g.theta = g.r > 0 ? std::atan2(0.0 - g1, 0.0 - g2) : 0;  // 0.0 - x: no signed zero, backwards is +pi
    return g;
}

double steered_angle(double theta_opt, const AngleInterval& valid, const GradientDirection& g, double r_c, double K_c) {
    if (valid.empty || !(K_c > 0) || g.r == 0) return theta_opt;
    const double toward_weaker = std::clamp(g.theta, valid.lo, valid.hi);  // argmin over I of |theta - theta_grad|
    return steered_towards(theta_opt, toward_weaker, g, r_c, K_c);
}

Vec3 front_velocity(double speed, double theta, const Vec3& n1, const Vec3& n2) {
    return speed * (std::sin(theta) * n1 + std::cos(theta) * n2);
}

}  // namespace cf::propagate
