#include "nodes/shape/box.hpp"

#include "graph/diagnostics.hpp"

#include <array>
#include <unordered_map>
#include <stdexcept>

namespace cf {

SurfaceMesh make_box(const BoxSpec& spec) {
    for (int a = 0; a < 3; ++a)
        if (!(spec.size[a] > 0))
            throw std::invalid_argument("parameter 'size': every edge length must be > 0 m, got " +
                                        graph::format_quantity(spec.size[a], "m") + " for axis " + "xyz"[a]);
    if (spec.subdivisions < 1)
        throw std::invalid_argument("parameter 'subdivisions' must be >= 1, got " + std::to_string(spec.subdivisions));

    const int n = spec.subdivisions;
    const Vec3 lo = spec.centre - 0.5 * spec.size;
    SurfaceMesh m;
    m.region_names = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    // Vertices live on the integer lattice {0..n}^3; welding by lattice index makes faces share
    // their edge and corner vertices exactly.
    std::unordered_map<long long, int> index_of;
    index_of.reserve(6 * std::size_t(n) * n + 2);
    auto vertex = [&](const std::array<int, 3>& ijk) {
        const long long key = (static_cast<long long>(ijk[0]) * (n + 1) + ijk[1]) * (n + 1) + ijk[2];
        auto [it, inserted] = index_of.emplace(key, static_cast<int>(m.vertices.size()));
        if (inserted) {
            Vec3 p;
            for (int a = 0; a < 3; ++a) p[a] = ijk[a] == n ? lo[a] + spec.size[a] : lo[a] + spec.size[a] * ijk[a] / n;
            m.vertices.push_back(p);
        }
        return it->second;
    };

    for (int axis = 0; axis < 3; ++axis) {
        // (u, v, axis) is a right-handed frame, so a quad walked +u then +v faces +axis.
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            const int region = 2 * axis + side;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    auto corner = [&](int di, int dj) {
                        std::array<int, 3> ijk{};
                        ijk[axis] = side * n;
                        ijk[u] = i + di;
                        ijk[v] = j + dj;
                        return vertex(ijk);
                    };
                    const int p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1), p01 = corner(0, 1);
                    if (side == 1) {
                        m.triangles.push_back({p00, p10, p11});
                        m.triangles.push_back({p00, p11, p01});
                    } else {  // the min face looks the other way: reverse the winding
                        m.triangles.push_back({p00, p11, p10});
                        m.triangles.push_back({p00, p01, p11});
                    }
                    m.region.push_back(region);
                    m.region.push_back(region);
                }
        }
    }
    return m;
}

}  // namespace cf
