// Verification cases of the propagation laws (docs/verification.md cases 6 and 7).
#include "nodes/propagate/propagation_law.hpp"
#include "nodes/registration.hpp"

#include <cmath>
#include <sstream>

namespace cf {

namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

// theta maximising G(theta) of eq. (4.9) found numerically: a grid over (-pi, pi) then golden
// section; independent of the closed form of eq. (2.36).
double numerical_optimum(const propagate::Sifs& K) {
    const double pi = 3.14159265358979323846;
    auto G = [&](double t) { return propagate::energy_release_rate(K, t, 1.0, 0.3); };
    double best = 0, gbest = -1;
    for (int i = -3600; i <= 3600; ++i) {
        const double t = i * pi / 3601;
        if (G(t) > gbest) {
            gbest = G(t);
            best = t;
        }
    }
    double a = best - pi / 3601, b = best + pi / 3601;
    const double r = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 100; ++it) {
        const double c = b - r * (b - a), d = a + r * (b - a);
        (G(c) > G(d) ? b : a) = (G(c) > G(d) ? d : c);
    }
    return 0.5 * (a + b);
}

VerificationResult kink_angle_case() {
    struct Case {
        propagate::Sifs K;
        double expected_deg;
        const char* name;
    };
    // Closed forms: pure mode II -acos(1/3); K_I = K_II: 2 atan(-1/2) = -atan(4/3); pure mode I 0.
    const Case cases[] = {{{0, 1, 0}, -std::acos(1.0 / 3) * kDeg, "mode II"},
                          {{1, 1, 0}, -std::atan(4.0 / 3) * kDeg, "K_I = K_II"},
                          {{1, 0, 0}, 0.0, "mode I"}};
    double err = 0, num_err = 0;
    std::ostringstream os;
    os.precision(6);
    for (const Case& c : cases) {
        const double th = propagate::kink_angle(c.K.KI, c.K.KII) * kDeg;
        const double num = numerical_optimum(c.K) * kDeg;
        err = std::max(err, std::abs(th - c.expected_deg));
        num_err = std::max(num_err, std::abs(num - c.expected_deg));
        os << c.name << ": " << th << " deg (argmax G " << num << "); ";
    }
    // Compressive rule (ch. 4.5.1), f_c = 2: K_I = -1 is compressive and becomes K_I = 0.5 with
    // theta* = 0; K_I = +1 stays tensile; K = (-1, 0.3) is compressive, K_II flips sign.
    const auto comp = propagate::apply_compressive_rule({-1, 0, 0}, 2);
    const auto tens = propagate::apply_compressive_rule({1, 0, 0}, 2);
    const auto mixed = propagate::apply_compressive_rule({-1, 0.3, 0}, 2);
    const bool rule_ok = comp.compressive && comp.K.KI == 0.5 && propagate::kink_angle(comp.K.KI, comp.K.KII) == 0 &&
                         !tens.compressive && tens.K.KI == 1 && mixed.compressive && mixed.K.KI == 0.5 &&
                         mixed.K.KII == -0.15;
    os << "compressive rule (f_c = 2): " << (rule_ok ? "ok" : "WRONG");
    VerificationResult r;
    // A maximum is flat: golden section resolves it to ~sqrt(machine eps), hence 1e-4 deg there.
    r.error = err;
    r.tolerance = 1e-9;
    r.passed = err <= r.tolerance && num_err <= 1e-4 && rule_ok;
    os << "; max |theta* - closed form| = " << err << " deg, |argmax G - closed form| = " << num_err << " deg";
    r.details = os.str();
    return r;
}

VerificationResult propagation_speed_case() {
    // PMMA of thesis-cases.yaml: E 3.1e9 Pa, nu 0.327, rho 1200 kg/m^3.
    const double mu = 3.1e9 / (2 * 1.327), rho = 1200, Kc = 1e6;
    const double cR = propagate::rayleigh_speed(mu, rho);
    const double expected = 0.9 * std::sqrt(mu / rho);
    const double below = propagate::propagation_speed(0.999 * Kc, Kc, cR);
    const double at = propagate::propagation_speed(Kc, Kc, cR);
    const double twice = propagate::propagation_speed(2 * Kc, Kc, cR);  // c_R (1 - 1/4)
    VerificationResult r;
    r.error = std::max(std::abs(cR - expected) / expected, std::abs(twice - 0.75 * expected) / expected);
    r.tolerance = 1e-12;
    r.passed = r.error <= r.tolerance && below == 0 && at == 0;
    std::ostringstream os;
    os << "PMMA c_R = " << cR << " m/s; v(0.999 K_c) = " << below << ", v(K_c) = " << at << ", v(2 K_c) = " << twice
       << " m/s (expect 0.75 c_R)";
    r.details = os.str();
    return r;
}

}  // namespace

void add_propagate_verification_cases(std::vector<VerificationCase>& cases) {
    cases.push_back({"kink_angle", "case 6: kink angle eq. (2.36)/(4.10) vs closed forms and argmax G; compressive rule",
                     kink_angle_case});
    cases.push_back({"propagation_speed", "case 7: Rayleigh speed 0.9 sqrt(mu/rho), eq. (4.8) speed 0 below K_c",
                     propagation_speed_case});
}

}  // namespace cf
