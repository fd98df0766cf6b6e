// Verification cases of the rigid-body coupling (thesis ch. 7; docs/verification.md cases 23-25).
#include "nodes/registration.hpp"
#include "nodes/rigid/balanced_tractions.hpp"
#include "nodes/rigid/contact_duration.hpp"
#include "nodes/rigid/rigid_world.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"

#include <Eigen/QR>

#include <cmath>
#include <random>
#include <sstream>

namespace cf {
namespace {

// Case 23: a spinning box without contacts. Bullet integrates semi-implicit Euler (velocity first,
// then position with the new velocity), whose exact solution under constant g after t = n dt is
// x0 + v0 t + g t (t + dt) / 2 (the continuous parabola plus g dt t / 2), and a torque-free body
// spinning about a principal axis keeps omega, so its rotation is exp(omega t) R0.
VerificationResult ballistic_free_fall() {
    VerificationResult r;
    r.tolerance = 1e-9;
    rigid::WorldSettings ws;
    ws.time_step = 1.0 / 250;
    rigid::RigidWorld world(ws);
    rigid::BodySpec b;
    b.name = "box";
    BoxSpec box;
    box.size = Vec3(0.3, 0.2, 0.1);
    box.centre = Vec3(1, 2, 30);
    box.subdivisions = 2;
    b.mesh = make_box(box);
    b.density = 2300;
    b.velocity = Vec3(3, -1, 12);
    const int id = world.add_body(b);
    const rigid::MassProperties& mp = world.mass_properties_of(id);
    // Spin about the body's principal axis of largest moment (a stable, torque-free rotation).
    const Vec3 axis = mp.principal_axes.col(2);
    const double spin = 7.0;  // [rad/s]
    rigid::RigidWorld world2(ws);
    b.angular_velocity = spin * axis;
    const int id2 = world2.add_body(b);
    const rigid::BodyState s0 = world2.state(id2);
    const int steps = 500;
    for (int k = 0; k < steps; ++k) world2.step();
    const double t = steps * ws.time_step;
    const rigid::BodyState s = world2.state(id2);
    const Vec3 expect = mp.centre + b.velocity * t + 0.5 * ws.gravity * t * (t + ws.time_step);
    const Vec3 v_expect = b.velocity + ws.gravity * t;
    const Eigen::Quaterniond q_expect = Eigen::Quaterniond(Eigen::AngleAxisd(spin * t, axis)) * s0.rotation;
    const double ex = (s.position - expect).norm() / expect.norm();
    const double ev = (s.velocity - v_expect).norm() / v_expect.norm();
    const double eq = std::min((s.rotation.coeffs() - q_expect.coeffs()).norm(), (s.rotation.coeffs() + q_expect.coeffs()).norm());
    const double ew = (s.angular_velocity - spin * axis).norm() / spin;
    r.error = std::max({ex, ev, eq, ew});
    r.passed = r.error <= r.tolerance && id == 0;
    std::ostringstream os;
    os.precision(3);
    os << steps << " steps of " << ws.time_step << " s, box 0.3 x 0.2 x 0.1 m spinning at " << spin
       << " rad/s: position " << ex << ", velocity " << ev << ", rotation " << eq << ", spin " << ew
       << " (relative; the continuous parabola differs by g dt t / 2 = " << 0.5 * ws.gravity.norm() * ws.time_step * t << " m)";
    r.details = os.str();
    return r;
}

// Case 24: random collision tractions on an icosphere placed far from the origin: the balanced
// field has no net force or torque, and it is the closest such field: it equals the projection
// computed independently by a QR factorisation of the dense constraint matrix S^T (3M x 6).
VerificationResult balanced_tractions_case() {
    VerificationResult r;
    r.tolerance = 1e-12;
    SphereSpec sp;
    sp.radius = 0.05;
    sp.level = 2;
    SurfaceMesh m = make_icosphere(sp);
    for (Vec3& v : m.vertices) v += Vec3(40, -25, 7);  // far from the origin
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-1e6, 1e6);
    std::vector<Vec3> q(m.num_triangles());
    for (Vec3& x : q) x = Vec3(U(rng), U(rng), U(rng));
    // A concentrated "impact" on one element, as a collision gives.
    q[3] += Vec3(0, 0, -5e8);
    std::ostringstream os;
    os.precision(3);
    bool ok = true;
    double worst = 0;
    for (bool weighted : {false, true}) {
        const rigid::BalancedTractions bt = rigid::balance_tractions(m, q, weighted);
        Vec3 F, T, F0, T0;
        rigid::traction_resultants(m, bt.traction, F, T);
        rigid::traction_resultants(m, q, F0, T0);
        double A = 0, qmax = 0;
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            const Tri& tr = m.triangles[t];
            A += 0.5 * (m.vertices[tr[1]] - m.vertices[tr[0]]).cross(m.vertices[tr[2]] - m.vertices[tr[0]]).norm();
            qmax = std::max(qmax, q[t].norm());
        }
        const double fscale = A * qmax, tscale = fscale * sp.radius;
        const double ef = F.norm() / fscale, et = T.norm() / tscale;
        // Independent projection: with W^(1/2) scaling, q_c = W^-1/2 P W^-1/2 S^T (..) where P projects
        // onto range(W^-1/2 S^T); equivalently the correction is the least-squares fit of W^1/2 q_i in
        // range(W^-1/2 S^T). Build B = W^-1/2 S^T (3M x 6) densely and solve with Householder QR.
        const std::size_t M = m.num_triangles();
        Eigen::MatrixXd B(3 * M, 6);
        Eigen::VectorXd y(3 * M);
        Vec3 c = Vec3::Zero();
        std::vector<double> area(M);
        std::vector<Vec3> cen(M);
        for (std::size_t t = 0; t < M; ++t) {
            const Tri& tr = m.triangles[t];
            area[t] = 0.5 * (m.vertices[tr[1]] - m.vertices[tr[0]]).cross(m.vertices[tr[2]] - m.vertices[tr[0]]).norm();
            cen[t] = (m.vertices[tr[0]] + m.vertices[tr[1]] + m.vertices[tr[2]]) / 3;
            c += area[t] * cen[t];
        }
        c /= A;
        for (std::size_t t = 0; t < M; ++t) {
            const double w = weighted ? area[t] : 1.0, s = 1 / std::sqrt(w);
            const Vec3 a = cen[t] - c;
            Eigen::Matrix3d X;
            X << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
            B.block<3, 3>(3 * t, 0) = s * area[t] * Eigen::Matrix3d::Identity();
            B.block<3, 3>(3 * t, 3) = s * area[t] * X.transpose();
            y.segment<3>(3 * t) = std::sqrt(w) * q[t];
        }
        const Eigen::VectorXd fit = B * B.householderQr().solve(y);  // projection of y onto range(B)
        double diff = 0, ref = 0;
        for (std::size_t t = 0; t < M; ++t) {
            const double s = 1 / std::sqrt(weighted ? area[t] : 1.0);
            const Vec3 qc = s * fit.segment<3>(3 * t);
            diff = std::max(diff, ((q[t] - qc) - bt.traction[t]).norm());
            ref = std::max(ref, q[t].norm());
        }
        const double ek = diff / ref;
        worst = std::max({worst, ef, et, ek});
        ok = ok && ef <= r.tolerance && et <= r.tolerance && ek <= 1e-9 && F0.norm() > 1e-3 * fscale;
        os << (weighted ? "area-weighted" : "unweighted") << ": net force " << ef << ", torque " << et
           << " (relative), distance to the QR projection " << ek << "; ";
    }
    r.error = worst;
    r.passed = ok;
    r.details = std::string("icosphere of 320 triangles centred 48 m from the origin, random tractions and one impact: ") + os.str();
    return r;
}

// Case 25: t_c for a hand-computed contact, and finite positive durations for flat and resting contacts.
VerificationResult hertz_duration_case() {
    VerificationResult r;
    r.tolerance = 1e-12;
    // Two equal PMMA spheres of R = 0.05 m (H = 20 1/m each), m = 0.6 kg each, meeting at 2 m/s:
    // E* = 1 / (2 (1 - 0.327^2) / 3.1e9) = 1.7355e9 Pa, R* = 0.025 m, m* = 0.3 kg,
    // t_c = 2.87 (0.09 / (E*^2 0.025 2))^(1/5).
    const rigid::ContactBody s{3.1e9, 0.327, 0.6, 20.0};
    const rigid::ContactDuration d = rigid::hertz_contact_duration(s, s, 2.0);
    const double E = 1 / (2 * (1 - 0.327 * 0.327) / 3.1e9);
    const double hand = 2.87 * std::pow(0.09 / (E * E * 0.025 * 2.0), 0.2);
    const double e = std::abs(d.seconds - hand) / hand;
    // Flat contact on a static floor (H = 0, infinite mass) and a contact at rest.
    const rigid::ContactBody floor{3.0e10, 0.2, 0.0, 0.0};
    const rigid::ContactBody flat_box{3.1e9, 0.327, 0.6, 0.0};
    const rigid::ContactDuration flat = rigid::hertz_contact_duration(flat_box, floor, 2.0);
    const rigid::ContactDuration rest = rigid::hertz_contact_duration(s, floor, 0.0);
    const bool finite = std::isfinite(flat.seconds) && flat.seconds > 0 && flat.radius_capped && std::isfinite(rest.seconds) &&
                        rest.seconds > 0 && rest.speed_raised;
    r.error = e;
    r.passed = e <= r.tolerance && finite;
    std::ostringstream os;
    os.precision(6);
    os << "PMMA spheres R = 0.05 m, 0.6 kg, 2 m/s: t_c = " << d.seconds << " s (hand " << hand << "); flat box on concrete: "
       << flat.seconds << " s (R capped at " << flat.R << " m); sphere at rest on concrete: " << rest.seconds << " s (v raised to "
       << rest.v << " m/s)";
    r.details = os.str();
    return r;
}

}  // namespace

void add_rigid_verification_cases(std::vector<VerificationCase>& cases) {
    cases.push_back({"ballistic_free_fall",
                     "case 23: a spinning body without contacts follows the closed-form trajectory of the integrator (1e-9)",
                     ballistic_free_fall});
    cases.push_back({"balanced_tractions", "case 24: eq. (7.5): no net force or torque, and the closest such field (QR check)",
                     balanced_tractions_case});
    cases.push_back({"hertz_duration", "case 25: Hertz contact duration against a hand computation; flat and resting contacts finite",
                     hertz_duration_case});
}

}  // namespace cf
