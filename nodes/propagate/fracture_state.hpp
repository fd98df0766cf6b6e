#pragma once
// The state a fracture simulation carries from one BEM time step to the next (thesis ch. 4.1):
// the coarse crack sheets the BEM sees, every crack front with its fine-resolution markers, the
// fine crack level sets, and the bookkeeping of initiation. It is the loop variable of a fracture
// pipeline: initiate.* nodes append cracks, propagate.fronts moves the fronts, records the swept
// surfaces and grows the sheets. Immutable once published; nodes copy and modify.
#include "graph/value.hpp"
#include "nodes/bem/estimated_growth.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/propagate/front_markers.hpp"

#include <string>
#include <vector>

namespace cf::propagate {

struct FrontState {
    CrackFront front;      // coarse front: vertex ids in FractureState::cracks, SIFs/frames of the last BEM step
    FrontMarkers markers;  // fine front; empty until the front's first propagation
    bool fresh = true;     // not propagated yet: markers are placed and the first sub-step is planar (ch. 4.5.2)
};

struct FractureState {
    double r_c = 0;                  // coarse (BEM) crack edge length [m]
    double r_f = 0;                  // level-set voxel size = marker spacing [m]
    SurfaceMesh cracks;              // BEM crack sheets; region r is crack r
    std::vector<FrontState> fronts;  // every front of every crack, in the order the cracks were added
    CrackLevelSets grids;            // grids.cracks[r]: crack r's thickened swept surface (ch. 6.2)
    std::vector<char> initiated;     // per ordinary-surface element: already initiated a crack (ch. 4.4 b)
    int step = 0;                    // BEM time steps completed
    int cracks_initiated = 0;        // cracks added by stress-based initiation (user-given ones not counted)
    std::size_t elements_added = 0;  // crack triangles added in the last step (initiation and growth)
    bem::CrackOpeningEstimate openings;  // eq. (5.5)-(5.6) for nodes fronts left behind (used once growth is estimated)

    int num_cracks() const { return static_cast<int>(grids.cracks.size()); }
    bool has_active_markers() const;  // some front is fresh or has an active marker
};

// Starts a state for an object whose ordinary BEM surface has `surface_elements` triangles.
// Throws std::invalid_argument unless 0 < r_f < r_c (parameter names in the message).
FractureState start_fracture_state(double r_c, double r_f, double half_width, std::size_t surface_elements);

// Appends a crack: `sheet` (an open triangle sheet with at least one interior node, strictly
// inside the body) joins the BEM crack mesh as a new region, its fronts become fresh fronts, and
// `recorded` (the fine surface of the crack, e.g. the sheet itself, or a larger surface reaching
// through the object's boundary for an edge crack) is recorded into a new crack grid.
// Existing vertices and triangles are untouched (append-only BEM assembly). Returns the region.
// Throws std::invalid_argument when the sheet is empty or has no interior node.
int add_crack(FractureState& state, const SurfaceMesh& sheet, const std::vector<Triangle3>& recorded);

// Per crack vertex: 1 for the nodes of fronts that have not propagated yet and for both nodes of
// every front edge with an active marker (marker k of edge i is index i n + k), else 0.
std::vector<char> moving_front_nodes(const FractureState& state);

// Triangles of a mesh as geometry (e.g. to record a sheet).
std::vector<Triangle3> mesh_triangles(const SurfaceMesh& m);

}  // namespace cf::propagate

CF_GRAPH_TYPE(cf::propagate::FractureState, "FractureState");
