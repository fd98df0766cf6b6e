#pragma once
// Incomplete cracks of a fragment (thesis ch. 7.3, fig. 43): when a body breaks, a crack that did
// not separate it stays inside a large fragment; the fragment's fracture state carries the part of
// its BEM sheet that lies inside the fragment, so the crack can grow again in a later collision.
// The kept sheet is a subset of the parent's triangles, made a manifold with boundary (exactly two
// front edges at every front node) by adding the 1-ring of pinched front nodes, with no triangle
// whose three nodes are front nodes (it would carry no opening unknown). Fronts keep their fine
// markers where they coincide with the parent's; where the fragment cut the crack they are stopped.
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_state.hpp"

#include <cstddef>

namespace cf::propagate {

struct FragmentCracks {
    FractureState state;            // the fragment's state: its incomplete cracks, or no cracks
    std::size_t kept_triangles = 0;     // parent crack triangles in the fragment's state
    std::size_t dropped_triangles = 0;  // parent crack triangles left out
    std::size_t ring_triangles = 0;     // of the kept ones: added as the 1-ring of a pinched front node
};

struct FragmentCrackSettings {
    // Smallest distance [m] from a kept crack triangle to the fragment's BEM surface; negative:
    // max(r_f, 0.05 r_c), the margin user-given crack sheets keep from the ordinary surface
    // (initiate::user_crack_margin). The BEM only rejects touching triangles; this keeps the
    // nearly singular surface-crack pairs no closer than the parent run's own stopped fronts
    // (surface_margin r_f inside the level set, whose BEM surface is offset r_f outward).
    double clearance = -1;
};

// parent: the final state of the fracture run that broke the body (the body's material frame).
// fragment: the fragment's level set from segment.fragments (voxel size parent.r_f); incomplete
//           cracks are thin slits (positive values) in it, so a crack triangle is inside when the
//           fragment has material on both sides of the sheet (see fragment_cracks.cpp).
// surface: the fragment's new ordinary BEM surface (closed, outward), same frame.
// A parent triangle is kept when, at its vertices and centroid, the fragment is at least r_f deep
// on both sides of the sheet, and it lies inside `surface` at least the clearance from it. A
// triangle of the 1-ring of a pinched front node is added when it is inside the fragment at all
// and clear of the surface (else the node's triangles are removed). The result has step 0, no
// known openings, `initiated` sized to the surface (all 0), grids of the cracks that keep a
// triangle, regions renumbered 0..n-1 in the parent's order. Deterministic.
// Fronts: a loop made only of one parent front's edges is that front unchanged (markers, SIFs,
// `fresh`). Any other loop is not fresh and has no SIFs yet (the next step assigns them); its
// edges keep the parent's markers, except that edges of a fresh parent front get active markers
// on the coarse edge (as place_markers puts them; the planar first sub-step is lost) and edges
// where the fragment cut the crack get stopped ones.
// Caller: the fragment's segmentation grid has these cracks cut in, so it must not be the `object`
// of the fragment's next fracture run as is: test (a) of fig. 27 reads the slit ahead of a front as
// outside and stops its markers in the first sub-step.
// Throws std::invalid_argument for a voxel-size mismatch, an empty fragment grid, a surface that
// is not closed and outward, or a parent state whose meshes, fronts and markers disagree.
FragmentCracks restrict_to_fragment(const FractureState& parent, const LevelSet& fragment, const SurfaceMesh& surface,
                                    const FragmentCrackSettings& settings = {});

// The clearance `settings` gives for these resolutions [m].
double fragment_crack_clearance(double r_c, double r_f, const FragmentCrackSettings& settings = {});

}  // namespace cf::propagate
