#pragma once
// A closed circular cylinder along z, tessellated as the inscribed regular prism: its volume is
// exactly (s/2) r^2 sin(2 pi / s) h for s segments.
#include "nodes/domain/surface_mesh.hpp"

namespace cf {

enum class CapStyle {
    Fan,    // one centre vertex joined to every rim vertex: s triangles per cap
    Rings,  // concentric rings on the rim's radial lines, a fan only in the innermost ring
};

struct CylinderSpec {
    double radius = 0.5;    // [m], > 0
    double height = 1;      // [m], > 0; the cylinder spans centre.z -/+ height/2
    Vec3 centre{0, 0, 0};   // [m]
    int segments = 32;      // vertices around the rim, >= 3
    int rings = 8;          // bands along the height, >= 1
    CapStyle caps = CapStyle::Fan;
    int cap_rings = 3;      // concentric bands per cap for CapStyle::Rings, >= 1
};

// Regions, in id order: side, top (+z), bottom (-z). Throws std::invalid_argument on bad specs.
SurfaceMesh make_cylinder(const CylinderSpec& spec);

}  // namespace cf
