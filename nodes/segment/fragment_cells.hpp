#pragma once
// Cells for the surface mesher (surface_fragments.hpp): for each fragment i a closed region C_i
// that equals the fragment inside the object, with its fracture faces in the middle of the crack
// gap, and reaches `margin` beyond the fragment's outer surface, so that the input surface
// intersected with C_i is the fragment with the artist's own outer triangles. No OpenVDB here.
//
//   psi_i = max( (d_i - min_{j != i} d_j) / 2,  Phi_o - margin )
//
// d_k is the distance to fragment k, needed only where another fragment is within a few voxels
// (the crack gaps): there it is estimated from fragment k's own grid by min over its inside
// voxels y near x of |x - y| + phi_k(y) (no fragment's distance is rebuilt; one pass over the
// fragments' leaves finds those places). The first term is negative where fragment i is the
// nearest fragment (its zero set the bisector of the gap between i and j), the second keeps the
// cell within `margin` of the uncut object Phi_o. Cells of neighbouring fragments meet on the
// bisector, so two fragments' fracture faces coincide; each gains at most half the gap, under one
// voxel layer times the crack area.
#include "nodes/segment/fragments.hpp"

#include <memory>

namespace cf {

// How the nearest fragments of the contact zone are searched: per label, a min-plus filter over
// whole leaf rows (the default), or per voxel over every ball offset (the original brute force,
// kept as the tests' reference). Both give the same bits.
enum class NearestSearch { per_label, per_voxel };

class FragmentCells {
public:
    // Labels the fragments' inside voxels and finds, for every voxel within margin + 2 voxels of
    // a place where two fragments meet, its nearest fragments (oneTBB over leaves; the same for any
    // thread count). margin_voxels in [1, 8]. Throws std::invalid_argument without f.object.
    FragmentCells(const Fragments& f, double margin_voxels, NearestSearch search = NearestSearch::per_label);
    ~FragmentCells();
    FragmentCells(const FragmentCells&) = delete;
    FragmentCells& operator=(const FragmentCells&) = delete;

    // The dual-contoured zero set of psi_i at an adaptivity in [0, 1]: closed, outward oriented
    // (thread-safe, any order).
    SurfaceMesh cell_mesh(std::size_t i, double adaptivity = 0) const;
    // psi_i as a level set; with `bound` (same voxel size and frame), max(psi_i, bound): the cell
    // within the cell of an earlier break, so a fragment broken again keeps its earlier fracture
    // faces where its own cell reaches past them (rigid-body scenes).
    LevelSet cell(std::size_t i, const LevelSet* bound = nullptr) const;
    double margin() const;  // [m]

private:
    struct Grids;
    std::unique_ptr<Grids> g_;
};

}  // namespace cf
