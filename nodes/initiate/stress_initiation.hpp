#pragma once
// One crack-initiation pass of a fracture step (thesis ch. 4.4): surface stress of every BEM
// element from the solution, the Rankine-type rules (a)-(d), and new hexagonal cracks appended to
// the fracture state. SI units.
#include "nodes/bem/solver.hpp"
#include "nodes/initiate/initiation.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_state.hpp"

namespace cf::initiate {

struct CrackInitiationSettings {
    int max_cracks = 1;      // App. A item 21: limit on stress-initiated cracks in the whole run (d)
    bool branching = false;  // crack faces may initiate too (branching cracks)
    // The object's level set, or null. Given: hexagons are placed below the object's surface (each
    // element's point moved along its normal onto it, where the BEM surface is within r_c / 4 of it),
    // not below the BEM element, which stands off the object by the remesh offset and its chords;
    // and a hexagon whose centre is not inside the object is skipped. The BEM surface alone does not
    // tell: a fragment that keeps its parent's BEM mesh (ch. 7.3, class (d)) is smaller than that
    // mesh where a chip broke off, and a hexagon there would start outside the material.
    const LevelSet* object = nullptr;
    // [m] How far outside the object an element's point may lie and still be moved onto it; 0:
    // r_c / 4. A scene sets it from its body's BEM standoff (a remesh offset and its chords can
    // exceed r_c / 4; then nearly every hexagon was skipped as outside).
    double snap_distance = 0;
};

struct CrackInitiationReport {
    int cracks_added = 0;
    int from_surface = 0;            // ... started on the ordinary surface
    int from_crack_faces = 0;        // ... branching off crack faces
    int crack_face_candidates = 0;   // crack elements considered (branching on)
    SelectionCounts selection;       // over strength, skipped near a front, rejected below
    int skipped_outside = 0;         // hexagon centre not inside the ordinary surface (or the object)
    int skipped_surface = 0;         // hexagon touches or crosses the ordinary BEM surface
    int skipped_crack = 0;           // hexagon touches or crosses an existing (or just added) crack sheet
    std::size_t triangles_added = 0;
};

// Appends to `state` every crack that the rules of ch. 4.4 start from `sol`:
//  - each ordinary-surface element gives sigma_e by eq. (4.6); with `branching`, each crack
//    element gives the stress of its two faces (u+- = u_c +- [u]/2, q = 0) and competes with
//    the face of larger excess over the strength (the thesis: the side of higher principal
//    stress magnitude); its outward normal is that face's;
//  - select_initiations applies (a)-(d) with the segments of every front of the state (coarse
//    node positions), state.initiated for (b) and state.cracks_initiated for (d);
//  - a candidate's hexagon (hexagon_crack at initial_crack_centre, radius 0.2 r_c, normal the
//    principal direction) must have its centre inside the ordinary surface and touch neither the
//    surface nor any crack sheet; otherwise it is skipped (counted) and the next one is tried;
//  - accepted hexagons are add_crack()ed (recorded surface = the hexagon), their surface
//    element is marked initiated, and state.cracks_initiated grows.
// Rule (b) for crack elements: the state keeps initiated flags for ordinary-surface elements
// only; a crack face that initiated before is blocked by the intersection test, since the
// sheets are append-only and keep the first hexagon.
// Throws std::invalid_argument when the solution does not belong to the state (sizes differ).
CrackInitiationReport initiate_cracks(propagate::FractureState& state, const bem::BemSolution& sol,
                                      const ScalarField& strength, const CrackInitiationSettings& settings);

// Segments of every front edge of the state, at the coarse node positions (rule (c)).
std::vector<Segment> front_segments(const propagate::FractureState& state);

}  // namespace cf::initiate
