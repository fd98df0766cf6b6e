#pragma once
// One assembly of a fracture run (thesis ch. 4.2, ch. 5, fig. 40): reuses the previous step's
// surface blocks, appends the new crack elements to the system (full BEM), or, once growth is
// estimated, integrates only the influence of the new estimated openings on the surface
// (EstimatedGrowth). The hybrid switch happens here: the first assembly whose mesh (surface plus
// crack triangles) exceeds the threshold keeps the cracks assembled so far as they are and
// estimates everything after. The choice of method is made on the first assembly (no previous
// operators) and carried by the operators to every later step.
#include "nodes/bem/bem_types.hpp"

#include <optional>

namespace cf::bem {

struct AssemblyRequest {
    const SurfaceMesh* mesh = nullptr;             // ordinary surface
    const SurfaceMesh* cracks = nullptr;           // may be null or empty
    const BemOperators* previous = nullptr;        // may be null
    // May be null: surface blocks assembled before for the same surface (a rigid body's earlier
    // fracture run, ch. 7.3), used instead of assembling when surface, material and quadrature match.
    // Unlike `previous`, nothing else (method, cracks) is carried over.
    std::shared_ptr<const SurfaceOperators> surface_blocks;
    const CrackOpeningEstimate* openings = nullptr;  // needed once growth is estimated and nodes left a front
    Material material;
    AssemblyOptions options;
    std::optional<CrackMethod> method;             // empty: full, or the previous operators' method
    long long switch_elements = 0;                 // hybrid threshold (elements), used with method hybrid
    int step = 0;                                  // BEM step, for the report of the switch
    bool opening_update = true;                    // false: estimated openings do not update the surface (fig. 22a)
    std::optional<bool> tip_elements;              // square-root crack-front elements (full BEM only); empty: the
                                                   // previous operators' choice, or square_root on a first assembly
};

struct AssemblyReport {
    bool surface_reused = false;
    bool switched = false;          // growth became estimated in this assembly
    bool estimated = false;         // growth is estimated (now or before)
    std::size_t elements = 0;       // surface + crack triangles
    std::size_t crack_pairs = 0;    // crack element pairs integrated (system blocks or estimated openings)
    std::size_t tip_pairs = 0;      // element pairs re-integrated with square-root front elements
    std::size_t tip_pairs_reused = 0;  // their corrections taken from the previous step (front unchanged there)
    std::size_t tip_pairs_in_append = 0;  // computed ones made inside the append (TipCorrectionsOfAppend)
};

// Throws std::invalid_argument with the parameter or input to fix: a method that contradicts the
// previous operators', estimated growth without an opening estimate, and what the assembly throws.
BemOperators assemble_step(const AssemblyRequest& request, AssemblyReport& report);

// "full" / "estimator" / "hybrid"; throws std::invalid_argument for anything else.
CrackMethod parse_crack_method(const std::string& name);

}  // namespace cf::bem
