#pragma once
// High-resolution crack-front markers (thesis ch. 4.5.2): n = ceil(r_c / r_f) markers per front
// edge, kept equally spaced along the polyline they form; SIFs and frames are interpolated from
// the front nodes by marker index (geometry-agnostic, as the spacing is uniform).
#include "nodes/propagate/crack_front.hpp"
#include "nodes/propagate/marker_motion.hpp"

#include <vector>

namespace cf::propagate {

// n = ceil(r_c / r_f) (at least 1). Throws std::invalid_argument for non-positive sizes.
int markers_per_edge(double r_c, double r_f);

struct FrontMarkers {
    bool closed = true;
    int per_edge = 1;                  // n
    std::vector<MarkerState> markers;  // marker i*n sits at front node i when placed
    std::vector<Vec3> positions() const;
};

// Markers of one front: on edge i (node i -> node i+1) marker k = 0..n-1 at
// x_i + (k/n)(x_{i+1} - x_i) (the thesis' k = 1..n with (k-1)/n); an open front adds its last
// node. States are interpolated from the front (see interpolate_front_state).
FrontMarkers place_markers(const CrackFront& front, const SurfaceMesh& cracks, int per_edge);

// Interpolates node SIFs and frames to markers by index: marker k of edge ij gets
// K = (n-k)/n K_i + k/n K_j, and n1, n3 likewise, normalised, n2 = n3 x n1 (ch. 4.5.2).
// With keep_history the markers' current SIFs become K_old first (a BEM update).
// Throws std::invalid_argument when the counts of markers, nodes, SIFs or frames disagree.
void interpolate_front_state(FrontMarkers& markers, const CrackFront& front, bool keep_history);

// `count` points equally spaced by arc length along the polyline `pts` (closed: a loop),
// starting at arc length `start` (closed) or spanning first to last point (open).
std::vector<Vec3> resample_polyline(const std::vector<Vec3>& pts, bool closed, std::size_t count, double start = 0);
double polyline_length(const std::vector<Vec3>& pts, bool closed);

// One forward-Euler sub-step of all markers (in parallel, independent of thread count), then
// the markers slide back to equal spacing along their polyline. `substep` = 0..n_substeps-1
// sets the blend weight of eq. (4.12); `planar` forces straight motion (first sub-step of a new
// crack). Returns the largest marker displacement [m].
double advance_markers(FrontMarkers& markers, const ScalarField& toughness, const PropagationSettings& settings,
                       int substep, int n_substeps, bool planar);

}  // namespace cf::propagate
