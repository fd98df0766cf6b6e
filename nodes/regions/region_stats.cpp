#include "nodes/regions/region_stats.hpp"

namespace cf {

std::vector<RegionStats> region_stats(const SurfaceMesh& mesh) {
    std::vector<RegionStats> stats(static_cast<std::size_t>(mesh.num_regions()));
    for (std::size_t id = 0; id < stats.size(); ++id) stats[id].name = mesh.region_name(static_cast<int>(id));
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        RegionStats& s = stats[static_cast<std::size_t>(mesh.region_of(t))];
        ++s.triangles;
        s.area += triangle_area(mesh, t);
    }
    return stats;
}

void count_region_stats(graph::NodeContext& c, const SurfaceMesh& mesh) {
    for (const RegionStats& s : region_stats(mesh)) {
        c.count("region." + s.name + ".triangles", static_cast<double>(s.triangles));
        c.count("region." + s.name + ".area", s.area);
    }
}

}  // namespace cf
