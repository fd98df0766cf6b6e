#include "nodes/simplify/carry_regions.hpp"

#include "nodes/domain/triangle_grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace cf {

CarriedRegions carry_regions(const SurfaceMesh& coarse, const SurfaceMesh& fine) {
    if (fine.num_triangles() == 0) throw std::invalid_argument("the mesh to take regions from has no triangles");
    std::vector<Triangle3> tris;
    tris.reserve(fine.num_triangles());
    for (const Tri& t : fine.triangles) tris.push_back({fine.vertices[t[0]], fine.vertices[t[1]], fine.vertices[t[2]]});
    // Cells of about two fine triangles' size: a few triangles per cell, and the query widens its
    // shells until the closest triangle is certain, however far the coarse centroid lies.
    const double cell = 2 * std::sqrt(2 * surface_area(fine) / double(fine.num_triangles()));
    const TriangleGrid grid(std::move(tris), cell > 0 && std::isfinite(cell) ? cell : 1.0);
    CarriedRegions out;
    out.mesh = coarse;
    out.mesh.region.assign(coarse.num_triangles(), 0);
    out.mesh.region_names.clear();
    for (int r = 0; r < fine.num_regions(); ++r) out.mesh.region_names.push_back(fine.region_name(r));
    // Each triangle is independent and the grid breaks ties by index: the same for any thread count.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, coarse.num_triangles()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t t = r.begin(); t != r.end(); ++t)
            out.mesh.region[t] = fine.region_of(std::size_t(grid.closest(triangle_centroid(coarse, t)).triangle));
    });
    std::vector<std::size_t> fine_count(fine.num_regions(), 0), coarse_count(fine.num_regions(), 0);
    for (std::size_t t = 0; t < fine.num_triangles(); ++t) ++fine_count[fine.region_of(t)];
    for (int r : out.mesh.region) ++coarse_count[r];
    for (int r = 0; r < fine.num_regions(); ++r)
        if (fine_count[r] > 0 && coarse_count[r] == 0) out.empty_regions.push_back(fine.region_name(r));
    return out;
}

}  // namespace cf
