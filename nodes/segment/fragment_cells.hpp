#pragma once
// Cells for the surface mesher (surface_fragments.hpp): for each fragment i a closed region C_i
// that equals the fragment inside the object, with its fracture faces in the middle of the crack
// gap, and reaches `margin` beyond the fragment's outer surface, so that the input surface
// intersected with C_i is the fragment with the artist's own outer triangles. No OpenVDB here.
//
//   psi_i = max( (phi_i - min_{j != i} phi_j) / 2,  phi_i - margin )
//
// phi_k is fragment k's signed distance, rebuilt with a band wide enough to hold margin (the
// segmentation grids keep only 1-2 voxels outside a fragment, and inside a crack gap both sides
// hold the same crack distance). The first term is negative where fragment i is the nearest
// fragment (its zero set the bisector of the gap between i and j), the second keeps the cell
// within `margin` of fragment i. Cells of neighbouring fragments meet on the bisector, so two
// fragments' fracture faces coincide; each gains at most half the gap, under one voxel layer times
// the crack area.
#include "nodes/segment/fragments.hpp"

#include <memory>

namespace cf {

class FragmentCells {
public:
    // Rebuilds every fragment's distance grid (oneTBB, one task per fragment) with a band of
    // margin + 2 voxels. margin_voxels in [1, 8].
    FragmentCells(const Fragments& f, double margin_voxels);
    ~FragmentCells();
    FragmentCells(const FragmentCells&) = delete;
    FragmentCells& operator=(const FragmentCells&) = delete;

    // The dual-contoured zero set of psi_i at an adaptivity in [0, 1]: closed, outward oriented
    // (thread-safe, any order).
    SurfaceMesh cell_mesh(std::size_t i, double adaptivity = 0) const;
    // psi_i as a level set (tests).
    LevelSet cell(std::size_t i) const;
    double margin() const;  // [m]

private:
    struct Grids;
    std::unique_ptr<Grids> g_;
};

}  // namespace cf
