#pragma once
// The notched bar of the 3-point-bending test (thesis fig. 19 and 35): a long box with a notch
// across the middle of its bottom face, resting on two support strips near its ends and loaded
// on a strip at the top centre.
#include "nodes/domain/surface_mesh.hpp"

namespace cf {

enum class NotchShape {
    V,            // a triangular groove: apex notch_depth above the bottom face
    Rectangular,  // a slot with vertical walls and a flat ceiling
};

struct NotchedBarSpec {
    double length = 0.4;         // along x [m]
    double height = 0.1;         // along z [m]
    double depth = 0.05;         // along y [m]
    Vec3 centre{0, 0, 0};        // [m]
    NotchShape notch = NotchShape::V;
    double notch_width = 0.01;   // x extent of the notch opening in the bottom face [m], < length
    double notch_depth = 0.03;   // z extent of the notch [m], < height
    double support_span = 0.32;  // distance between the centres of the two support strips [m]
    double strip_width = 0.02;   // x width of each support strip and of the load strip [m]
    double resolution = 0.01;    // target edge length [m]
};

// The bar spans centre -/+ (length, depth, height)/2 and has the notch at x = centre.x, running
// through the whole depth. Regions, in id order: rest, support_left, support_right (bottom-face
// strips centred at x = -/+ support_span/2), load (top-face strip centred at x = 0), notch (all
// notch faces). Strip and notch edges are mesh lines, so every region is represented exactly.
// The mesh is mirror-symmetric in x (left of the notch mirrors right).
// Throws std::invalid_argument naming the parameter when the dimensions do not fit together.
SurfaceMesh make_notched_bar(const NotchedBarSpec& spec);

}  // namespace cf
