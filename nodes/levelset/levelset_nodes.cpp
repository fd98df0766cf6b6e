// Node adapters for nodes/levelset: levelset.from_mesh, levelset.crack_planar (ch. 6.1-6.2) and
// record.cracks (ch. 6.2, fig. 27).
#include "graph/diagnostics.hpp"
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"

#include <cmath>
#include <stdexcept>

namespace cf {
namespace {


graph::NodeType from_mesh_node() {
    graph::NodeType t("levelset.from_mesh",
                      "Signed distance grid of a closed surface mesh (ch. 6.1): voxel size r_f, narrow band of "
                      "half_width voxels, interior sign everywhere by flood fill. Reports the volume measured on "
                      "the grid. Rejects open or inward-oriented meshes and r_f too large for the object.");
    t.input<SurfaceMesh>("mesh", "closed, outward-oriented surface");
    t.param_real("voxel_size", 0.01, "m", "r_f, the level-set resolution (App. A item 16)").above(0);
    t.param_real("half_width", 3, "voxels", "narrow-band half-width (the thesis uses 3)").range(2, 10);
    t.param_choice("band", "openvdb", {"openvdb", "exact"},
                   "how the narrow band is computed: openvdb (OpenVDB's meshToLevelSet, the results of "
                   "docs/pipelines.md) or exact (exact distances rasterised per block in parallel: less CPU, "
                   "Ctrl-C within a block; values differ from meshToLevelSet's by up to 0.13 voxel away from the "
                   "surface, which moves remeshed BEM meshes, and by up to a voxel inside thin parts, which "
                   "meshToLevelSet's renormalisation thickens)");
    t.param_bool("write_vdb", false, "also write object.vdb into the output directory");
    t.writes_fixed("object.vdb", "write_vdb");
    t.output<LevelSet>("level_set", "object signed distance grid [m]");
    t.run([](graph::NodeContext& c) {
        LevelSet ls;
        try {
            const SurfaceMesh& mesh = c.in<SurfaceMesh>("mesh");
            ls = c.string("band") == "exact" ? exact_level_set_from_mesh(mesh, c.real("voxel_size"), c.real("half_width"))
                                             : level_set_from_mesh(mesh, c.real("voxel_size"), c.real("half_width"));
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("input 'mesh' / parameter 'voxel_size': ") + e.what());
        }
        c.count("active_voxels", double(active_voxel_count(ls)));
        c.count("volume_m3", level_set_volume(ls));
        if (c.boolean("write_vdb")) write_vdb(c.output_dir() / "object.vdb", {{"object", ls}});
        c.out("level_set", std::move(ls));
    });
    return t;
}

// True if some point of the disk lies inside the object (sampled at <= r_f spacing, capped).
bool disk_meets_object(const LevelSet& object, const Vec3& centre, const Vec3& n, double radius) {
    const Vec3 u = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized(), w = n.cross(u);
    const int steps = std::min(256, std::max(1, int(std::ceil(radius / object.voxel_size))));
    for (int i = -steps; i <= steps; ++i)
        for (int j = -steps; j <= steps; ++j) {
            const double a = radius * i / steps, b = radius * j / steps;
            if (a * a + b * b > radius * radius) continue;
            if (sample(object, centre + a * u + b * w) < 0) return true;
        }
    return false;
}

graph::NodeType crack_planar_node() {
    graph::NodeType t("levelset.crack_planar",
                      "A user-given planar crack: the disk of given radius around a centre with a normal, recorded "
                      "as its own crack grid (thickened by sqrt(3) r_f / 2, ch. 6.2) at the object's voxel size. A "
                      "radius larger than the object cuts it through.");
    t.input<LevelSet>("object", "object grid: gives r_f and checks that the crack meets the object");
    t.optional_input<CrackLevelSets>("cracks", "existing cracks; the new one is appended");
    t.param_reals("centre", {0, 0, 0}, "m", "a point on the crack plane (disk centre)").size(3);
    t.param_reals("normal", {0, 0, 1}, "", "crack plane normal (any length > 0)").size(3);
    t.param_real("radius", 10, "m", "disk radius").above(0);
    t.output<CrackLevelSets>("cracks", "all crack grids");
    t.run([](graph::NodeContext& c) {
        const LevelSet& object = c.in<LevelSet>("object");
        const Vec3 centre = vec3_param(c, "centre"), normal = vec3_param(c, "normal");
        if (!(normal.norm() > 0)) c.fail("parameter 'normal': must be a non-zero vector");
        const double radius = c.real("radius");
        if (!disk_meets_object(object, centre, normal.normalized(), radius))
            c.fail("the planar crack (centre, normal, radius) does not meet the object: it would be an empty crack; "
                   "move its centre into the object or enlarge the radius");
        CrackLevelSets out = c.has("cracks") ? c.in<CrackLevelSets>("cracks")
                                             : CrackLevelSets{object.voxel_size, object.half_width, {}};
        if (std::abs(out.voxel_size - object.voxel_size) > 1e-9 * object.voxel_size)
            c.fail("input 'cracks' has voxel size " + graph::format_number(out.voxel_size) + " m, the object " +
                   graph::format_number(object.voxel_size) + " m");
        try {
            out.cracks.push_back(planar_disk_crack(centre, normal, radius, object.voxel_size, object.half_width));
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.count("cracks", double(out.cracks.size()));
        c.count("crack_voxels", double(active_voxel_count(out.cracks.back())));
        c.out("cracks", std::move(out));
    });
    return t;
}

graph::NodeType record_node() {
    graph::NodeType t("record.cracks",
                      "Records one crack-propagation sub-step (ch. 6.2): tests every moving marker against the "
                      "grids so far (fig. 27: a left the object, b crossed another crack, c self-intersection by "
                      "eq. 6.2), then unions each crack's new front strip (p0 -> p1, neighbours joined) into its "
                      "grid, in parallel across cracks. Only the new strips are voxelised.");
    t.input<CrackLevelSets>("cracks", "crack grids up to the previous sub-step");
    t.input<std::vector<FrontMotion>>("fronts", "one front motion per crack, in crack order");
    t.optional_input<LevelSet>("object", "object grid for test (a); without it (a) is skipped");
    t.param_bool("write_vdb", false, "write the crack grids after this sub-step (App. A item 19) as cracks_<i>.vdb");
    t.writes_fixed("cracks_*.vdb", "write_vdb");
    t.output<CrackLevelSets>("cracks", "updated crack grids");
    t.output<std::vector<std::vector<MarkerTest>>>("hits", "per crack, per marker: which case stopped it (or none)");
    t.run([](graph::NodeContext& c) {
        const CrackLevelSets& in = c.in<CrackLevelSets>("cracks");
        const auto& fronts = c.in<std::vector<FrontMotion>>("fronts");
        if (fronts.size() != in.cracks.size())
            c.fail("input 'fronts' has " + std::to_string(fronts.size()) + " front motions for " +
                   std::to_string(in.cracks.size()) + " cracks; give one per crack");
        CrackRecorder rec(in);
        std::vector<std::vector<MarkerTest>> hits;
        std::size_t written = 0;
        try {
            hits = rec.record_substep(fronts, c.has("object") ? &c.in<LevelSet>("object") : nullptr, &written);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        CrackLevelSets out = rec.release();
        double counts[4] = {0, 0, 0, 0};
        for (const auto& crack : hits)
            for (const MarkerTest& m : crack) counts[int(m.hit)] += 1;
        c.count("voxels_written", double(written));
        c.count("hits_left_object", counts[int(MarkerHit::left_object)]);
        c.count("hits_crossed_crack", counts[int(MarkerHit::crossed_crack)]);
        c.count("hits_self_intersection", counts[int(MarkerHit::self_intersection)]);
        if (c.boolean("write_vdb")) {
            std::vector<std::pair<std::string, LevelSet>> grids;
            for (std::size_t i = 0; i < out.cracks.size(); ++i) grids.emplace_back("crack" + std::to_string(i), out.cracks[i]);
            write_vdb(c.output_dir() / ("cracks_" + std::to_string(std::max(0, c.iteration())) + ".vdb"), grids);
        }
        c.out("cracks", std::move(out));
        c.out("hits", std::move(hits));
    });
    return t;
}

}  // namespace

void register_levelset_nodes(graph::NodeRegistry& r) {
    r.add(from_mesh_node());
    r.add(crack_planar_node());
    r.add(record_node());
}

}  // namespace cf
