#include "nodes/shape/torus.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>
#include <stdexcept>

namespace cf {
namespace {

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

// Distance between two angles on the circle, in [0, pi].
double angle_between(double a, double b) {
    const double two_pi = 2 * std::acos(-1.0);
    double d = std::fmod(std::abs(a - b), two_pi);
    return d > 0.5 * two_pi ? two_pi - d : d;
}

}  // namespace

SurfaceMesh make_torus(const TorusSpec& spec) {
    const double pi = std::acos(-1.0);
    require(spec.minor_radius > 0, "parameter 'minor_radius' must be > 0 m, got " + graph::format_number(spec.minor_radius));
    require(spec.major_radius > spec.minor_radius,
            "parameter 'major_radius' (" + graph::format_number(spec.major_radius) +
                " m) must exceed 'minor_radius' (" + graph::format_number(spec.minor_radius) +
                " m), otherwise the tube intersects itself");
    require(spec.major_segments >= 4 && spec.major_segments % 2 == 0,
            "parameter 'major_segments' must be even and >= 4 (so the left and right pulled faces are mirror "
            "images), got " + std::to_string(spec.major_segments));
    require(spec.minor_segments >= 3, "parameter 'minor_segments' must be >= 3, got " + std::to_string(spec.minor_segments));
    const double triangles = 2.0 * spec.major_segments * spec.minor_segments;
    require(triangles <= 4e6, "major_segments and minor_segments would make " +
                                  std::to_string(static_cast<long long>(triangles)) + " triangles (limit 4000000); reduce them");
    // The quad centres nearest the pulled directions are half a segment away from them.
    const double needed = std::max(pi / spec.major_segments, pi / spec.minor_segments);
    require(spec.pull_angle >= needed && spec.pull_angle < 0.5 * pi,
            "parameter 'pull_angle' must be in [" + graph::format_number(needed) + ", pi/2) rad for these segment counts "
            "(a smaller angle selects no quad centre), got " + graph::format_quantity(spec.pull_angle, "rad"));

    enum { rest = 0, pull_left = 1, pull_right = 2 };
    const int nu = spec.major_segments, nv = spec.minor_segments;
    SurfaceMesh m;
    m.region_names = {"rest", "pull_left", "pull_right"};
    m.vertices.reserve(std::size_t(nu) * nv);
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double phi = 2 * pi * i / nu, theta = 2 * pi * j / nv;
            const double rho = spec.major_radius + spec.minor_radius * std::cos(theta);
            m.vertices.push_back(spec.centre + Vec3(rho * std::cos(phi), rho * std::sin(phi), spec.minor_radius * std::sin(theta)));
        }
    auto at = [nu, nv](int i, int j) { return (i % nu) * nv + (j % nv); };
    const double tol = 1e-12;
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const double phi_c = 2 * pi * (i + 0.5) / nu, theta_c = 2 * pi * (j + 0.5) / nv;
            int region = rest;
            if (angle_between(theta_c, 0) <= spec.pull_angle + tol) {
                if (angle_between(phi_c, pi) <= spec.pull_angle + tol) region = pull_left;
                else if (angle_between(phi_c, 0) <= spec.pull_angle + tol) region = pull_right;
            }
            // Walking +phi then +theta faces outward: d/dphi x d/dtheta = cos(theta) e_rho + sin(theta) e_z.
            const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
            m.region.push_back(region);
            m.region.push_back(region);
        }
    return m;
}

}  // namespace cf
