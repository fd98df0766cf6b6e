#include "nodes/initiate/user_crack.hpp"

#include "nodes/initiate/sheet_mesher.hpp"
#include "nodes/initiate/surface_queries.hpp"
#include "nodes/propagate/front_markers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cf::initiate {

namespace {

std::string format(const Vec3& v) {
    std::ostringstream s;
    s << v.x() << " " << v.y() << " " << v.z();
    return s.str();
}

std::string metres(double x) {
    std::ostringstream s;
    s.precision(4);
    s << x << " m";
    return s.str();
}

// Distance from the surface for points inside it, -1 outside.
double clearance(const SurfaceMesh& surface, const Vec3& p) {
    return inside_closed_mesh(surface, p) ? distance_to_mesh(surface, p) : -1.0;
}

}  // namespace

UserCrack build_user_crack(const UserCrackSpec& spec, const SurfaceMesh& surface, const ObjectDistance& object_distance,
                           double r_c, double r_f, const std::string& name) {
    if (!(r_c > 0) || !(r_f > 0)) throw std::invalid_argument("user crack: r_c and r_f must be > 0 m");
    const double R = spec.radius;
    if (!(R > 0) || !std::isfinite(R)) throw std::invalid_argument("parameter 'radius' must be a finite length > 0 m");
    const double nn = spec.normal.norm();
    if (!(nn > 0) || !std::isfinite(nn))
        throw std::invalid_argument("parameter 'normal' (" + format(spec.normal) +
                                    ") is zero: give the normal of the crack plane, e.g. '0 0 1'");
    UserCrack out;
    const Vec3 n = spec.normal / nn;
    const Vec3& d = spec.front_direction;
    out.half = d.norm() > 0;
    if (out.half) {
        const Vec3 dp = d - d.dot(n) * n;  // into the crack plane
        if (!(dp.norm() > 1e-6 * d.norm()))
            throw std::invalid_argument("parameter 'front_direction' (" + format(d) + ") is parallel to 'normal' (" +
                                        format(spec.normal) +
                                        "): it must lie in the crack plane and point from the centre into the body "
                                        "(e.g. the inward normal of the face the centre is on), or be '0 0 0' for a full disk");
        out.t1 = dp.normalized();
    } else {
        const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
        out.t1 = (helper - helper.dot(n) * n).normalized();
    }
    out.plane_normal = n;
    out.t2 = n.cross(out.t1);
    const Vec3& t1 = out.t1;
    const Vec3& t2 = out.t2;
    const Vec3& c = spec.centre;
    const double m = out.margin = user_crack_margin(r_c, r_f);
    // The region in polar coordinates about the centre: phi in [phi0, phi0 + span].
    const double phi0 = out.half ? -M_PI / 2 : 0.0, span = out.half ? M_PI : 2 * M_PI;
    const std::string what = out.half ? "half-disk" : "disk";

    // Some part of the region must be inside the object.
    std::vector<Vec3> samples;
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 32; ++j) {
            const double rho = R * i / 8.0, phi = phi0 + span * j / 32.0;
            samples.push_back(c + rho * (std::cos(phi) * t1 + std::sin(phi) * t2));
        }
    if (std::none_of(samples.begin(), samples.end(), [&](const Vec3& p) { return object_distance(p) < 0; }))
        throw std::invalid_argument("the crack " + what + " (parameter 'centre' " + format(c) + ", 'radius' " + metres(R) +
                                    ") lies outside the object: no part of it is inside; move 'centre' into the object "
                                    "(or onto its surface with 'front_direction' pointing into it)");

    // An interior node at edge length r_c needs r_c/2 of room around the inner point; an edge
    // crack also loses the margin along its straight edge (the object's face).
    const double min_radius = out.half ? r_c + 2 * m : 0.5 * r_c;
    if (R < min_radius)
        throw std::invalid_argument("parameter 'radius' (" + metres(R) + ") is too small: a BEM crack sheet with edges of r_c = " +
                                    metres(r_c) + " needs an interior node, which takes radius >= " + metres(min_radius) +
                                    (out.half ? " for an edge crack (r_c + 2 x the surface margin " + metres(m) + ")" : " (r_c / 2)") +
                                    "; increase 'radius' or refine r_c");

    // Inner point: the centre, for an edge crack centre + R/2 d, else the deepest sample.
    Vec3 o = out.half ? Vec3(c + 0.5 * R * t1) : c;
    if (clearance(surface, o) < m) {
        double best = -1;
        for (const Vec3& p : samples) {
            const double h = clearance(surface, p);
            if (h > best) {
                best = h;
                o = p;
            }
        }
        if (best < m)
            throw std::invalid_argument("the crack " + what + " (parameter 'centre' " + format(c) + ", 'radius' " + metres(R) +
                                        ") has no point at least the margin " + metres(m) +
                                        " inside the BEM surface 'mesh'; move 'centre' deeper into the object (is 'mesh' "
                                        "closed and outward oriented?)");
    }
    out.inner_point = o;

    // Rays in the plane from o, each cut at the region's edge or where it comes within the
    // margin of the surface (sphere tracing: a step never exceeds the clearance left).
    const int rays = std::max(128, 16 * static_cast<int>(std::ceil(2 * M_PI * R / r_c)));
    const Vec3 w = o - c;
    std::vector<Vec3> rim(rays);
    double s_min = std::numeric_limits<double>::infinity();
    for (int i = 0; i < rays; ++i) {
        const double theta = 2 * M_PI * i / rays;
        const Vec3 u = std::cos(theta) * t1 + std::sin(theta) * t2;
        const double b = w.dot(u);
        double s_end = -b + std::sqrt(std::max(0.0, b * b - (w.squaredNorm() - R * R)));  // the circle
        if (out.half && u.dot(t1) < 0) s_end = std::min(s_end, -w.dot(t1) / u.dot(t1));  // the straight edge
        double s = 0;
        for (int it = 0; it < 400; ++it) {
            const double h = distance_to_mesh(surface, o + s * u) - m;
            if (s + h >= s_end) {
                s = s_end;
                break;
            }
            if (h <= 1e-7 * R) break;
            s += h;
        }
        s_min = std::min(s_min, s);
        rim[i] = Vec3(s * std::cos(theta), s * std::sin(theta), 0);
    }
    if (s_min < 0.5 * r_c)
        throw std::invalid_argument("the crack " + what + " (parameter 'centre' " + format(c) + ", 'radius' " + metres(R) +
                                    ") is too close to the object's surface: kept " + metres(m) +
                                    " inside it, the BEM sheet reaches only " + metres(s_min) +
                                    " from its inner point, but needs r_c / 2 = " + metres(0.5 * r_c) +
                                    " for an interior node; move 'centre' deeper into the object or increase 'radius'");

    const std::size_t count =
        std::max<std::size_t>(6, static_cast<std::size_t>(std::ceil(propagate::polyline_length(rim, true) / (0.5 * r_c))));
    std::vector<Vec2> boundary;
    for (const Vec3& p : propagate::resample_polyline(rim, true, count)) boundary.emplace_back(p.x(), p.y());
    // Longest edges up to 1.4 r_c: the range front growth keeps new front edges in (fig. 16), so
    // the mean edge is ~r_c; the r_c/2 rim spacing grades towards the front.
    out.sheet = mesh_planar_region(boundary, Vec2::Zero(), max_sheet_edge_factor * r_c, o, t1, t2, name);

    TriangleObstacles obstacles;
    obstacles.add(surface, "BEM surface 'mesh'");
    if (obstacles.intersects(out.sheet))
        throw std::invalid_argument("the crack sheet of '" + name + "' touches the BEM surface 'mesh' although it was kept " +
                                    metres(m) + " inside it; is 'mesh' closed and outward oriented?");

    // The recorded fine surface: the whole region as a fan about the centre, chords finer than r_f.
    const int segments = std::max(out.half ? 32 : 64, static_cast<int>(std::ceil(span * R / r_f)));
    for (int k = 0; k < segments; ++k) {
        const double a0 = phi0 + span * k / segments, a1 = phi0 + span * (k + 1) / segments;
        out.recorded.push_back({c, c + R * (std::cos(a0) * t1 + std::sin(a0) * t2), c + R * (std::cos(a1) * t1 + std::sin(a1) * t2)});
    }
    return out;
}

}  // namespace cf::initiate
