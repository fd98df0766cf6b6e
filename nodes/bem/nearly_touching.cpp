#include "nodes/bem/nearly_touching.hpp"

#include "nodes/bem/surface_intersection.hpp"
#include "nodes/domain/triangle_closest_point.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cf::bem {

namespace {

// Closest points of segments [p0, p1] and [q0, q1]: the parameters minimising |p(s) - q(t)| over
// the unit square, by clamping each in turn (the usual construction for the closed segments).
void closest_segment_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3& x, Vec3& y) {
    const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    double s = 0, t = 0;
    if (a <= 0 && e <= 0) {
        s = t = 0;
    } else if (a <= 0) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = d1.dot(r);
        if (e <= 0) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = d1.dot(d2), denom = a * e - b * b;
            s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = std::clamp(-c / a, 0.0, 1.0);
            } else if (t > 1) {
                t = 1;
                s = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    x = p0 + s * d1;
    y = q0 + t * d2;
}

}  // namespace

double triangle_distance(const ElementGeometry& a, const ElementGeometry& b, Vec3* midpoint) {
    if (triangles_intersect(a, b)) {
        if (midpoint) *midpoint = 0.5 * (a.centroid + b.centroid);
        return 0;
    }
    // Apart, the closest points are a vertex and a point of the other triangle, or two edge points.
    double best = std::numeric_limits<double>::infinity();
    Vec3 x = a.p[0], y = b.p[0];
    auto consider = [&](const Vec3& p, const Vec3& q) {
        const double d2 = (p - q).squaredNorm();
        if (d2 < best) {
            best = d2;
            x = p;
            y = q;
        }
    };
    for (int k = 0; k < 3; ++k) {
        consider(a.p[k], closest_point_on_triangle(a.p[k], b.p[0], b.p[1], b.p[2]).point);
        consider(b.p[k], closest_point_on_triangle(b.p[k], a.p[0], a.p[1], a.p[2]).point);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            Vec3 p, q;
            closest_segment_points(a.p[i], a.p[(i + 1) % 3], b.p[j], b.p[(j + 1) % 3], p, q);
            consider(p, q);
        }
    if (midpoint) *midpoint = 0.5 * (x + y);
    return std::sqrt(best);
}

NearlyTouchingPair nearly_touching_pair(const std::vector<ElementGeometry>& g) {
    NearlyTouchingPair out;
    double best = std::numeric_limits<double>::infinity();
    // Each triangle lies within `reach` of its centroid: a pair whose centroids are farther apart
    // than the sum plus best * size cannot beat the best ratio so far.
    std::vector<double> reach(g.size(), 0);
    for (std::size_t i = 0; i < g.size(); ++i)
        for (const Vec3& p : g[i].p) reach[i] = std::max(reach[i], (p - g[i].centroid).norm());
    for (std::size_t i = 0; i < g.size(); ++i)
        for (std::size_t j = i + 1; j < g.size(); ++j) {
            const Tri& u = g[i].nodes;
            const Tri& v = g[j].nodes;
            bool shared = false;
            for (int x : u) shared = shared || x == v[0] || x == v[1] || x == v[2];
            if (shared) continue;
            const double size = std::max(g[i].diameter, g[j].diameter);
            if ((g[i].centroid - g[j].centroid).norm() - reach[i] - reach[j] >= best * size) continue;
            Vec3 mid;
            const double gap = triangle_distance(g[i], g[j], &mid);
            if (gap / size < best) {
                best = gap / size;
                out = {true, int(i), int(j), gap, size, mid};
            }
        }
    return out;
}

namespace {

std::string num(double v) {  // three significant digits are enough to find the place
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
}

}  // namespace

std::string describe_worst_row(const std::vector<ElementGeometry>& g, int element, double residual, double residual_limit) {
    if (element < 0 || static_cast<std::size_t>(element) >= g.size() || !(residual >= residual_limit)) return "";
    const ElementGeometry& e = g[element];
    // The edge neighbour whose normal turns furthest from this one's: the fold's inner angle is 180 degrees
    // minus the angle between the normals.
    int fold = -1;
    double fold_cos = 2;
    for (std::size_t b = 0; b < g.size(); ++b) {
        if (static_cast<int>(b) == element) continue;
        int shared = 0;
        for (int i : e.nodes)
            for (int j : g[b].nodes) shared += i == j;
        if (shared != 2) continue;
        const double c = e.normal.dot(g[b].normal);
        if (c < fold_cos) {
            fold_cos = c;
            fold = static_cast<int>(b);
        }
    }
    const Vec3& w = e.centroid;
    std::string out = "triangle " + std::to_string(element) + " at (" + num(w.x()) + ", " + num(w.y()) + ", " + num(w.z()) +
                      ") m, whose row of the double layer misses the rigid translations by " + num(residual) +
                      " (a well-shaped surface: about 1e-4)";
    if (fold >= 0) {
        const double inner = 180 - std::acos(std::clamp(fold_cos, -1.0, 1.0)) * 180 / M_PI;
        out += ", folds at " + num(inner) + " degrees against triangle " + std::to_string(fold);
    }
    const double sliver = e.area / (0.25 * std::sqrt(3.0) * e.diameter * e.diameter);  // 1 for equilateral
    out += " and has " + num(sliver) + " of an equilateral triangle's area for its longest edge";
    return out;
}

std::string describe_nearly_touching(const std::vector<ElementGeometry>& g, double ratio_limit) {
    const NearlyTouchingPair p = nearly_touching_pair(g);
    if (!p.found || p.ratio() >= ratio_limit) return "";
    const Vec3& w = p.where;
    return "triangles " + std::to_string(p.a) + " and " + std::to_string(p.b) + " share no vertex but lie " + num(p.gap) +
           " m apart at (" + num(w.x()) + ", " + num(w.y()) + ", " + num(w.z()) + ") m, " + num(p.ratio()) +
           " of their size (" + num(p.size) +
           " m): too close for their integrals (a fold or a thin gap of the mesh). Remesh with more, smaller triangles "
           "(simplify.remesh target_triangles; lib/surface.yaml 'triangles') or open the gap";
}

}  // namespace cf::bem
