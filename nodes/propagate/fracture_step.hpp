#pragma once
// One BEM time step of crack propagation (thesis ch. 4.5.2, fig. 14): SIFs from the BEM (or an
// estimator) are averaged to the coarse front nodes and interpolated to the fine markers; the
// markers advance by n forward-Euler sub-steps, each followed by the geometry tests of fig. 27
// and the recording of the swept strip (ch. 6.2); finally the coarse crack sheets grow by the
// triangles of fig. 16. Plain C++; the propagate.fronts node wraps it.
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/fields/scalar_field.hpp"
#include "nodes/propagate/fracture_state.hpp"
#include "nodes/propagate/front_growth.hpp"

#include <functional>

namespace cf::propagate {

struct StepSettings {
    PropagationSettings law;      // E, nu, rho, r_c, r_f (r_c, r_f are taken from the state)
    int substeps = 0;             // sub-steps per BEM step; 0: n = ceil(r_c / r_f) (ch. 4.5.2)
    double surface_margin = 0;    // new BEM nodes stay at least this deep inside the object [m]
    double crack_margin = 0;      // ... and this far outside other cracks' recorded volumes [m]
    // The ordinary BEM surface the next assembly solves on (may be null): new crack triangles that
    // touch or cross it are held back this step (front_growth.hpp, crosses_surface).
    const SurfaceMesh* bem_surface = nullptr;
};

struct StepReport {
    int fronts_propagated = 0;       // fronts that had SIFs and active markers
    int fronts_waiting = 0;          // fronts without SIFs yet (initiated after the solve)
    int fronts_stopped = 0;          // fronts whose markers are all deactivated
    std::size_t markers = 0, active_markers = 0;  // after the step
    std::size_t hits_left_object = 0, hits_crossed_crack = 0, hits_self_intersection = 0;
    std::size_t voxels_written = 0;
    std::size_t elements_added = 0, vertices_added = 0;
    std::size_t openings_estimated = 0;  // nodes left behind by a front, with an opening of eq. (5.5)
    int edges_kept = 0, edges_split = 0, edges_contracted = 0;  // fig. 16 (a), (b), (c)
    int substeps = 0;
    double max_marker_travel = 0;    // [m] over the step
    double simulated_time = 0;       // n dt_s [s]
    double propagate_seconds = 0, record_seconds = 0, grow_seconds = 0;  // wall clock
    // Go on while the crack grew, new fronts wait for SIFs, or markers still moved: a front whose
    // coarse nodes may not advance (their targets lie within the surface margin) can still have
    // markers running towards the surface, and stopping then leaves the crack a sliver short of it.
    bool should_continue() const { return elements_added > 0 || fronts_waiting > 0 || max_marker_travel > 0; }
};

// Converts displacement-correlation records (frame e1 forward, e2 normal, e3 = e1 x e2) to the
// propagation frame (n1 normal, n2 forward, n3 = n1 x n2 = -e3); K_III is re-signed with n3.
std::vector<EdgeSifs> to_edge_sifs(const std::vector<bem::FrontEdgeSif>& sifs);

// Called after every sub-step with its index and the grids as recorded so far.
using SubstepObserver = std::function<void(int substep, const CrackRecorder& grids)>;

// Advances every front of `state` by one BEM time step and grows its crack sheets. `object`
// (may be null) is the object's level set for test (a) and the surface margin. Fronts whose
// edges have no SIFs in `sifs` (cracks initiated after the solve) wait for the next step.
// Throws std::invalid_argument on inconsistent input (naming what is wrong).
StepReport propagate_step(FractureState& state, const std::vector<bem::FrontEdgeSif>& sifs, const ScalarField& toughness,
                          const LevelSet* object, const StepSettings& settings, const SubstepObserver& observer = {});

}  // namespace cf::propagate
