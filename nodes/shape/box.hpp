#pragma once
// An axis-aligned box whose six faces are uniform grids of 2*n*n triangles each.
#include "nodes/domain/surface_mesh.hpp"

namespace cf {

struct BoxSpec {
    Vec3 size{1, 1, 1};      // edge lengths along x, y, z [m], each > 0
    Vec3 centre{0, 0, 0};    // [m]
    int subdivisions = 4;    // grid cells per edge (same count on every edge), >= 1
};

// Regions, in id order: x_min, x_max, y_min, y_max, z_min, z_max (the face whose outward normal
// is -x, +x, ...). Vertices on shared edges and corners are shared, so the surface is closed.
// Throws std::invalid_argument for a non-positive size or subdivisions < 1.
SurfaceMesh make_box(const BoxSpec& spec);

}  // namespace cf
