// Node adapters for nodes/segment: segment.fragments (ch. 6.3) and export.fragments (ch. 6.4).
#include "graph/diagnostics.hpp"
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/segment/fragment_export.hpp"
#include "nodes/segment/fragment_sheet.hpp"
#include "nodes/segment/fragments.hpp"

#include <iostream>
#include <memory>
#include <stdexcept>

namespace cf {
namespace {

graph::NodeType fragments_node() {
    graph::NodeType t("segment.fragments",
                      "Cuts the object by all cracks (eq. 6.1) and splits it into fragments: connected components of "
                      "inside voxels (26-neighbourhood) and inside tiles (tile-aware, keeps interior cracks), after "
                      "over-segmenting by s to remove spindles thinner than s (ch. 6.3, listing 1). Fragments are "
                      "sorted by volume, largest first, those below min_volume dropped; writes fragments.csv and "
                      "fragments.json.");
    t.input<LevelSet>("object", "object signed distance grid (levelset.from_mesh)");
    t.optional_input<CrackLevelSets>("cracks", "crack grids (same voxel size); none: the object is one fragment");
    t.param_real("s", -1, "m",
                 "over-segmentation threshold s in [0, r_f]; -1 means s = r_f (thesis default). Larger values "
                 "would lose surface detail and are rejected");
    t.param_bool("tiles", true, "tile-aware search (needed to keep cracks deep inside the object)");
    t.param_real("min_volume", 0, "m^3",
                 "drop fragments smaller than this (specks where cracks pass close together or run along the "
                 "surface); 0 keeps every fragment")
        .range(0, 1e30);
    t.param_bool("write_listing", true, "write fragments.csv and fragments.json into the output directory");
    t.writes_fixed("fragments.csv", "write_listing");
    t.writes_fixed("fragments.json", "write_listing");
    t.output<Fragments>("fragments", "fragment grids with volume [m^3], bbox [m], centroid [m]");
    t.run([](graph::NodeContext& c) {
        const LevelSet& object = c.in<LevelSet>("object");
        Fragments f;
        try {
            const LevelSet broken =
                c.has("cracks") ? broken_object(object, c.in<CrackLevelSets>("cracks")) : object;
            const double s = c.real("s");
            if (s < 0 && s != -1) c.fail("parameter 's': " + graph::format_number(s) + " m is negative; use -1 for s = r_f or a value in [0, r_f]");
            const double min_volume = c.real("min_volume");  // finite and >= 0: the parameter's range
            f = find_fragments(broken, SegmentOptions{s, c.boolean("tiles"), min_volume});
            f.object = object;
            double dropped_volume = 0;
            c.count("dropped_fragments", double(drop_small_fragments(f, min_volume, &dropped_volume)));
            c.count("dropped_volume_m3", dropped_volume);
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

// export.fragments' declaration and run, in steps.

void declare_export_fragments_params(graph::NodeType& t) {
    t.param_bool("meshes", true, "write one mesh file per fragment");
    t.param_choice("format", "obj", {"obj", "ply", "stl", "off", "glb"},
                   "mesh file format: obj (with <prefix>s.mtl: a material per input region and 'inside', UVs, "
                   "normals), ply (face properties region and inside, vertex u v nx ny nz), glb (glTF 2.0, a "
                   "material per region in the fragment's preview colour), stl or off (geometry only)");
    t.param_choice("mesher", "auto", {"auto", "surface", "levelset"},
                   "surface: the input mesh ('surface' input) clipped by each fragment's cell: the input's own "
                   "triangles with their UVs, normals and materials outside, fracture faces in the group/material "
                   "'inside' with box-projected UVs; levelset: the dual-contoured fragment grid (App. A item 22); "
                   "auto: surface when the 'surface' input is connected");
    t.param_real("cell_margin", 2, "voxels",
                 "surface mesher: how far a fragment's cell reaches beyond the fragment's level-set surface, in "
                 "voxels r_f; input detail further out than this from the level set is cut off")
        .range(1, 8);
    t.param_bool("binary", true, "binary PLY/STL (ignored for OBJ/OFF)");
    t.param_real("adaptivity", 0.0, "", "mesh adaptivity in [0, 1] (App. A item 22): 0 keeps every polygon").range(0, 1);
    t.param_choice("displacement", "none", {"none", "continuous", "continuous_and_opening"},
                   "deformation added to the mesh files (App. A items 24-25): none (material space), the "
                   "continuous BEM displacement, or that plus the crack-opening displacement");
    t.param_real("displacement_scale", 1.0, "", "factor on the displacement and opening, e.g. > 1 to exaggerate them "
                 "for visualisation (not applied to the gap closing)").at_least(0);
    t.param_bool("remove_compressive_opening", true,
                 "drop the interpenetrating normal part of the crack opening, [u].n < 0, at every crack vertex "
                 "before applying it");
    t.param_bool("close_gaps", false, "move cut-face vertices onto the recorded crack surfaces (App. A item 23); "
                 "needs the 'cracks' input");
    t.param_bool("vdb", true, "write all fragment grids into fragments.vdb (undeformed)");
    t.param_bool("preview", true, "render an exploded preview PNG (undeformed)");
    t.param_real("explode", 1.0, "", "preview: fragments move by this fraction of their centroid offset").range(0, 5);
    t.param_bool("contact_sheet", true, "preview: four views in one PNG (the oblique 'view', front, side, top)");
    t.param_int("width", 640, "preview width [pixels] (the contact sheet's views are half of it)").range(16, 8192);
    t.param_int("height", 480, "preview height [pixels] (the contact sheet's views are half of it)").range(16, 8192);
    t.param_reals("up", {0, 0, 1}, "", "preview: the scene's vertical, drawn upwards (0 1 0 for most imported meshes)")
        .size(3);
    t.param_reals("view", {0.5, -1.2, 0.7}, "",
                  "preview: direction from the scene's centre to the camera (any length, not parallel to up)")
        .size(3);
    t.param_string("prefix", "fragment", "file name prefix");
}

// The file and preview options, checked.
FragmentExportOptions export_options(graph::NodeContext& c) {
    FragmentExportOptions o;
    o.meshes = c.boolean("meshes");
    o.format = mesh_format_from_name(c.string("format"));
    o.binary = c.boolean("binary");
    o.adaptivity = c.real("adaptivity");
    o.vdb = c.boolean("vdb");
    o.preview = c.boolean("preview");
    o.preview_options.explode = c.real("explode");
    o.contact_sheet = c.boolean("contact_sheet");
    const std::string mesher = c.string("mesher");
    o.mesher.kind = mesher == "surface" || (mesher == "auto" && c.has("surface")) ? FragmentMesherKind::surface
                                                                                  : FragmentMesherKind::levelset;
    if (o.mesher.kind == FragmentMesherKind::surface) {
        if (!c.has("surface"))
            c.fail("parameter 'mesher' = surface needs the input 'surface' (the mesh the object's level set was made "
                   "from), or set 'mesher' to levelset");
        o.mesher.surface = &c.in<SurfaceMesh>("surface");
    }
    o.mesher.margin_voxels = c.real("cell_margin");
    o.preview_options.width = int(c.integer("width"));
    o.preview_options.height = int(c.integer("height"));
    o.preview_options.up = vec3_param(c, "up");
    o.preview_options.view = vec3_param(c, "view");
    if (const std::string problem = preview_camera_problem(o.preview_options); !problem.empty())
        c.fail("parameter " + problem);
    o.prefix = c.string("prefix");
    if (o.prefix.empty() || o.prefix.find_first_of("/\\") != std::string::npos)
        c.fail("parameter 'prefix': must be a non-empty file name without slashes");
    return o;
}

// The deformation of the mesh files, checked against the inputs it needs.
DeformationOptions deformation_options(graph::NodeContext& c) {
    DeformationOptions d;
    const std::string mode = c.string("displacement");
    d.mode = displacement_mode_from_name(mode);
    d.scale = c.real("displacement_scale");
    d.remove_compressive_opening = c.boolean("remove_compressive_opening");
    d.close_gaps = c.boolean("close_gaps");
    if (d.mode != DisplacementMode::none && !c.has("solution"))
        c.fail("parameter 'displacement' = " + mode + " needs the input 'solution' (connect solve.sgbem), or set "
               "'displacement' to none");
    if (d.mode == DisplacementMode::continuous_and_opening && !c.has("cracks"))
        c.fail("parameter 'displacement' = continuous_and_opening needs the input 'cracks' (the crack grids the "
               "fragments were cut with): the fine crack surfaces decide which face a vertex is on");
    if (d.close_gaps && !c.has("cracks"))
        c.fail("parameter 'close_gaps' = true needs the input 'cracks' (the crack grids the fragments were cut "
               "with), or set 'close_gaps' to false");
    return d;
}

void count_export(graph::NodeContext& c, const FragmentExportOptions& o, const FragmentExportResult& r) {
    c.count("files", double(r.files.size()));
    c.count("triangles", double(r.triangles));
    if (o.mesher.kind == FragmentMesherKind::surface) {
        // A fragment the surface mesher could not clip is written as its level-set mesh; the
        // count says how many, stderr says which and why.
        c.count("fallback_fragments", double(r.fallback_fragments));
        for (const std::string& w : r.warnings) std::cerr << "warning: export.fragments: " << w << '\n';
    }
    if (o.deformation) {
        c.count("vertices_on_crack_sheets", double(r.deformation.on_crack));
        c.count("vertices_opened", double(r.deformation.opened));
        c.count("vertices_closed", double(r.deformation.closed));
        c.count("opening_sign_from_coarse_mesh", double(r.deformation.sign_from_coarse));
        c.count("max_vertex_displacement_m", r.deformation.max_displacement);
    }
}

void run_export_fragments(graph::NodeContext& c) {
    FragmentExportOptions o = export_options(c);
    const Fragments& fragments = c.in<Fragments>("fragments");
    DeformationOptions d = deformation_options(c);
    const CrackLevelSets* cracks = c.has("cracks") ? &c.in<CrackLevelSets>("cracks") : nullptr;
    if (cracks) d.opening_band = cracks->half_width;
    std::unique_ptr<FragmentDeformation> deformation;
    FragmentExportResult r;
    try {
        if (o.meshes && (d.mode != DisplacementMode::none || d.close_gaps)) {  // only mesh files are deformed
            std::shared_ptr<const CoarseDisplacement> coarse;
            if (d.mode != DisplacementMode::none)
                coarse = std::make_shared<const CoarseDisplacement>(
                    coarse_displacement_from(c.in<bem::BemSolution>("solution"), true));
            deformation = std::make_unique<FragmentDeformation>(coarse, cracks, fragments.voxel_size, d);
            o.deformation = deformation.get();
            c.count("compressive_opening_vertices", double(deformation->compressive_vertices()));
        }
        r = export_fragments(c.output_dir(), fragments, o);
    } catch (const std::invalid_argument& e) {
        c.fail(e.what());
    }
    count_export(c, o, r);
    c.out("directory", c.output_dir().string());
}

graph::NodeType export_fragments_node() {
    graph::NodeType t("export.fragments",
                      "Writes each fragment as a mesh (the input surface clipped by the fragment's cell, keeping its "
                      "UVs, normals and materials, with fracture faces in the material 'inside'; or dual contouring "
                      "of its grid at an adaptivity), all fragment grids into one .vdb (Houdini/Blender), and an "
                      "exploded preview PNG: a contact sheet of four views, each fragment in its own colour, "
                      "fracture faces in a pale shade of it (ch. 6.4, listing 2). "
                      "The mesh files can be deformed (App. A items 23-25; the acceleration grid cell r_c is the BEM mesh's mean edge length): 'continuous' adds the BEM displacement "
                      "interpolated linearly in the closest coarse triangle (nodal u on the ordinary surface, the "
                      "crack's average displacement u_c on crack sheets); 'continuous_and_opening' also adds "
                      "+-w [u] of every crack within half_width r_f, the face chosen by the recorded fine crack "
                      "surface (w = 1/2 on the crack face, fading linearly to 0 at the band edge where the closest "
                      "coarse point is on the ordinary surface); 'close_gaps' moves cut-face vertices onto the "
                      "recorded crack surfaces, removing the sqrt(3) r_f gap of the thickened cracks. The .vdb "
                      "grids and the preview stay undeformed.");
    t.input<Fragments>("fragments", "from segment.fragments");
    t.optional_input<SurfaceMesh>("surface",
                                  "the object's input mesh (import.mesh or shape.*, before remeshing) for the surface "
                                  "mesher: its triangles, UVs, normals and regions become the fragments' outer faces");
    t.optional_input<bem::BemSolution>("solution", "from solve.sgbem; needed when 'displacement' is not none");
    t.optional_input<CrackLevelSets>("cracks",
                                     "the crack grids the fragments were cut with (same r_f, crack r = BEM crack "
                                     "region r); needed for 'continuous_and_opening' and 'close_gaps'");
    declare_export_fragments_params(t);
    t.writes_fixed("<prefix>_*.<format>", "meshes");
    t.writes_fixed("<prefix>s.mtl", "meshes");
    t.writes_fixed("<prefix>s.vdb", "vdb");
    t.writes_fixed("<prefix>s_preview.png", "preview");
    t.input_needed_when("surface", "mesher", {"surface"}, "the input mesh whose triangles the fragments keep");
    t.input_needed_when("solution", "displacement", {"continuous", "continuous_and_opening"},
                        "the BEM displacement that deforms the meshes");
    t.input_needed_when("cracks", "displacement", {"continuous_and_opening"},
                        "the fine crack surfaces decide which face of a crack a vertex is on");
    t.input_needed_when("cracks", "close_gaps", {"true"}, "cut-face vertices move onto the recorded crack surfaces");
    t.output<std::string>("directory", "the directory the files were written to");
    t.run(run_export_fragments);
    return t;
}

// A preview image per fracture step (issue 14): the cracks' recorded surfaces inside the cut-away
// object, so a run's growth can be watched step by step without a VTK viewer.
graph::NodeType step_preview_node() {
    graph::NodeType t("export.step_preview",
                      "Writes a PNG of the cracks at this step: four views (the oblique 'view', front, side, top) of "
                      "the object cut away (only its far walls drawn, pale grey) with every crack's recorded "
                      "high-resolution surface in front of them, crack i in fragment colour i. Framed on the object, "
                      "so a run's images line up. Inside a fracture loop it writes every step ('{iteration}' in the "
                      "path); path 'none' writes nothing.");
    t.input<SurfaceMesh>("surface", "the object's surface (the BEM mesh), closed and outward oriented");
    t.input<CrackLevelSets>("cracks", "the crack grids of this step (fracture.geometry's 'grids')");
    t.param_string("path", "preview_{iteration}.png",
                   "PNG file relative to the run's output directory; '{iteration}' becomes the loop iteration; "
                   "'none': no file (the node does nothing)")
        .writes_file();
    t.param_real("adaptivity", 0.5, "", "mesh adaptivity of the crack surfaces in [0, 1]: 0 keeps every polygon")
        .range(0, 1);
    t.param_bool("contact_sheet", true, "four views in one PNG (the oblique 'view', front, side, top)");
    t.param_int("width", 640, "width [pixels] (the contact sheet's views are half of it)").range(16, 8192);
    t.param_int("height", 480, "height [pixels] (the contact sheet's views are half of it)").range(16, 8192);
    t.param_reals("up", {0, 0, 1}, "", "the scene's vertical, drawn upwards (0 1 0 for most imported meshes)").size(3);
    t.param_reals("view", {0.5, -1.2, 0.7}, "",
                  "direction from the object's centre to the camera (any length, not parallel to up)")
        .size(3);
    t.run([](graph::NodeContext& c) {
        if (c.string("path") == "none") return;
        const SurfaceMesh& object = c.in<SurfaceMesh>("surface");
        const CrackLevelSets& grids = c.in<CrackLevelSets>("cracks");
        std::vector<SurfaceMesh> cracks;
        for (const LevelSet& g : grids.cracks)
            if (!g.empty()) cracks.push_back(level_set_to_mesh(g, c.real("adaptivity")));
        SheetOptions o;
        o.width = int(c.integer("width"));
        o.height = int(c.integer("height"));
        o.contact_sheet = c.boolean("contact_sheet");
        o.up = vec3_param(c, "up");
        o.view = vec3_param(c, "view");
        const std::filesystem::path png = c.output_path(c.string("path"));
        try {
            write_crack_sheet(png, object, cracks, o);
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("parameters 'width' / 'height' / 'up' / 'view' or input 'surface': ") + e.what());
        } catch (const std::runtime_error& e) {
            c.fail("parameter 'path' (" + png.string() + "): " + e.what());
        }
        std::size_t triangles = 0;
        for (const SurfaceMesh& m : cracks) triangles += m.num_triangles();
        c.count("crack_triangles", double(triangles));
    });
    return t;
}

}  // namespace

void register_segment_nodes(graph::NodeRegistry& r) {
    r.add(fragments_node());
    r.add(export_fragments_node());
    r.add(step_preview_node());
}

}  // namespace cf
