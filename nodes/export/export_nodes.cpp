// Node adapters for the export stage.
#include "nodes/export/mesh_writers.hpp"
#include "nodes/registration.hpp"

#include "graph/node_context.hpp"

namespace cf {

void register_export_nodes(graph::NodeRegistry& r) {
    graph::NodeType t("export.mesh", "Writes a surface mesh to OBJ, OFF, PLY, STL or VTK PolyData (.vtp, with the "
                                     "per-triangle region ids as cell data), atomically.");
    t.input<SurfaceMesh>("mesh", "the surface to write (metres)");
    t.param_string("path", "", "output file; relative paths are relative to the run's output directory").required().writes_file();
    t.param_choice("format", "auto", {"auto", "obj", "off", "ply", "stl", "vtp", "glb"},
                   "file format; auto picks it from the path's extension");
    t.param_bool("binary", true, "binary PLY / STL (smaller, faster); binary STL rounds coordinates to float32");
    t.run([](graph::NodeContext& c) {
        const std::filesystem::path path = c.output_path(c.string("path"));  // stays inside --out
        const SurfaceMesh& m = c.in<SurfaceMesh>("mesh");
        try {
            const MeshFormat f =
                c.string("format") == "auto" ? mesh_format_from_extension(path) : mesh_format_from_name(c.string("format"));
            c.count("bytes", static_cast<double>(write_mesh_file(path, m, f, c.boolean("binary"))));
        } catch (const std::exception& e) {
            c.fail("parameter 'path' (" + path.string() + "): " + e.what());
        }
        c.count("triangles", static_cast<double>(m.num_triangles()));
    });
    r.add(std::move(t));
}

}  // namespace cf
