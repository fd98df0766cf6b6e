// Node adapter for nodes/simplify: simplify.remesh (ch. 6.1).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/registration.hpp"
#include "nodes/regions/assign_regions.hpp"
#include "nodes/regions/region_stats.hpp"
#include "nodes/simplify/carry_regions.hpp"
#include "nodes/simplify/remesh.hpp"

#include <stdexcept>

namespace cf {
namespace {

graph::NodeType remesh_node() {
    graph::NodeType t("simplify.remesh",
                      "Coarse BEM mesh from the object level set: dual contouring of the surface offset outward on the "
                      "distance field (ch. 6.1, App. A items 13-14), QEM simplification (Garland-Heckbert) to four times "
                      "the target, isotropic remeshing to the target count with vertices projected onto the offset "
                      "surface, element-shape repair (flips, collapses, splits, vertex moves), self-intersection repair "
                      "(delete one-ring, fill holes). Guarantees a closed, manifold, oriented mesh without "
                      "self-intersections, every triangle angle >= min_angle and every dihedral between neighbours >= "
                      "min_dihedral (fails naming the bound otherwise); the count as close to the target as up to six "
                      "edge-length corrections get it (counter triangles; a run note when it is more than 5 % off). "
                      "Shells smaller than one element are left out (counter dropped_shells).");
    t.input<LevelSet>("level_set", "object signed distance grid");
    t.optional_input<SurfaceMesh>("regions_from",
                                  "the fine mesh the level set was made from (e.g. import.mesh with face groups): each "
                                  "coarse triangle takes the region of the fine triangle nearest its centroid; a region "
                                  "that no coarse triangle takes is an error");
    t.param_int("target_triangles", 1000, "target triangle count (App. A item 13)").range(4, 10000000);
    t.param_real("offset_voxels", 1, "voxels", "outward offset in multiples of r_f (App. A item 14)").range(0, 3);
    t.param_real("adaptivity", 0, "",
                 "adaptivity of the dense dual-contoured mesh, [0, 1]: 0 keeps every voxel face; 0.1 merges nearly "
                 "flat ones first, so the QEM pass (most of this node's time) has several times fewer triangles to "
                 "collapse (a 30 cm camel at 1 mm: 345k -> 41k, 5.1 -> 1.2 s), at the price of a different BEM mesh")
        .range(0, 1);
    t.param_real("min_angle", 15, "degrees", "smallest triangle angle the result must have; the node fails if repair cannot reach it")
        .range(1, 40);
    t.param_real("min_dihedral", 30, "degrees",
                 "smallest dihedral between neighbouring triangles (180 = flat, 0 = folded back) the result must have; the "
                 "node fails if repair cannot reach it")
        .range(1, 120);
    t.param_string("regions", "",
                   "boundary regions by half-spaces (nodes/regions spec, e.g. as for regions.halfspace); with "
                   "'regions_from' they are applied on top (unmatched triangles keep the carried region); empty: the "
                   "carried regions, or one region 'surface'");
    t.output<SurfaceMesh>("mesh", "closed coarse mesh, outward oriented");
    t.run([](graph::NodeContext& c) {
        RemeshOptions o;
        o.target_triangles = std::size_t(c.integer("target_triangles"));
        o.offset_voxels = c.real("offset_voxels");
        o.adaptivity = c.real("adaptivity");
        o.min_angle_deg = c.real("min_angle");
        o.min_dihedral_deg = c.real("min_dihedral");
        RemeshResult r;
        try {
            r = remesh(c.in<LevelSet>("level_set"), o);
        } catch (const std::exception& e) {
            c.fail(std::string(e.what()));
        }
        SurfaceMesh mesh = std::move(r.mesh);
        mesh.region_names = {"surface"};
        const bool carried = c.has("regions_from");
        if (carried) {
            const SurfaceMesh& fine = c.in<SurfaceMesh>("regions_from");
            if (fine.num_triangles() == 0) c.fail("input 'regions_from' has no triangles");
            CarriedRegions cr = carry_regions(mesh, fine);
            if (!cr.empty_regions.empty()) {
                std::string names;
                for (const auto& n : cr.empty_regions) names += (names.empty() ? "'" : ", '") + n + "'";
                c.fail("input 'regions_from': region(s) " + names + " of the fine mesh got no triangle of the " +
                       std::to_string(mesh.num_triangles()) +
                       "-triangle coarse mesh (too small for it); raise target_triangles or merge the region into a "
                       "neighbour in the modelling tool");
            }
            mesh = std::move(cr.mesh);
        }
        if (!c.string("regions").empty()) {
            try {
                mesh = assign_regions(mesh, parse_region_spec(c.string("regions")), carried).mesh;
            } catch (const std::exception& e) {
                c.fail(std::string("parameter 'regions': ") + e.what());
            }
        }
        c.count("dense_triangles", double(r.dense_triangles));
        c.count("triangles", double(mesh.num_triangles()));
        c.count("vertices", double(mesh.num_vertices()));
        c.count("self_intersections_repaired", double(r.self_intersections_before));
        c.count("repair_rounds", r.repair_rounds);
        c.count("sliver_flips", double(r.sliver_flips));
        c.count("sliver_collapses", double(r.sliver_collapses));
        c.count("shape_flips", double(r.quality_flips));
        c.count("shape_collapses", double(r.quality_collapses));
        c.count("shape_splits", double(r.quality_splits));
        c.count("shape_moves", double(r.quality_moves));
        c.count("dropped_shells", double(r.dropped_shells));
        // Measured on the result (the guarantee, not a count of repairs): degrees.
        c.count("min_angle_deg", r.quality.min_angle_deg);
        c.count("min_dihedral_deg", r.quality.min_dihedral_deg);
        count_region_stats(c, mesh);
        c.out("mesh", std::move(mesh));
    });
    return t;
}

}  // namespace

void register_simplify_nodes(graph::NodeRegistry& r) { r.add(remesh_node()); }

}  // namespace cf
