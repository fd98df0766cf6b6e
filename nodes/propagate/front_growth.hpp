#pragma once
// New crack elements after n sub-steps (thesis ch. 4.5.2, fig. 16): each front node moves to the
// mean of the n markers centred on it; the surface swept by a front edge is triangulated by one
// of three cases so new front edges stay within (0.2 r_c, 1.4 r_c):
//   (a) in range: two triangles (one if only one node moved);
//   (b) too long: a node is inserted at the mean of the n + 1 markers spanning the edge (centred
//       on its middle), three triangles (two if only one node moved);
//   (c) too short (both nodes moved): the two new nodes merge into one, one triangle.
// Existing vertices and triangles are never changed: the result appends to the crack mesh.
// Nodes whose new triangles would be inverted or slivers (near the object's surface, where some
// markers stopped and others slid along the front) do not move this step.
#include "nodes/propagate/front_markers.hpp"

#include <functional>

namespace cf::propagate {

struct GrowthSettings {
    double r_c = 0;            // target BEM edge length [m]
    double min_factor = 0.2;   // contract new front edges at or below min_factor r_c
    double max_factor = 1.4;   // split new front edges at or above max_factor r_c
    // New triangles must not fold back: quality 4 sqrt(3) area / sum(edge^2) (1 = equilateral) at
    // least min_quality, and normal within acos(min_normal_dot) of the old front triangle's.
    // A node whose triangles fail stays on the front this step (its markers keep advancing).
    double min_quality = 0.1;
    double min_normal_dot = 0.2;
    // Where a new BEM node may go (empty: anywhere). The fracture loop rejects points closer to
    // the ordinary surface or another crack than the BEM quadrature tolerates; a node whose
    // target is rejected stays on the front, a split whose midpoint is rejected is not made.
    std::function<bool(const Vec3&)> admissible;
    // Whether a point lies inside the object (empty: everywhere). Every new triangle is sampled on
    // a barycentric lattice (spacing 1/4) away from its corners; a triangle with a sample outside
    // crosses a concave part of the surface (a notch between two admissible nodes) and is undone
    // like a folded one: its new nodes stay on the front this step.
    std::function<bool(const Vec3&)> inside;
    // Whether a new triangle (corners a, b, c) touches or crosses the ordinary BEM surface (empty:
    // never). The BEM surface stands off the object's surface by up to half a voxel inwards between
    // its sample points, so a triangle inside the object by the lattice test can still cut it where
    // a small fragment is thin or concave; the assembly would refuse it (sgbem-math §2), so it is
    // undone like a folded one.
    std::function<bool(const Vec3&, const Vec3&, const Vec3&)> crosses_surface;
};

struct FrontGrowth {
    CrackFront front;       // the new front (node ids in the grown mesh; SIFs/frames empty)
    FrontMarkers markers;   // markers re-sampled to n per new edge; K moved to K_old
    std::size_t added_vertices = 0, added_triangles = 0;
    int kept = 0, split = 0, contracted = 0;  // front edges by case (a), (b), (c)
};

// Appends the triangles swept by `front` (whose markers have moved) to `cracks`. A node whose
// window mean lies less than min_factor r_c from the node does not propagate this step (its
// markers keep advancing and it moves in a later step). New triangles take the front's region
// and the orientation of the sheet. Throws std::invalid_argument when the markers do not
// belong to the front (counts disagree) or r_c <= 0.
FrontGrowth grow_front(SurfaceMesh& cracks, const CrackFront& front, const FrontMarkers& markers,
                       const GrowthSettings& settings);

}  // namespace cf::propagate
