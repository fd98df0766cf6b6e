#include "nodes/shape/box.hpp"

#include "graph/diagnostics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <stdexcept>

namespace cf {

std::array<int, 3> box_cells(const BoxSpec& spec) {
    if (spec.cell_size < 0 || !std::isfinite(spec.cell_size))
        throw std::invalid_argument("parameter 'cell_size' must be >= 0 m (0: use 'subdivisions'), got " +
                                    graph::format_quantity(spec.cell_size, "m"));
    std::array<int, 3> n{spec.subdivisions, spec.subdivisions, spec.subdivisions};
    if (spec.cell_size > 0) {
        for (int a = 0; a < 3; ++a) {
            const double cells = std::round(spec.size[a] / spec.cell_size);
            if (!(cells <= 1e6))
                throw std::invalid_argument("parameter 'cell_size' is too small for the box: " + graph::format_number(cells) +
                                            " cells along " + "xyz"[a] + "; raise it");
            n[a] = std::max(1, static_cast<int>(cells));
        }
    }
    return n;
}

SurfaceMesh make_box(const BoxSpec& spec) {
    for (int a = 0; a < 3; ++a)
        if (!(spec.size[a] > 0))
            throw std::invalid_argument("parameter 'size': every edge length must be > 0 m, got " +
                                        graph::format_quantity(spec.size[a], "m") + " for axis " + "xyz"[a]);
    if (spec.subdivisions < 1)
        throw std::invalid_argument("parameter 'subdivisions' must be >= 1, got " + std::to_string(spec.subdivisions));

    const std::array<int, 3> n = box_cells(spec);
    const double triangles = 4.0 * (double(n[0]) * n[1] + double(n[1]) * n[2] + double(n[2]) * n[0]);
    if (triangles > 1e6)
        throw std::invalid_argument("the box would have " + std::to_string(static_cast<long long>(triangles)) +
                                    " triangles (more than 1e6); lower 'subdivisions' or raise 'cell_size'");
    const Vec3 lo = spec.centre - 0.5 * spec.size;
    SurfaceMesh m;
    m.region_names = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    // Vertices live on the integer lattice {0..n_x} x {0..n_y} x {0..n_z}; welding by lattice index
    // makes faces share their edge and corner vertices exactly.
    std::unordered_map<long long, int> index_of;
    index_of.reserve(static_cast<std::size_t>(triangles / 2) + 2);
    auto vertex = [&](const std::array<int, 3>& ijk) {
        const long long key = (static_cast<long long>(ijk[0]) * (n[1] + 1) + ijk[1]) * (n[2] + 1) + ijk[2];
        auto [it, inserted] = index_of.emplace(key, static_cast<int>(m.vertices.size()));
        if (inserted) {
            Vec3 p;
            for (int a = 0; a < 3; ++a)
                p[a] = ijk[a] == n[a] ? lo[a] + spec.size[a] : lo[a] + spec.size[a] * ijk[a] / n[a];
            m.vertices.push_back(p);
        }
        return it->second;
    };

    for (int axis = 0; axis < 3; ++axis) {
        // (u, v, axis) is a right-handed frame, so a quad walked +u then +v faces +axis.
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            const int region = 2 * axis + side;
            for (int i = 0; i < n[u]; ++i)
                for (int j = 0; j < n[v]; ++j) {
                    auto corner = [&](int di, int dj) {
                        std::array<int, 3> ijk{};
                        ijk[axis] = side * n[axis];
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
