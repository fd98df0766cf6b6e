#include "nodes/segment/fragment_mesher.hpp"

#include "nodes/segment/fragment_cells.hpp"
#include "nodes/segment/fracture_faces.hpp"
#include "nodes/segment/surface_fragments.hpp"

#include <stdexcept>

namespace cf {

FragmentMesherKind fragment_mesher_from_name(const std::string& name) {
    if (name == "levelset") return FragmentMesherKind::levelset;
    if (name == "surface") return FragmentMesherKind::surface;
    throw std::invalid_argument("unknown fragment mesher '" + name + "'; use levelset or surface");
}

FragmentMesher::FragmentMesher(const Fragments& f, const FragmentMesherOptions& o) : f_(f), o_(o) {
    if (o.kind != FragmentMesherKind::surface) return;
    if (!o.surface)
        throw std::invalid_argument("mesher 'surface' needs the input surface (connect the mesh the object's level set "
                                    "was made from), or set mesher: levelset");
    clipper_ = std::make_unique<SurfaceClipper>(*o.surface);
    cells_ = std::make_unique<FragmentCells>(f, o.margin_voxels);
}

FragmentMesher::~FragmentMesher() = default;

SurfaceMesh FragmentMesher::mesh(std::size_t i, std::string* warning) const {
    if (clipper_) {
        SurfaceMesh m;
        std::string problem;
        if (clipper_->clip(cells_->cell_mesh(i, o_.adaptivity), m, &problem)) return m;
        if (warning) *warning = "fragment " + std::to_string(i) + ": " + problem + "; written as its level-set mesh";
    }
    SurfaceMesh m = level_set_to_mesh(f_.fragments[i].grid, o_.adaptivity);
    if (!f_.object.empty()) tag_fracture_faces(m, f_.object, kFractureFaceDepthVoxels * f_.voxel_size);
    return m;
}

}  // namespace cf
