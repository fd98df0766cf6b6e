#pragma once
// Per-region triangle counts and areas: what a user checks after naming regions, and what the
// run report shows for every node that produces a surface with regions.
#include "graph/node_context.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace cf {

struct RegionStats {
    std::string name;
    std::size_t triangles = 0;
    double area = 0;  // [m^2]
};

// One entry per region id 0 .. num_regions()-1, empty regions included.
std::vector<RegionStats> region_stats(const SurfaceMesh& mesh);

// Reports "region.<name>.triangles" and "region.<name>.area" for every region.
void count_region_stats(graph::NodeContext& c, const SurfaceMesh& mesh);

}  // namespace cf
