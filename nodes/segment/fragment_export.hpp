#pragma once
// Output of the fragments (ch. 6.4, App. B listing 2): one mesh per fragment from its own grid
// (OpenVDB dual contouring at an adaptivity setting, App. A item 22), optionally deformed by the
// interpolated BEM displacement, crack opening and gap closing (fragment_displacement.hpp,
// App. A items 23-25), one .vdb with every fragment grid (readable by Houdini/Blender) and a
// preview PNG. Grids and preview always show the undeformed geometry. The meshes come from either
// mesher (fragment_mesher.hpp): the level set's zero set, or the input surface clipped by the
// fragment's cell, keeping the input's triangles, UVs, normals and materials (issue 14).
#include "nodes/export/mesh_writers.hpp"
#include "nodes/segment/fragment_displacement.hpp"
#include "nodes/segment/fragment_mesher.hpp"
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
    PreviewOptions preview_options;  // size (of each view), explode, camera
    bool contact_sheet = true;       // four views (oblique, front, side, top) in the preview PNG
    FragmentMesherOptions mesher;    // its adaptivity is `adaptivity` below
    std::string prefix = "fragment";
    const FragmentDeformation* deformation = nullptr;  // moves the mesh vertices before writing; null: undeformed
};

struct FragmentExportResult {
    std::vector<std::filesystem::path> files;
    std::size_t triangles = 0;  // over all fragment meshes
    DeformationStats deformation;  // over all fragment meshes (zero without a deformation)
    std::size_t fallback_fragments = 0;  // surface mesher: fragments written as level-set meshes
    std::vector<std::string> warnings;   // one per fall-back, in fragment order
};

// Writes into `dir`: <prefix>_000.<ext>, ..., <prefix>s.vdb, <prefix>s_preview.png, and for OBJ
// <prefix>s.mtl (the materials: the input's regions and "inside").
FragmentExportResult export_fragments(const std::filesystem::path& dir, const Fragments& f,
                                      const FragmentExportOptions& options);

}  // namespace cf
