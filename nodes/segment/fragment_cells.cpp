// OpenVDB translation unit: the cells of the surface mesher (fragment_cells.hpp).
#include "nodes/segment/fragment_cells.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/LevelSetRebuild.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

namespace cf {

struct FragmentCells::Grids {
    std::vector<openvdb::FloatGrid::Ptr> phi;  // rebuilt distance per fragment
    std::vector<openvdb::CoordBBox> box;       // active voxels of phi, per fragment
    double voxel = 0, margin = 0, half_width = 0;
};

FragmentCells::FragmentCells(const Fragments& f, double margin_voxels) : g_(std::make_unique<Grids>()) {
    if (!(margin_voxels >= 1 && margin_voxels <= 8))
        throw std::invalid_argument("cell margin must lie in [1, 8] voxels");
    ensure_openvdb_initialized();
    const CancelToken cancel = CancelToken::current();
    g_->voxel = f.voxel_size;
    g_->margin = margin_voxels * f.voxel_size;
    g_->half_width = margin_voxels + 2;
    const std::size_t n = f.fragments.size();
    g_->phi.resize(n);
    g_->box.resize(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        cancel.poll();
        // levelSetRebuild meshes the zero set and voxelises it again: true distances in the band.
        g_->phi[i] = openvdb::tools::levelSetRebuild(grid_of(f.fragments[i].grid), 0.0f, float(g_->half_width));
        g_->box[i] = g_->phi[i]->evalActiveVoxelBoundingBox();
    });
}

FragmentCells::~FragmentCells() = default;

double FragmentCells::margin() const { return g_->margin; }

LevelSet FragmentCells::cell(std::size_t i) const {
    const openvdb::FloatGrid& phi_i = *g_->phi.at(i);
    openvdb::FloatGrid::Ptr psi = phi_i.deepCopy();
    // Fragments whose band can reach fragment i's: the only ones the bisector term needs.
    std::vector<std::size_t> near;
    for (std::size_t j = 0; j < g_->phi.size(); ++j)
        if (j != i && g_->box[j].hasOverlap(g_->box[i])) near.push_back(j);
    std::vector<openvdb::FloatGrid::ConstAccessor> others;
    for (std::size_t j : near) others.push_back(g_->phi[j]->getConstAccessor());
    const float margin = float(g_->margin);
    for (auto it = psi->beginValueOn(); it; ++it) {
        const float own = *it;
        float other = float(g_->half_width * g_->voxel);  // no neighbour: as far as the band reaches
        for (auto& acc : others) other = std::min(other, acc.getValue(it.getCoord()));
        it.setValue(std::max(0.5f * (own - other), own - margin));
    }
    return wrap_grid(psi, g_->voxel, g_->half_width);
}

SurfaceMesh FragmentCells::cell_mesh(std::size_t i, double adaptivity) const {
    return level_set_to_mesh(cell(i), adaptivity);
}

}  // namespace cf
