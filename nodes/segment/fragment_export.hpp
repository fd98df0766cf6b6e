#pragma once
// Output of the fragments (ch. 6.4, App. B listing 2): one mesh per fragment from its own grid
// (OpenVDB dual contouring at an adaptivity setting, App. A item 22), optionally deformed by the
// interpolated BEM displacement, crack opening and gap closing (fragment_displacement.hpp,
// App. A items 23-25), one .vdb with every fragment grid (readable by Houdini/Blender) and a
// preview PNG. Grids and preview always show the undeformed geometry.
#include "nodes/export/mesh_writers.hpp"
#include "nodes/segment/fragment_displacement.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/segment/preview_render.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace cf {

struct FragmentExportOptions {
    bool meshes = true;
    MeshFormat format = MeshFormat::Obj;
    bool binary = true;        // PLY/STL
    double adaptivity = 0.0;   // [0, 1]
    bool vdb = true;
    bool preview = true;
    PreviewOptions preview_options;
    std::string prefix = "fragment";
    const FragmentDeformation* deformation = nullptr;  // moves the mesh vertices before writing; null: undeformed
};

struct FragmentExportResult {
    std::vector<std::filesystem::path> files;
    std::size_t triangles = 0;  // over all fragment meshes
    DeformationStats deformation;  // over all fragment meshes (zero without a deformation)
};

// Writes into `dir`: <prefix>_000.<ext>, ..., <prefix>s.vdb, <prefix>s_preview.png.
FragmentExportResult export_fragments(const std::filesystem::path& dir, const Fragments& f,
                                      const FragmentExportOptions& options);

}  // namespace cf
