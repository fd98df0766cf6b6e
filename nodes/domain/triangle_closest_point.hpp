#pragma once
// The closest point of a triangle to a point: the one copy every stage uses (initiation's
// distance to the surface, the crack-grid rasteriser of levelset/, interior evaluation in bem/,
// the fragment-mesh deformation grid of segment/, fragment cracks in propagate/, impact loads).
// By the Voronoi regions of the vertices, edges and face (C. Ericson, "Real-Time Collision
// Detection", Morgan Kaufmann, 2005, section 5.1.5). Inline: the rasteriser calls it for every
// voxel in a triangle's band. SI units (metres).
#include "nodes/domain/surface_mesh.hpp"

#include <algorithm>

namespace cf {

// Which part of the triangle holds the closest point.
enum class TriangleFeature { vertex_a, vertex_b, vertex_c, edge_ab, edge_bc, edge_ca, face };

struct TriangleClosestPoint {
    Vec3 point = Vec3::Zero();        // the closest point [m]
    Vec3 barycentric = Vec3::Zero();  // its weights of a, b, c: each in [0, 1], sum 1
    double distance2 = 0;             // squared distance from the query point [m^2]
    TriangleFeature feature = TriangleFeature::face;
};

struct SegmentClosestPoint {
    Vec3 point = Vec3::Zero();  // a + s (b - a) [m]
    double s = 0;               // in [0, 1]; 0 for a segment of zero length
    double distance2 = 0;       // [m^2]
};

// Closest point of segment [a, b] to p.
inline SegmentClosestPoint closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double l2 = ab.squaredNorm();
    const double s = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return {a + s * ab, s, (p - a - s * ab).squaredNorm()};
}

// Closest point of the three edges of triangle (a, b, c) to p; on a tie the first of ab, bc, ca.
// What a triangle of zero area is: its edges (a collapsed edge, or one point three times).
inline TriangleClosestPoint closest_point_on_triangle_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3* corner[3] = {&a, &b, &c};
    const TriangleFeature edge[3] = {TriangleFeature::edge_ab, TriangleFeature::edge_bc, TriangleFeature::edge_ca};
    TriangleClosestPoint best;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        const SegmentClosestPoint q = closest_point_on_segment(p, *corner[i], *corner[j]);
        if (i > 0 && !(q.distance2 < best.distance2)) continue;
        best.point = q.point;
        best.barycentric = Vec3::Zero();
        best.barycentric[i] = 1 - q.s;
        best.barycentric[j] = q.s;
        best.distance2 = q.distance2;
        best.feature = edge[i];
    }
    return best;
}

// Whether a triangle is too flat for the face formulas below: twice its area at most 1e-12 of its
// longest edge squared (collinear corners, a collapsed edge, three equal points, or a sliver
// flatter than rounding resolves). BEM meshes never hold one (their elements need an area above
// 1e-12 diameter^2); crack strips do, where a stopped marker meets a moving one.
inline bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a);
    const double scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    return n.squaredNorm() <= 1e-24 * scale * scale || scale == 0;
}

// Closest point of a triangle that is not degenerate (is_degenerate_triangle false), by the
// regions of its vertices, edges and face; for callers that test each triangle once and query it
// many times (the rasteriser). Its face formulas would divide by about zero on a degenerate one.
inline TriangleClosestPoint closest_point_on_nondegenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    using F = TriangleFeature;
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return {a, Vec3(1, 0, 0), ap.squaredNorm(), F::vertex_a};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return {b, Vec3(0, 1, 0), bp.squaredNorm(), F::vertex_b};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {a + v * ab, Vec3(1 - v, v, 0), (ap - v * ab).squaredNorm(), F::edge_ab};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return {c, Vec3(0, 0, 1), cp.squaredNorm(), F::vertex_c};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {a + w * ac, Vec3(1 - w, 0, w), (ap - w * ac).squaredNorm(), F::edge_ca};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        const Vec3 bc = c - b;
        return {b + w * bc, Vec3(0, 1 - w, w), (bp - w * bc).squaredNorm(), F::edge_bc};
    }
    const double sum = va + vb + vc;  // |ab x ac|^2 (Lagrange's identity)
    if (!(sum > 0)) return closest_point_on_triangle_edges(p, a, b, c);
    const double denom = 1 / sum;
    const double v = vb * denom, w = vc * denom;
    return {a + ab * v + ac * w, Vec3(1 - v - w, v, w), (ap - ab * v - ac * w).squaredNorm(), F::face};
}

// Closest point of triangle (a, b, c) to p, with its barycentric weights, squared distance and
// feature. Any triangle is accepted: a degenerate one (is_degenerate_triangle) answers with its
// closest edge, never NaN.
inline TriangleClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    return is_degenerate_triangle(a, b, c) ? closest_point_on_triangle_edges(p, a, b, c)
                                           : closest_point_on_nondegenerate_triangle(p, a, b, c);
}

}  // namespace cf
