// Node adapters for nodes/segment: segment.fragments (ch. 6.3) and export.fragments (ch. 6.4).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/registration.hpp"
#include "nodes/segment/fragment_export.hpp"
#include "nodes/segment/fragments.hpp"

#include <stdexcept>

namespace cf {
namespace {

graph::NodeType fragments_node() {
    graph::NodeType t("segment.fragments",
                      "Cuts the object by all cracks (eq. 6.1) and splits it into fragments: connected components of "
                      "inside voxels (26-neighbourhood) and inside tiles (tile-aware, keeps interior cracks), after "
                      "over-segmenting by s to remove spindles thinner than s (ch. 6.3, listing 1). Fragments are "
                      "sorted by volume, largest first; writes fragments.csv and fragments.json.");
    t.input<LevelSet>("object", "object signed distance grid (levelset.from_mesh)");
    t.optional_input<CrackLevelSets>("cracks", "crack grids (same voxel size); none: the object is one fragment");
    t.param_real("s", -1, "m",
                 "over-segmentation threshold s in [0, r_f]; -1 means s = r_f (thesis default). Larger values "
                 "would lose surface detail and are rejected");
    t.param_bool("tiles", true, "tile-aware search (needed to keep cracks deep inside the object)");
    t.param_bool("write_listing", true, "write fragments.csv and fragments.json into the output directory");
    t.output<Fragments>("fragments", "fragment grids with volume [m^3], bbox [m], centroid [m]");
    t.run([](graph::NodeContext& c) {
        const LevelSet& object = c.in<LevelSet>("object");
        Fragments f;
        try {
            const LevelSet broken =
                c.has("cracks") ? broken_object(object, c.in<CrackLevelSets>("cracks")) : object;
            const double s = c.real("s");
            if (s < 0 && s != -1) c.fail("parameter 's': " + std::to_string(s) + " m is negative; use -1 for s = r_f or a value in [0, r_f]");
            f = find_fragments(broken, SegmentOptions{s, c.boolean("tiles")});
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        if (c.boolean("write_listing")) {
            write_fragments_csv(c.output_dir() / "fragments.csv", f);
            write_fragments_json(c.output_dir() / "fragments.json", f);
        }
        c.count("fragments", double(f.fragments.size()));
        double v = 0;
        for (const Fragment& g : f.fragments) v += g.volume;
        c.count("total_volume_m3", v);
        if (!f.fragments.empty()) c.count("largest_volume_m3", f.fragments.front().volume);
        c.out("fragments", std::move(f));
    });
    return t;
}

graph::NodeType export_fragments_node() {
    graph::NodeType t("export.fragments",
                      "Writes each fragment as a mesh (dual contouring of its grid at an adaptivity), all fragment "
                      "grids into one .vdb (Houdini/Blender), and an exploded preview PNG (ch. 6.4). Undeformed "
                      "geometry only: interpolated displacement and crack opening wait for the BEM solution type.");
    t.input<Fragments>("fragments", "from segment.fragments");
    t.param_bool("meshes", true, "write one mesh file per fragment");
    t.param_choice("format", "obj", {"obj", "ply", "stl", "off"}, "mesh file format");
    t.param_bool("binary", true, "binary PLY/STL (ignored for OBJ/OFF)");
    t.param_real("adaptivity", 0.0, "", "mesh adaptivity in [0, 1] (App. A item 22): 0 keeps every polygon").range(0, 1);
    t.param_bool("vdb", true, "write all fragment grids into fragments.vdb");
    t.param_bool("preview", true, "render an exploded preview PNG");
    t.param_real("explode", 0.3, "", "preview: fragments move by this fraction of their centroid offset").range(0, 5);
    t.param_int("width", 640, "preview width [pixels]").range(16, 8192);
    t.param_int("height", 480, "preview height [pixels]").range(16, 8192);
    t.param_string("prefix", "fragment", "file name prefix");
    t.output<std::string>("directory", "the directory the files were written to");
    t.run([](graph::NodeContext& c) {
        FragmentExportOptions o;
        o.meshes = c.boolean("meshes");
        o.format = mesh_format_from_name(c.string("format"));
        o.binary = c.boolean("binary");
        o.adaptivity = c.real("adaptivity");
        o.vdb = c.boolean("vdb");
        o.preview = c.boolean("preview");
        o.preview_options.explode = c.real("explode");
        o.preview_options.width = int(c.integer("width"));
        o.preview_options.height = int(c.integer("height"));
        o.prefix = c.string("prefix");
        if (o.prefix.empty() || o.prefix.find_first_of("/\\") != std::string::npos)
            c.fail("parameter 'prefix': must be a non-empty file name without slashes");
        FragmentExportResult r;
        try {
            r = export_fragments(c.output_dir(), c.in<Fragments>("fragments"), o);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.count("files", double(r.files.size()));
        c.count("triangles", double(r.triangles));
        c.out("directory", c.output_dir().string());
    });
    return t;
}

}  // namespace

void register_segment_nodes(graph::NodeRegistry& r) {
    r.add(fragments_node());
    r.add(export_fragments_node());
}

}  // namespace cf
