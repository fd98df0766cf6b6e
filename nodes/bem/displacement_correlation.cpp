#include "nodes/bem/displacement_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace cf::bem {

int front_edge_frame(const SurfaceMesh& cracks, int tri, int v0, int v1, Vec3& e1, Vec3& e2, Vec3& e3) {
    const Tri& t = cracks.triangles[tri];
    int third = -1;
    for (int v : t)
        if (v != v0 && v != v1) third = v;
    const Vec3 p0 = cracks.vertices[v0], p1 = cracks.vertices[v1];
    e2 = (cracks.vertices[t[1]] - cracks.vertices[t[0]]).cross(cracks.vertices[t[2]] - cracks.vertices[t[0]]).normalized();
    e1 = (p1 - p0).normalized().cross(e2);
    if (e1.dot(p0 - cracks.vertices[third]) < 0) e1 = -e1;
    e3 = e1.cross(e2);
    return third;
}

namespace {

// displacement_correlation_sifs' steps, in the order it calls them.

// The crack mesh's edges with their triangles, the front nodes (on an edge of one triangle) and
// the vertex adjacency.
struct CrackEdges {
    std::map<std::pair<int, int>, std::vector<int>> edge_tris;
    std::vector<char> front;
    std::vector<std::vector<int>> adjacent;
};

CrackEdges crack_edges(const SurfaceMesh& cracks) {
    CrackEdges c;
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = cracks.triangles[t][k], b = cracks.triangles[t][(k + 1) % 3];
            c.edge_tris[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
        }
    c.front.assign(cracks.num_vertices(), 0);
    for (const auto& e : c.edge_tris)
        if (e.second.size() == 1) c.front[e.first.first] = c.front[e.first.second] = 1;
    c.adjacent.resize(cracks.num_vertices());
    for (const auto& e : c.edge_tris) {
        c.adjacent[e.first.first].push_back(e.first.second);
        c.adjacent[e.first.second].push_back(e.first.first);
    }
    return c;
}

// The correlation node of a front triangle whose third node is itself on the front (an "ear" at
// a corner of the sheet): the interior node one edge away from the triangle's corners, behind the
// edge (v0, v1), closest to the perpendicular through the edge midpoint. Failing that (a corner
// of a coarse sheet), the interior node of the same crack nearest to the point one edge length
// behind the midpoint.
int ear_correlation_node(const SurfaceMesh& cracks, const CrackEdges& c, int tri, int v0, int v1, const Vec3& e1) {
    const Tri& t = cracks.triangles[tri];
    const Vec3 p0 = cracks.vertices[v0], p1 = cracks.vertices[v1];
    const Vec3 tang = (p1 - p0).normalized();
    const Vec3 mid = 0.5 * (p0 + p1);
    const double h = (p1 - p0).norm();
    double best = std::numeric_limits<double>::infinity();
    int interior = -1;
    for (int corner : t)
        for (int q : c.adjacent[corner]) {
            if (c.front[q]) continue;
            const Vec3 r = cracks.vertices[q] - mid;
            if (-r.dot(e1) < 0.1 * h) continue;
            const double lateral = std::abs(r.dot(tang));
            if (lateral < best) {
                best = lateral;
                interior = q;
            }
        }
    if (interior < 0) {
        const int region = cracks.region_of(tri);
        const Vec3 behind = mid - h * e1;
        for (std::size_t tt = 0; tt < cracks.num_triangles(); ++tt) {
            if (cracks.region_of(tt) != region) continue;
            for (int q : cracks.triangles[tt]) {
                if (c.front[q] || -(cracks.vertices[q] - mid).dot(e1) < 0.1 * h) continue;
                const double dist = (cracks.vertices[q] - behind).norm();
                if (dist < best) {
                    best = dist;
                    interior = q;
                }
            }
        }
    }
    if (interior < 0)
        throw std::invalid_argument("crack front triangle " + std::to_string(tri) +
                                    " has no interior node behind it; displacement correlation needs one "
                                    "(the crack sheet has no interior node)");
    return interior;
}

}  // namespace

std::vector<FrontEdgeSif> displacement_correlation_sifs(const SurfaceMesh& cracks, const std::vector<Vec3>& opening,
                                                        double E, double nu) {
    const CrackEdges c = crack_edges(cracks);
    const double mu = E / (2 * (1 + nu));
    std::vector<FrontEdgeSif> out;
    for (const auto& e : c.edge_tris) {
        if (e.second.size() != 1) continue;
        FrontEdgeSif s;
        s.v0 = e.first.first;
        s.v1 = e.first.second;
        Vec3 e1, n, e3;
        const int third = front_edge_frame(cracks, e.second[0], s.v0, s.v1, e1, n, e3);
        s.interior = c.front[third] ? ear_correlation_node(cracks, c, e.second[0], s.v0, s.v1, e1) : third;
        const Vec3 p0 = cracks.vertices[s.v0];
        const Vec3 q = cracks.vertices[s.interior];
        s.e1 = e1;
        s.e2 = n;
        s.e3 = e3;
        s.d = (p0 - q).dot(e1);
        const Vec3& du = opening[s.interior];
        const double f = mu * std::sqrt(2 * M_PI / s.d) / 4;
        s.KI = f * du.dot(s.e2) / (1 - nu);
        s.KII = f * du.dot(s.e1) / (1 - nu);
        s.KIII = f * du.dot(s.e3);
        out.push_back(s);
    }
    return out;
}

}  // namespace cf::bem
