// Node adapters for nodes/regions: regions.halfspace.
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/regions/assign_regions.hpp"
#include "nodes/regions/region_stats.hpp"
#include "nodes/registration.hpp"

#include <sstream>

namespace cf {
namespace {

std::string describe_box(const SurfaceMesh& m) {
    const Box3 b = bounding_box(m);
    std::ostringstream s;
    s << "x in [" << b.min.x() << ", " << b.max.x() << "], y in [" << b.min.y() << ", " << b.max.y() << "], z in ["
      << b.min.z() << ", " << b.max.z() << "]";
    return s.str();
}

void run_halfspace(graph::NodeContext& c) {
    const SurfaceMesh& mesh = c.in<SurfaceMesh>("mesh");
    if (mesh.num_triangles() == 0) c.fail("input 'mesh' has no triangles");
    std::vector<RegionDefinition> defs;
    try {
        defs = parse_region_spec(c.string("regions"));
    } catch (const RegionSpecError& e) {
        c.fail(std::string("parameter 'regions': ") + e.what());
    }
    RegionAssignment a = assign_regions(mesh, defs, c.boolean("keep_unmatched"));
    if (!c.boolean("allow_empty"))
        for (std::size_t k = 0; k < defs.size(); ++k)
            if (a.matched[k] == 0)
                c.fail("parameter 'regions': region '" + defs[k].name +
                       "' holds no triangle centroid (an earlier region may have taken them, or the inequalities "
                       "miss the mesh, whose bounding box is " + describe_box(mesh) +
                       "); fix the inequalities or set allow_empty: true");
    c.count("unmatched_triangles", static_cast<double>(a.unmatched));
    count_region_stats(c, a.mesh);
    c.out("mesh", std::move(a.mesh));
}

}  // namespace

void register_regions_nodes(graph::NodeRegistry& r) {
    graph::NodeType t("regions.halfspace",
                      "Names boundary regions by convex intersections of half-spaces (thesis App. A (10)): each "
                      "triangle gets the first listed region whose conditions all hold at its centroid; unmatched "
                      "triangles go to region 0 'default' or keep their region. Syntax: nodes/regions/README.md.");
    t.input<SurfaceMesh>("mesh", "surface to label");
    t.output<SurfaceMesh>("mesh", "the same surface with region ids and region_names set");
    t.param_string("regions", "",
                   "regions in order, e.g. 'top: z >= 0.49; bottom: z <= -0.49; corner: x <= -0.4 & y >= 0' "
                   "(coordinates in m; earlier regions win)")
        .required();
    t.param_bool("keep_unmatched", false,
                 "unmatched triangles keep their region (true) instead of going to region 0 'default' (false)");
    t.param_bool("allow_empty", false, "accept a region that holds no triangle (otherwise that is an error)");
    t.run(run_halfspace);
    r.add(std::move(t));
}

}  // namespace cf
