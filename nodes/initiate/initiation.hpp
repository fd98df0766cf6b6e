#pragma once
// Crack initiation (thesis ch. 4.4): Rankine-type selection of surface elements and the initial
// hexagonal crack. SI units.
#include "nodes/fields/scalar_field.hpp"
#include "nodes/initiate/surface_stress.hpp"

#include <array>
#include <functional>
#include <vector>

namespace cf::initiate {

struct ElementStress {
    Mat3 sigma = Mat3::Zero();   // surface stress, eq. (4.6) [Pa]
    Vec3 centroid = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ(); // outward unit normal of the element
};

struct InitiationSettings {
    double r_c = 0;          // BEM edge length [m]: no initiation within r_c of a crack front (c)
    int max_cracks = 1;      // user limit on cracks in the whole simulation (d)
    int existing_cracks = 0; // cracks already present (counted against the limit)
};

struct Initiation {
    int element = -1;
    double excess = 0;          // principal stress magnitude minus local strength [Pa]
    bool compressive = false;   // minimal principal stress against f_c * strength
    double principal = 0;       // the principal stress [Pa]
    Vec3 plane_normal;          // principal direction: normal of the new crack
    Vec3 centre;                // crack centre: centroid offset into the body
};

using Segment = std::array<Vec3, 2>;

// What happened to the candidates of one selection (for the run report).
struct SelectionCounts {
    int over_strength = 0;       // not initiated before and (a) holds
    int skipped_near_front = 0;  // (c) failed
    int rejected = 0;            // passed (a)-(c) but the caller's `admissible` check refused it
    // Passed (a)-(c) after the budget (d) was used up: where the stress still exceeds the strength
    // away from every front but max_cracks holds new cracks back (not checked by `admissible`).
    int over_budget = 0;
};

// Extra test a candidate must pass after (a)-(c) (e.g. its hexagon must not cut the surface);
// a refused candidate does not use up the budget (d).
using CandidateCheck = std::function<bool(const Initiation&)>;

// Conditions (a)-(d) of ch. 4.4: (a) sigma_max > strength(centroid) or -sigma_min > f_c strength;
// (b) the element has not initiated before (`initiated`, per element, may be empty = none);
// (c) the centroid is farther than r_c from every crack-front segment, including fronts of
// cracks accepted earlier in this call; (d) at most max_cracks - existing_cracks new cracks.
// Candidates are taken in decreasing order of excess (ties: lower element index), at most one
// crack per element. Throws std::invalid_argument when sizes disagree or r_c <= 0.
std::vector<Initiation> select_initiations(const std::vector<ElementStress>& elements, const ScalarField& strength,
                                           const std::vector<char>& initiated, const std::vector<Segment>& front_segments,
                                           const InitiationSettings& settings, const CandidateCheck& admissible = {},
                                           SelectionCounts* counts = nullptr);

// Centre of the new crack: the element centroid moved into the body (against the outward
// normal) by R (|n - (n.p) p| + 1/4), R = 0.2 r_c, so the hexagon of radius R in the plane
// normal to p stays clear of the element's plane by at least R/4.
Vec3 initial_crack_centre(const Vec3& centroid, const Vec3& element_normal, const Vec3& plane_normal, double r_c);

// Planar hexagon of radius 0.2 r_c around `centre` in the plane with unit normal `plane_normal`:
// one central node (vertex 0, the crack's first opening unknown) and six rim nodes, six
// triangles oriented with normal +plane_normal. One region named `name`.
SurfaceMesh hexagon_crack(const Vec3& centre, const Vec3& plane_normal, double r_c, const std::string& name);

// Boundary (front) segments of a hexagon from hexagon_crack (the six rim edges).
std::vector<Segment> hexagon_front(const SurfaceMesh& hexagon);

// Appends `sheet` to `cracks` as a new region; existing vertices and triangles are untouched
// (append-only, so BEM blocks can be reused). Returns the new region id.
int append_crack_sheet(SurfaceMesh& cracks, const SurfaceMesh& sheet);

}  // namespace cf::initiate
