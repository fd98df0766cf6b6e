#pragma once
// An axis-aligned box whose six faces are uniform grids of triangles: n cells along every edge, or,
// with a cell size, about that size along each axis (slender boxes get square-ish cells).
#include "nodes/domain/surface_mesh.hpp"

#include <array>

namespace cf {

struct BoxSpec {
    Vec3 size{1, 1, 1};      // edge lengths along x, y, z [m], each > 0
    Vec3 centre{0, 0, 0};    // [m]
    int subdivisions = 4;    // grid cells per edge (same count on every edge), >= 1
    double cell_size = 0;    // > 0: round(size / cell_size) cells along each axis (at least 1) instead [m]
};

// Cells along x, y, z for `spec` (subdivisions, or from cell_size).
std::array<int, 3> box_cells(const BoxSpec& spec);

// Regions, in id order: x_min, x_max, y_min, y_max, z_min, z_max (the face whose outward normal
// is -x, +x, ...). Vertices on shared edges and corners are shared, so the surface is closed.
// Throws std::invalid_argument for a non-positive size, subdivisions < 1, a negative cell size, or
// more than 1e6 triangles.
SurfaceMesh make_box(const BoxSpec& spec);

}  // namespace cf
