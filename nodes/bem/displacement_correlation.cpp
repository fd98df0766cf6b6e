#include "nodes/bem/displacement_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace cf::bem {

std::vector<FrontEdgeSif> displacement_correlation_sifs(const SurfaceMesh& cracks, const std::vector<Vec3>& opening,
                                                        double E, double nu) {
    std::map<std::pair<int, int>, std::vector<int>> edge_tris;
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = cracks.triangles[t][k], b = cracks.triangles[t][(k + 1) % 3];
            edge_tris[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(t));
        }
    std::vector<char> front(cracks.num_vertices(), 0);
    for (const auto& e : edge_tris)
        if (e.second.size() == 1) front[e.first.first] = front[e.first.second] = 1;
    const double mu = E / (2 * (1 + nu));
    std::vector<FrontEdgeSif> out;
    for (const auto& e : edge_tris) {
        if (e.second.size() != 1) continue;
        const Tri& t = cracks.triangles[e.second[0]];
        FrontEdgeSif s;
        s.v0 = e.first.first;
        s.v1 = e.first.second;
        for (int v : t)
            if (v != s.v0 && v != s.v1) s.interior = v;
        if (front[s.interior])
            throw std::invalid_argument("crack front triangle " + std::to_string(e.second[0]) +
                                        " has no interior node; displacement correlation needs one node off the front");
        const Vec3 p0 = cracks.vertices[s.v0], p1 = cracks.vertices[s.v1], q = cracks.vertices[s.interior];
        const Vec3 n = (cracks.vertices[t[1]] - cracks.vertices[t[0]]).cross(cracks.vertices[t[2]] - cracks.vertices[t[0]]).normalized();
        const Vec3 tang = (p1 - p0).normalized();
        Vec3 e1 = tang.cross(n);
        if (e1.dot(p0 - q) < 0) e1 = -e1;
        s.e1 = e1;
        s.e2 = n;
        s.e3 = e1.cross(n);
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
