#pragma once
// Checks every generated shape must pass: closed, 2-manifold, outward, no degenerate triangles,
// every triangle in a named region.
#include "nodes/domain/mesh_topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace cf::testing {

inline void expect_closed_outward(const SurfaceMesh& m, long long euler_characteristic) {
    const MeshTopologyReport r = check_topology(m);
    EXPECT_TRUE(r.is_closed_manifold()) << r.describe();
    EXPECT_EQ(r.euler_characteristic, euler_characteristic);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.unreferenced_vertices, 0u);
    EXPECT_GT(signed_volume(m), 0);
    ASSERT_EQ(m.region.size(), m.num_triangles());
    for (int id : m.region) {
        ASSERT_GE(id, 0);
        ASSERT_LT(id, static_cast<int>(m.region_names.size()));
    }
}

inline double region_area(const SurfaceMesh& m, const std::string& name) {
    double a = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        if (m.region_name(m.region_of(t)) == name) a += triangle_area(m, t);
    return a;
}

inline std::size_t region_triangles(const SurfaceMesh& m, const std::string& name) {
    std::size_t n = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) n += m.region_name(m.region_of(t)) == name;
    return n;
}

inline double longest_edge(const SurfaceMesh& m) {
    double l = 0;
    for (const Tri& f : m.triangles)
        for (int k = 0; k < 3; ++k) l = std::max(l, (m.vertices[f[k]] - m.vertices[f[(k + 1) % 3]]).norm());
    return l;
}

// Smallest interior angle over all triangles [degrees].
inline double smallest_angle_degrees(const SurfaceMesh& m) {
    double smallest = 180;
    for (const Tri& f : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const Vec3 u = (m.vertices[f[(k + 1) % 3]] - m.vertices[f[k]]).normalized();
            const Vec3 v = (m.vertices[f[(k + 2) % 3]] - m.vertices[f[k]]).normalized();
            smallest = std::min(smallest, std::acos(std::clamp(u.dot(v), -1.0, 1.0)) * 180 / std::acos(-1.0));
        }
    return smallest;
}

}  // namespace cf::testing
