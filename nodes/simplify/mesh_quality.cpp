#include "nodes/simplify/mesh_quality.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace cf {

namespace {
constexpr double kDeg = 180.0 / 3.14159265358979323846;

// Angle between u and v [degrees], robust for tiny and nearly parallel vectors (atan2 of
// |u x v| and u . v rather than acos).
double angle_deg(const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)) * kDeg; }

std::string point(const Vec3& p) {
    std::ostringstream os;
    os.precision(4);
    os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ") m";
    return os.str();
}
}  // namespace

double min_triangle_angle_deg(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, bc = c - b, ca = a - c;
    if (ab.squaredNorm() == 0 || bc.squaredNorm() == 0 || ca.squaredNorm() == 0) return 0;
    return std::min({angle_deg(ab, -ca), angle_deg(bc, -ab), angle_deg(ca, -bc)});
}

double dihedral_deg(const Vec3& n1, const Vec3& n2) {
    if (n1.squaredNorm() == 0 || n2.squaredNorm() == 0) return 0;
    return 180.0 - angle_deg(n1, n2);
}

MeshQuality measure_quality(const SurfaceMesh& m, double angle_bound, double dihedral_bound) {
    MeshQuality q;
    std::vector<Vec3> normal(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Tri& f = m.triangles[t];
        const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
        normal[t] = (b - a).cross(c - a);
        const double ang = min_triangle_angle_deg(a, b, c);
        if (ang < angle_bound) ++q.angles_below;
        if (ang < q.min_angle_deg) {
            q.min_angle_deg = ang;
            q.worst_triangle = t;
            q.worst_angle_at = (a + b + c) / 3;
        }
    }
    // Directed edge (a, b) -> triangle; the twin (b, a) is the neighbour across it.
    std::unordered_map<long long, int> half;
    half.reserve(3 * m.triangles.size());
    const auto key = [&](int a, int b) { return (long long)a * (long long)(m.vertices.size() + 1) + b; };
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) half[key(m.triangles[t][k], m.triangles[t][(k + 1) % 3])] = int(t);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
            if (a > b) continue;  // each edge once
            const auto it = half.find(key(b, a));
            if (it == half.end()) continue;
            const double d = dihedral_deg(normal[t], normal[it->second]);
            if (d < dihedral_bound) ++q.dihedrals_below;
            if (d < q.min_dihedral_deg) {
                q.min_dihedral_deg = d;
                q.worst_dihedral_at = 0.5 * (m.vertices[a] + m.vertices[b]);
            }
        }
    return q;
}

std::string describe(const MeshQuality& q) {
    std::ostringstream os;
    os.precision(3);
    os << "min angle " << q.min_angle_deg << " deg (triangle " << q.worst_triangle << " at " << point(q.worst_angle_at)
       << "), min dihedral " << q.min_dihedral_deg << " deg (edge at " << point(q.worst_dihedral_at) << ")";
    return os.str();
}

}  // namespace cf
