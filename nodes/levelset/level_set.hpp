#pragma once
// Narrow-band signed distance grids (thesis ch. 6.1) behind an opaque handle, so code that
// passes grids between nodes never includes OpenVDB. The OpenVDB type lives in
// nodes/levelset/level_set_grid.hpp, which only the few OpenVDB translation units include.
// Convention: voxel (i,j,k) sits at world position (i,j,k) * voxel_size; values in metres;
// negative inside; inactive values are +-half_width * voxel_size.
#include "graph/cancel_token.hpp"
#include "graph/value.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace cf {

struct LevelSetGrid;  // wraps openvdb::FloatGrid::Ptr (level_set_grid.hpp)

// An immutable level set. Copying shares the grid.
struct LevelSet {
    std::shared_ptr<const LevelSetGrid> grid;
    double voxel_size = 0;  // r_f [m]
    double half_width = 3;  // narrow-band half-width [voxels]

    bool empty() const { return !grid; }
    double background() const { return half_width * voxel_size; }
};

// Signed distance grid of a closed, consistently oriented surface mesh (ch. 6.1): voxel size
// r_f [m], narrow band of `half_width` voxels, interior sign everywhere (flood fill).
// Throws std::invalid_argument when the mesh is open, non-manifold or inward oriented, when r_f
// is too large for the object (thinnest bounding-box side < 4 r_f) or so small that the band
// would exceed `max_voxels`.
LevelSet level_set_from_mesh(const SurfaceMesh& mesh, double voxel_size, double half_width = 3,
                             double max_voxels = 2e8, const CancelToken& cancel = CancelToken::current());

// The same grid with exact distances to the nearest triangle in the band (issue 17): rasterised per
// leaf-sized block near the surface in parallel (oneTBB, the same grid for any thread count),
// signed by angle-weighted pseudo-normals, the interior as tiles, then meshToLevelSet's own
// renormalisation and trimming; polls `cancel` per block (level_set_from_mesh polls it at every
// triangle-corner read inside OpenVDB's conversion). About 2.7x less CPU than meshToLevelSet on a box (object_band.cpp). Where meshToLevelSet's
// band expansion errs (up to 0.13 voxel beyond 2 voxels from an edge, 1.7 voxels beside a sharp
// concave notch) the values differ, which moves a remeshed BEM mesh and with it the results of
// curved cases (docs/performance.md); hence not the default. Meshes of several shells or with
// degenerate triangles go to meshToLevelSet.
LevelSet exact_level_set_from_mesh(const SurfaceMesh& mesh, double voxel_size, double half_width = 3,
                                   double max_voxels = 2e8, const CancelToken& cancel = CancelToken::current());

// Voxel-by-voxel difference of two grids of the same voxel size (tests): voxels active in either
// grid whose values differ by more than `tolerance` [m] or whose activity or sign differs are listed
// (index coordinates, up to `max_listed`).
struct GridDifference {
    std::size_t active_in_both = 0, active_only_in_a = 0, active_only_in_b = 0;
    std::size_t sign_differs = 0;  // over every voxel active in either grid
    double max_abs_difference = 0; // [m], over the voxels active in both
    std::vector<std::array<int, 3>> differing;
};
GridDifference compare_grids(const LevelSet& a, const LevelSet& b, double tolerance = 0, std::size_t max_listed = 0);

// Enclosed volume [m^3] measured on the grid: OpenVDB's LevelSetMeasure volume (the divergence
// theorem with a smeared delta function), computed the same way to the bit but faster.
double level_set_volume(const LevelSet& ls);
// Independent reference: openvdb::tools::levelSetVolume itself (used by tests).
double level_set_volume_openvdb(const LevelSet& ls);
// Trilinear value [m] and gradient (central differences of the trilinear field) at a point.
double sample(const LevelSet& ls, const Vec3& p);

// How far p lies outside the zero set along `direction` (unit, pointing towards the inside) [m]:
// the sampled value where it is within the narrow band (negative inside), else marched in steps of
// the sampled value (clamped at the band's half-width outside it), so points beyond the band are
// measured too. +infinity when max_steps steps do not reach the band (nothing that way).
double distance_along(const LevelSet& ls, const Vec3& p, const Vec3& direction, int max_steps = 16);
Vec3 sample_gradient(const LevelSet& ls, const Vec3& p);
// sample() at many points (one accessor per task, in parallel); the values do not depend on the
// thread count. Points outside the active band get the background value.
std::vector<double> sample_points(const LevelSet& ls, const std::vector<Vec3>& points);
std::size_t active_voxel_count(const LevelSet& ls);
// World-space bounding box of the active voxels (empty grid: min > max).
Box3 active_bounding_box(const LevelSet& ls);

// Dual-contoured surface (OpenVDB volumeToMesh) at the level `isovalue` [m] (0: the surface; > 0:
// the surface offset outward by that distance, which must stay a voxel inside the narrow band),
// triangles only, outward oriented. adaptivity in [0, 1]: 0 keeps every polygon, 1 merges flat
// regions most.
SurfaceMesh level_set_to_mesh(const LevelSet& ls, double adaptivity = 0, double isovalue = 0);

// Writes named grids into one .vdb file atomically (readable by Houdini and Blender).
void write_vdb(const std::filesystem::path& path, const std::vector<std::pair<std::string, LevelSet>>& grids);
// Reads every float grid of a .vdb file (used by tests and to resume).
std::vector<std::pair<std::string, LevelSet>> read_vdb(const std::filesystem::path& path);

}  // namespace cf

CF_GRAPH_TYPE(cf::LevelSet, "LevelSet");
