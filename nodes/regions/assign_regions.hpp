#pragma once
// Gives every triangle the first region (in the order written) whose half-spaces all contain
// the triangle's centroid.
//
// Why the centroid: a boundary region is a property of whole elements (each element gets one
// boundary condition, thesis App. A (11)), so one point per triangle must decide. The centroid
// treats the three vertices alike (the answer never depends on vertex order) and lies inside the
// triangle, so a triangle lying wholly inside a region always matches it and one lying wholly
// outside never does (a region is convex); a triangle straddling a region's boundary plane goes
// to the side holding its centroid, i.e. the side with more of its area near the plane.
#include "nodes/regions/region_spec.hpp"

#include <cstddef>
#include <vector>

namespace cf {

struct RegionAssignment {
    SurfaceMesh mesh;                  // regions and region_names set
    std::vector<int> region_id;        // per definition: its id in mesh.region_names
    std::vector<std::size_t> matched;  // per definition: triangles it took
    std::size_t unmatched = 0;         // triangles no definition took
};

// keep_unmatched = false: region ids restart; id 0 is "default" and takes every unmatched
//   triangle, the definitions follow as ids 1, 2, ...
// keep_unmatched = true: unmatched triangles keep their region (id and name); a definition named
//   like an existing region adds to it, other definitions get new ids after the existing ones.
// A definition named "default" (or, when keeping, like an existing region) shares that id.
RegionAssignment assign_regions(const SurfaceMesh& mesh, const std::vector<RegionDefinition>& regions,
                                bool keep_unmatched);

}  // namespace cf
