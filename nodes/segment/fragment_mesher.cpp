#include "nodes/segment/fragment_mesher.hpp"

#include "nodes/segment/fragment_cells.hpp"
#include "nodes/segment/fracture_faces.hpp"
#include "nodes/segment/surface_fragments.hpp"
#include "nodes/simplify/remesh.hpp"

#include <stdexcept>

namespace cf {

FragmentMesherKind fragment_mesher_from_name(const std::string& name) {
    if (name == "levelset") return FragmentMesherKind::levelset;
    if (name == "surface") return FragmentMesherKind::surface;
    throw std::invalid_argument("unknown fragment mesher '" + name + "'; use levelset or surface");
}

FragmentMesher::FragmentMesher(const Fragments& f, const FragmentMesherOptions& o) : f_(f), o_(o) {
    if (o.kind != FragmentMesherKind::surface) return;
    if (!o.surface && !o.clipper)
        throw std::invalid_argument("mesher 'surface' needs the input surface (connect the mesh the object's level set "
                                    "was made from), or set mesher: levelset");
    clipper_ = o.clipper ? o.clipper : std::make_shared<const SurfaceClipper>(*o.surface);
    cells_ = std::make_unique<FragmentCells>(f, o.margin_voxels);
}

FragmentMesher::~FragmentMesher() = default;

SurfaceMesh FragmentMesher::mesh(std::size_t i, std::string* warning, bool* folded, LevelSet* cell_out) const {
    if (folded) *folded = false;
    if (clipper_) {
        SurfaceMesh m, with_folds;
        std::string problem;
        bool has_folds = false;
        LevelSet psi = cells_->cell(i, o_.bound);
        SurfaceMesh cell = level_set_to_mesh(psi, o_.adaptivity);
        if (cell_out) *cell_out = std::move(psi);
        if (clipper_->clip(cell, m, &problem, o_.keep_folds ? &has_folds : nullptr)) {
            if (!has_folds) return m;
            with_folds = std::move(m);
            problem = "its fracture faces intersect each other";
        }
        // Dual contouring occasionally folds a few triangles of a cell where its fracture faces
        // meet the offset surface (a crease of psi_i); where that is near the input the
        // corefinement fails. The folds are cut out and the holes filled, then it is tried again.
        try {
            repair_self_intersections(cell, 3);
            if (clipper_->clip(cell, m, &problem)) return m;
        } catch (const std::exception& e) {
            problem += std::string("; repairing its cell failed: ") + e.what();
        }
        if (has_folds) {
            if (folded) *folded = true;
            return with_folds;
        }
        if (warning) *warning = "fragment " + std::to_string(i) + ": " + problem + "; written as its level-set mesh";
    }
    SurfaceMesh m = level_set_to_mesh(f_.fragments[i].grid, o_.adaptivity);
    if (!f_.object.empty()) tag_fracture_faces(m, f_.object, kFractureFaceDepthVoxels * f_.voxel_size);
    return m;
}

}  // namespace cf
