#include "nodes/regions/assign_regions.hpp"

#include <algorithm>

namespace cf {

RegionAssignment assign_regions(const SurfaceMesh& mesh, const std::vector<RegionDefinition>& regions,
                                bool keep_unmatched) {
    RegionAssignment out;
    out.mesh = mesh;
    SurfaceMesh& m = out.mesh;
    std::vector<std::string> names;
    if (keep_unmatched) {
        for (int id = 0; id < mesh.num_regions(); ++id) names.push_back(mesh.region_name(id));
    } else {
        names = {"default"};
    }
    for (const RegionDefinition& r : regions) {
        auto it = std::find(names.begin(), names.end(), r.name);
        if (it == names.end()) it = names.insert(names.end(), r.name);
        out.region_id.push_back(static_cast<int>(it - names.begin()));
    }
    m.region_names = names;

    out.matched.assign(regions.size(), 0);
    m.region.resize(mesh.num_triangles());
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const Vec3 centroid = triangle_centroid(mesh, t);
        std::size_t k = 0;
        while (k < regions.size() && !regions[k].contains(centroid)) ++k;
        if (k < regions.size()) {
            m.region[t] = out.region_id[k];
            ++out.matched[k];
        } else {
            m.region[t] = keep_unmatched ? mesh.region_of(t) : 0;
            ++out.unmatched;
        }
    }
    return out;
}

}  // namespace cf
