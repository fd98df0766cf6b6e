// Node adapters for the import stage.
#include "nodes/import/read_mesh.hpp"
#include "nodes/regions/region_stats.hpp"
#include "nodes/registration.hpp"

#include "graph/node_context.hpp"

namespace cf {

void register_import_nodes(graph::NodeRegistry& r) {
    graph::NodeType t("import.mesh",
                      "Reads a closed triangle surface from OBJ, OFF, PLY or STL; polygons are fan-triangulated. Regions "
                      "(for boundary conditions) come from the file: OBJ faces take the name of the latest 'g', 'o' or "
                      "'usemtl' line before them; PLY faces an integer face property region, material_index, material or "
                      "group (the first present) as '<property><value>', e.g. region3; faces without one (and OFF, STL) "
                      "get region 'default'. The report lists each region's triangles and area [m^2].");
    t.output<SurfaceMesh>("mesh", "the checked surface, outward oriented, in metres");
    t.param_string("path", "", "mesh file (.obj, .off, .ply, .stl); a relative path is looked up beside the pipeline file, then on CRACKFLOW_DATA_PATH and the build's data directory (docs/pipelines.md)").required().reads_file();
    t.param_bool("reorient", false,
                 "re-orient inconsistent or inside-out faces instead of failing (consistent per shell, outward)");
    t.param_real("scale", 1.0, "m", "length of one file unit in metres (0.001 for a file in millimetres)").above(0);
    t.param_real("weld_tolerance", 0.0, "m",
                 "merge vertices closer than this (after scaling); 0 disables (STL is always welded by exact position)")
        .at_least(0);
    t.run([](graph::NodeContext& c) {
        ImportOptions o;
        o.reorient = c.boolean("reorient");
        o.scale = c.real("scale");
        o.weld_tolerance = c.real("weld_tolerance");
        ImportedMesh im;
        try {
            im = read_mesh_file(c.string("path"), o);
        } catch (const MeshFileError& e) {
            c.fail(e.what());
        }
        c.count("vertices", static_cast<double>(im.mesh.num_vertices()));
        c.count("triangles", static_cast<double>(im.mesh.num_triangles()));
        c.count("regions", static_cast<double>(im.mesh.num_regions()));
        count_region_stats(c, im.mesh);
        c.count("shells", static_cast<double>(im.report.components));
        c.count("flipped_triangles", static_cast<double>(im.report.flipped_triangles));
        c.count("welded_vertices", static_cast<double>(im.report.welded_vertices));
        c.count("unreferenced_vertices", static_cast<double>(im.report.unreferenced_vertices));
        c.out("mesh", std::move(im.mesh));
    });
    r.add(std::move(t));
}

}  // namespace cf
