#pragma once
// The OpenVDB side of cf::LevelSet. Include ONLY from the OpenVDB translation units
// (nodes/levelset/level_set.cpp, object_band.cpp, crack_grids.cpp, polled_csg.cpp, nodes/segment/segmentation.cpp,
// nodes/segment/preview_render.cpp): each costs ~25 s to compile.
#include "graph/cancel_token.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/util/NullInterrupter.h>

#include <cstdint>
#include <functional>

namespace cf {

struct LevelSetGrid {
    openvdb::FloatGrid::Ptr grid;
};

// Calls openvdb::initialize() once (thread-safe).
void ensure_openvdb_initialized();

inline LevelSet wrap_grid(openvdb::FloatGrid::Ptr g, double voxel_size, double half_width) {
    LevelSet ls;
    ls.grid = std::make_shared<const LevelSetGrid>(LevelSetGrid{std::move(g)});
    ls.voxel_size = voxel_size;
    ls.half_width = half_width;
    return ls;
}
inline const openvdb::FloatGrid& grid_of(const LevelSet& ls) {
    if (!ls.grid || !ls.grid->grid) throw std::invalid_argument("level set is empty");
    return *ls.grid->grid;
}

// Lets OpenVDB's long tools (mesh to volume, volume to mesh, filters) stop early when the run is
// cancelled; the caller polls the token after the tool returns, since an interrupted tool returns
// an incomplete grid instead of throwing.
struct CancelInterrupter : openvdb::util::NullInterrupter {
    explicit CancelInterrupter(CancelToken t) : token(t) {}
    bool wasInterrupted(int = -1) override { return token.requested(); }
    CancelToken token;
};

// Turns a voxel's unsigned band value into the value stored, knowing the voxel's closest triangle
// (index into the rasterised set) and centre [m]: the object level set's sign.
using ClosestTriangleValue = std::function<float(std::uint32_t triangle, const Vec3& voxel, float value)>;

// The triangles' band rasterised into `grid` (crack_grids.cpp): every voxel with unsigned distance
// d < reach [m] to the nearest triangle gets min(old, d - thick) (or `finish` of it), leaf-sized
// blocks in parallel (oneTBB), the same result for any thread count; polls the current cancel
// token per block. Returns the number of voxels set or lowered.
std::size_t rasterise_triangle_band(openvdb::FloatGrid& grid, const std::vector<Triangle3>& tris, double r_f,
                                    double thick, double reach, const ClosestTriangleValue* finish = nullptr);

// The signed narrow band of one closed, manifold, outward oriented shell without degenerate
// triangles by exact distances (object_band.cpp; exact_level_set_from_mesh checks the mesh):
// the exact distance (in meshToVolume's float arithmetic, without its renormalisation, see
// object_band.cpp's band_value). Polls `cancel` per few blocks.
openvdb::FloatGrid::Ptr exact_band_grid(const SurfaceMesh& mesh, double r_f, double half_width, const CancelToken& cancel);

// openvdb::tools::csgDifference (a = max(a, -b), eq. (6.1)), csgUnion (a = min(a, b)) and
// pruneLevelSet with OpenVDB's own node operators, bit-identical to them, but polling `cancel`
// before every tree node (polled_csg.cpp): they throw Cancelled within milliseconds of Ctrl-C.
// `b` is emptied; after Cancelled both grids are half-combined and must be discarded.
void csg_difference_polled(openvdb::FloatGrid& a, openvdb::FloatGrid& b, const CancelToken& cancel);
void csg_union_polled(openvdb::FloatGrid& a, openvdb::FloatGrid& b, const CancelToken& cancel);
void prune_level_set_polled(openvdb::FloatTree& tree, const CancelToken& cancel);
void prune_level_set_polled(openvdb::FloatTree& tree, float outside, float inside, const CancelToken& cancel);
// Grid::deepCopy, value for value (every voxel and tile, metadata, transform), polled per leaf.
openvdb::FloatGrid::Ptr deep_copy_polled(const openvdb::FloatGrid& in, const CancelToken& cancel);

}  // namespace cf
