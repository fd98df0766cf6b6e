#pragma once
// One mesh per fragment, by either mesher (issue 14):
// - levelset: the dual-contoured zero set of the fragment's grid (ch. 6.4, App. A item 22);
// - surface: the input surface intersected with the fragment's cell (fragment_cells.hpp,
//   surface_fragments.hpp): the artist's triangles, UVs, normals and materials on the outside,
//   fracture faces in the region "inside". A fragment whose cell or intersection is not a closed
//   manifold falls back to the level-set mesh, with a warning naming it.
// No OpenVDB or CGAL here.
#include "nodes/segment/fragments.hpp"

#include <memory>
#include <string>
#include <vector>

namespace cf {

class FragmentCells;
class SurfaceClipper;

enum class FragmentMesherKind { levelset, surface };

struct FragmentMesherOptions {
    FragmentMesherKind kind = FragmentMesherKind::levelset;
    double adaptivity = 0;         // [0, 1]: the level-set meshes, and the cells of the surface mesher (its fracture faces)
    const SurfaceMesh* surface = nullptr;  // the input surface; needed by kind surface (or `clipper`)
    // Kind surface: the input prepared once and reused (a scene's body breaking many times); null:
    // prepared from `surface` here.
    std::shared_ptr<const SurfaceClipper> clipper;
    double margin_voxels = 2;      // how far a cell reaches beyond its fragment [voxels], in [1, 8]
    // Kind surface: a fragment whose folded fracture faces cannot be mended keeps its folds (a mesh
    // to draw, SurfaceClipper::clip) instead of falling back to its level-set mesh.
    bool keep_folds = false;
    // Kind surface: every cell within this level set (FragmentCells::cell's bound; null: none).
    const LevelSet* bound = nullptr;
};

class FragmentMesher {
public:
    // Prepares the cells and the input (kind surface). Throws std::invalid_argument when kind is
    // surface without a surface, or the surface cannot be intersected (not closed, manifold, or
    // self-intersecting), naming how to fix it.
    FragmentMesher(const Fragments& f, const FragmentMesherOptions& options);
    ~FragmentMesher();

    // Fragment i's mesh; thread-safe. For a fall-back, *warning says which fragment and why;
    // *folded is set when it keeps folds (keep_folds); *cell gets its cell (kind surface).
    SurfaceMesh mesh(std::size_t i, std::string* warning = nullptr, bool* folded = nullptr,
                     LevelSet* cell = nullptr) const;

private:
    const Fragments& f_;
    FragmentMesherOptions o_;
    std::unique_ptr<FragmentCells> cells_;
    std::shared_ptr<const SurfaceClipper> clipper_;
};

FragmentMesherKind fragment_mesher_from_name(const std::string& name);  // "levelset" | "surface"

}  // namespace cf
