#include "nodes/bem/test_meshes.hpp"

#include <cmath>
#include <array>
#include <map>

namespace cf::bem {

SurfaceMesh bem_cube_mesh(int m, double L, const Vec3& centre) {
    SurfaceMesh mesh;
    mesh.region_names = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    std::map<std::array<long long, 3>, int> ids;
    auto node = [&](const Vec3& p) {
        std::array<long long, 3> key;
        for (int k = 0; k < 3; ++k) key[k] = std::llround(p[k] / L * 4096.0 * m);
        auto it = ids.find(key);
        if (it != ids.end()) return it->second;
        mesh.vertices.push_back(centre + p);
        return ids[key] = static_cast<int>(mesh.vertices.size() - 1);
    };
    for (int ax = 0; ax < 3; ++ax)
        for (int side = 0; side < 2; ++side) {
            const int a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
            auto P = [&](int i, int j) {
                Vec3 p;
                p[ax] = (side - 0.5) * L;
                p[a1] = (double(i) / m - 0.5) * L;
                p[a2] = (double(j) / m - 0.5) * L;
                return p;
            };
            for (int i = 0; i < m; ++i)
                for (int j = 0; j < m; ++j) {
                    const int q0 = node(P(i, j)), q1 = node(P(i + 1, j)), q2 = node(P(i + 1, j + 1)), q3 = node(P(i, j + 1));
                    // (a1, a2, ax) is right-handed, so q0 q1 q2 is CCW seen from +ax.
                    if (side == 1) {
                        mesh.triangles.push_back({q0, q1, q2});
                        mesh.triangles.push_back({q0, q2, q3});
                    } else {
                        mesh.triangles.push_back({q0, q2, q1});
                        mesh.triangles.push_back({q0, q3, q2});
                    }
                    mesh.region.push_back(2 * ax + side);
                    mesh.region.push_back(2 * ax + side);
                }
        }
    return mesh;
}

SurfaceMesh bem_icosphere_mesh(int level, double R) {
    SurfaceMesh mesh;
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p.normalize();
    std::vector<Tri> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                          {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                          {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back((v[a] + v[b]).normalized());
            return mid[key] = static_cast<int>(v.size() - 1);
        };
        std::vector<Tri> g;
        for (const Tri& x : f) {
            const int a = midpoint(x[0], x[1]), b = midpoint(x[1], x[2]), c = midpoint(x[2], x[0]);
            g.push_back({x[0], a, c});
            g.push_back({x[1], b, a});
            g.push_back({x[2], c, b});
            g.push_back({a, b, c});
        }
        f.swap(g);
    }
    for (auto& p : v) mesh.vertices.push_back(R * p);
    mesh.triangles = f;
    mesh.region.assign(f.size(), 0);
    mesh.region_names = {"surface"};
    return mesh;
}

SurfaceMesh bem_disk_mesh(int rings, double a, const Vec3& centre, double grade) {
    SurfaceMesh mesh;
    mesh.region_names = {"crack"};
    mesh.vertices.push_back(centre);
    std::vector<int> prev = {0};
    for (int i = 1; i <= rings; ++i) {
        const double rho = a * (1 - std::pow(1 - double(i) / rings, grade));
        const int n = 6 * i;
        std::vector<int> ring;
        for (int k = 0; k < n; ++k) {
            const double th = 2 * M_PI * k / n;
            mesh.vertices.push_back(centre + Vec3(rho * std::cos(th), rho * std::sin(th), 0));
            ring.push_back(static_cast<int>(mesh.vertices.size() - 1));
        }
        if (i == 1) {
            for (int k = 0; k < n; ++k) mesh.triangles.push_back({0, ring[k], ring[(k + 1) % n]});
        } else {
            // Zip the two rings by angle (both start at angle 0), CCW seen from +z.
            const int n0 = static_cast<int>(prev.size());
            int p = 0, q = 0;
            while (p < n0 || q < n) {
                const double ap = 2 * M_PI * (p + 1) / n0, aq = 2 * M_PI * (q + 1) / n;
                if (p < n0 && (q == n || ap < aq)) {
                    mesh.triangles.push_back({prev[p % n0], ring[q % n], prev[(p + 1) % n0]});
                    ++p;
                } else {
                    mesh.triangles.push_back({prev[p % n0], ring[q % n], ring[(q + 1) % n]});
                    ++q;
                }
            }
        }
        prev = ring;
    }
    mesh.region.assign(mesh.triangles.size(), 0);
    return mesh;
}

}  // namespace cf::bem
