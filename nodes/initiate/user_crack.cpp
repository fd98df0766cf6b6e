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

// build_user_crack's steps, in the order it calls them.

// The sizes and the normal checked; returns the unit normal.
Vec3 checked_normal(const UserCrackSpec& spec, double r_c, double r_f) {
    if (!(r_c > 0) || !(r_f > 0)) throw std::invalid_argument("user crack: r_c and r_f must be > 0 m");
    const double R = spec.radius;
    if (!(R > 0) || !std::isfinite(R)) throw std::invalid_argument("parameter 'radius' must be a finite length > 0 m");
    const double nn = spec.normal.norm();
    if (!(nn > 0) || !std::isfinite(nn))
        throw std::invalid_argument("parameter 'normal' (" + format(spec.normal) +
                                    ") is zero: give the normal of the crack plane, e.g. '0 0 1'");
    return spec.normal / nn;
}

// The plane's frame: t1 along the front direction for an edge crack (half-disk), else any
// in-plane direction; t2 = n x t1.
void crack_frame(const UserCrackSpec& spec, const Vec3& n, UserCrack& out) {
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
}

// The region in polar coordinates about the centre c: radius R, phi in [phi0, phi0 + span].
struct CrackRegion {
    Vec3 c, t1, t2;
    double R, m;  // radius, surface margin [m]
    double phi0, span;
    bool half;
    std::string what;  // "disk" or "half-disk"

    Vec3 at(double rho, double phi) const { return c + rho * (std::cos(phi) * t1 + std::sin(phi) * t2); }
    // "the crack disk (parameter 'centre' ..., 'radius' ...)" for messages.
    std::string described() const {
        return "the crack " + what + " (parameter 'centre' " + format(c) + ", 'radius' " + metres(R) + ")";
    }
};

// Points of the region on 9 rings of 33 angles; some must be inside the object.
std::vector<Vec3> inside_samples(const CrackRegion& g, const ObjectDistance& object_distance) {
    std::vector<Vec3> samples;
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 32; ++j) samples.push_back(g.at(g.R * i / 8.0, g.phi0 + g.span * j / 32.0));
    if (std::none_of(samples.begin(), samples.end(), [&](const Vec3& p) { return object_distance(p) < 0; }))
        throw std::invalid_argument(g.described() +
                                    " lies outside the object: no part of it is inside; move 'centre' into the object "
                                    "(or onto its surface with 'front_direction' pointing into it)");
    return samples;
}

// An interior node at edge length r_c needs r_c/2 of room around the inner point; an edge
// crack also loses the margin along its straight edge (the object's face).
void check_radius(const CrackRegion& g, double r_c) {
    const double min_radius = g.half ? r_c + 2 * g.m : 0.5 * r_c;
    if (g.R < min_radius)
        throw std::invalid_argument("parameter 'radius' (" + metres(g.R) + ") is too small: a BEM crack sheet with edges of r_c = " +
                                    metres(r_c) + " needs an interior node, which takes radius >= " + metres(min_radius) +
                                    (g.half ? " for an edge crack (r_c + 2 x the surface margin " + metres(g.m) + ")" : " (r_c / 2)") +
                                    "; increase 'radius' or refine r_c");
}

// Inner point: the centre, for an edge crack centre + R/2 d, else the deepest sample.
Vec3 inner_point(const CrackRegion& g, const SurfaceMesh& surface, const std::vector<Vec3>& samples) {
    Vec3 o = g.half ? Vec3(g.c + 0.5 * g.R * g.t1) : g.c;
    if (clearance(surface, o) >= g.m) return o;
    double best = -1;
    for (const Vec3& p : samples) {
        const double h = clearance(surface, p);
        if (h > best) {
            best = h;
            o = p;
        }
    }
    if (best < g.m)
        throw std::invalid_argument(g.described() + " has no point at least the margin " + metres(g.m) +
                                    " inside the BEM surface 'mesh'; move 'centre' deeper into the object (is 'mesh' "
                                    "closed and outward oriented?)");
    return o;
}

// Rays in the plane from o, each cut at the region's edge or where it comes within the margin of
// the surface (sphere tracing: a step never exceeds the clearance left). The rim in plane
// coordinates about o (z = 0).
std::vector<Vec3> sheet_rim(const CrackRegion& g, const SurfaceMesh& surface, const Vec3& o, double r_c) {
    const double R = g.R, m = g.m;
    const int rays = std::max(128, 16 * static_cast<int>(std::ceil(2 * M_PI * R / r_c)));
    const Vec3 w = o - g.c;
    std::vector<Vec3> rim(rays);
    double s_min = std::numeric_limits<double>::infinity();
    for (int i = 0; i < rays; ++i) {
        const double theta = 2 * M_PI * i / rays;
        const Vec3 u = std::cos(theta) * g.t1 + std::sin(theta) * g.t2;
        const double b = w.dot(u);
        double s_end = -b + std::sqrt(std::max(0.0, b * b - (w.squaredNorm() - R * R)));  // the circle
        if (g.half && u.dot(g.t1) < 0) s_end = std::min(s_end, -w.dot(g.t1) / u.dot(g.t1));  // the straight edge
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
        throw std::invalid_argument(g.described() + " is too close to the object's surface: kept " + metres(m) +
                                    " inside it, the BEM sheet reaches only " + metres(s_min) +
                                    " from its inner point, but needs r_c / 2 = " + metres(0.5 * r_c) +
                                    " for an interior node; move 'centre' deeper into the object or increase 'radius'");
    return rim;
}

// The BEM sheet inside the rim, which must stay clear of the surface.
SurfaceMesh mesh_sheet(const std::vector<Vec3>& rim, const CrackRegion& g, const SurfaceMesh& surface, const Vec3& o,
                       double r_c, const std::string& name) {
    const std::size_t count =
        std::max<std::size_t>(6, static_cast<std::size_t>(std::ceil(propagate::polyline_length(rim, true) / (0.5 * r_c))));
    std::vector<Vec2> boundary;
    for (const Vec3& p : propagate::resample_polyline(rim, true, count)) boundary.emplace_back(p.x(), p.y());
    // Longest edges up to 1.4 r_c: the range front growth keeps new front edges in (fig. 16), so
    // the mean edge is ~r_c; the r_c/2 rim spacing grades towards the front.
    SurfaceMesh sheet = mesh_planar_region(boundary, Vec2::Zero(), max_sheet_edge_factor * r_c, o, g.t1, g.t2, name);
    TriangleObstacles obstacles;
    obstacles.add(surface, "BEM surface 'mesh'");
    if (obstacles.intersects(sheet))
        throw std::invalid_argument("the crack sheet of '" + name + "' touches the BEM surface 'mesh' although it was kept " +
                                    metres(g.m) + " inside it; is 'mesh' closed and outward oriented?");
    return sheet;
}

// The recorded fine surface: the whole region as a fan about the centre, chords finer than r_f.
std::vector<Triangle3> recorded_fan(const CrackRegion& g, double r_f) {
    std::vector<Triangle3> fan;
    const int segments = std::max(g.half ? 32 : 64, static_cast<int>(std::ceil(g.span * g.R / r_f)));
    for (int k = 0; k < segments; ++k) {
        const double a0 = g.phi0 + g.span * k / segments, a1 = g.phi0 + g.span * (k + 1) / segments;
        fan.push_back({g.c, g.c + g.R * (std::cos(a0) * g.t1 + std::sin(a0) * g.t2),
                       g.c + g.R * (std::cos(a1) * g.t1 + std::sin(a1) * g.t2)});
    }
    return fan;
}

}  // namespace

UserCrack build_user_crack(const UserCrackSpec& spec, const SurfaceMesh& surface, const ObjectDistance& object_distance,
                           double r_c, double r_f, const std::string& name) {
    const Vec3 n = checked_normal(spec, r_c, r_f);
    UserCrack out;
    crack_frame(spec, n, out);
    out.margin = user_crack_margin(r_c, r_f);
    CrackRegion g{spec.centre, out.t1, out.t2, spec.radius, out.margin, out.half ? -M_PI / 2 : 0.0,
                  out.half ? M_PI : 2 * M_PI, out.half, out.half ? "half-disk" : "disk"};
    // The region must reach into the object and have room for an interior node; the sheet is
    // meshed from an inner point out to the rim kept the margin inside the surface.
    const std::vector<Vec3> samples = inside_samples(g, object_distance);
    check_radius(g, r_c);
    out.inner_point = inner_point(g, surface, samples);
    const std::vector<Vec3> rim = sheet_rim(g, surface, out.inner_point, r_c);
    out.sheet = mesh_sheet(rim, g, surface, out.inner_point, r_c, name);
    out.recorded = recorded_fan(g, r_f);
    return out;
}

}  // namespace cf::initiate
