#pragma once
// Small closed meshes built in the tests (independent of nodes/shape).
#include "nodes/domain/surface_mesh.hpp"

namespace cf::testmesh {

// Axis-aligned box [lo, hi], 12 outward-oriented triangles.
inline SurfaceMesh box(const Vec3& lo, const Vec3& hi) {
    SurfaceMesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
    const int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

// Union of two disjoint meshes.
inline SurfaceMesh merge(const SurfaceMesh& a, const SurfaceMesh& b) {
    SurfaceMesh m = a;
    const int off = int(a.vertices.size());
    m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (Tri t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    return m;
}

}  // namespace cf::testmesh
