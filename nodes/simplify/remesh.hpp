#pragma once
// Coarse BEM mesh from an object level set (thesis ch. 6.1, App. A items 13-14): dual
// contouring (OpenVDB volumeToMesh) of the iso-surface k voxels outside (the offset taken on the
// distance field) -> shells smaller than one element dropped -> QEM simplification to 4x the
// target -> isotropic remeshing to the target count, vertices projected onto that iso-surface ->
// zero-area slivers and then every angle / dihedral below its bound repaired (quality_repair.hpp)
// -> self-intersecting pairs found, their one-ring deleted, the holes filled and repaired again.
// The result is checked: closed, manifold, consistently oriented, no self-intersections, every
// angle >= min_angle_deg and every dihedral >= min_dihedral_deg; otherwise remesh() throws.
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/simplify/mesh_quality.hpp"

namespace cf {

struct RemeshOptions {
    std::size_t target_triangles = 1000;  // App. A item 13
    double offset_voxels = 1;             // App. A item 14: outward offset in multiples of r_f
    double adaptivity = 0;                // dual-contouring adaptivity of the dense mesh, [0, 1]
    int max_repair_rounds = 6;            // each round deletes a wider neighbourhood
    double min_angle_deg = 15;            // every triangle angle at least this [degrees]
    double min_dihedral_deg = 30;         // every dihedral between neighbours at least this (flat: 180) [degrees]
};

// QEM stops at this many times the target before isotropic remeshing makes the elements.
constexpr std::size_t kRemeshQemOversampling = 4;
constexpr int kRemeshIsotropicIterations = 5;
// Edges whose dihedral is below this are kept as feature lines by the isotropic remeshing [deg].
constexpr double kRemeshFeatureDihedralDeg = 120;

struct RemeshResult {
    SurfaceMesh mesh;
    std::size_t dense_triangles = 0;            // dual-contoured mesh before simplification
    std::size_t self_intersections_before = 0;  // after simplification and offset, before repair
    std::size_t self_intersections_after = 0;   // always 0 on success
    int repair_rounds = 0;
    std::size_t sliver_flips = 0;      // zero-area caps removed by an edge flip
    std::size_t sliver_collapses = 0;  // zero-area needles removed by an edge collapse
    std::size_t quality_flips = 0;      // element-shape repair (quality_repair.hpp)
    std::size_t quality_collapses = 0;
    std::size_t quality_moves = 0;
    std::size_t quality_splits = 0;
    std::size_t dropped_shells = 0;  // closed pieces smaller than one element, left out
    MeshQuality quality;  // measured on the result: min angle, min dihedral
};

// Throws std::invalid_argument for a target below 4 triangles or a negative offset, and
// std::runtime_error naming what failed if the guarantees cannot be met.
// Peak bytes per triangle of the dense dual-contoured mesh during a remesh: 515 measured (the 1 x
// 0.6 x 0.4 m box at 4 mm, adaptivity 0: 314012 triangles, 162 MB above the level set), doubled
// for address-space caps, which also count reserved but untouched memory.
constexpr double kRemeshBytesPerDenseTriangle = 1000;
// Estimated peak memory of remesh() [bytes], and a check that throws std::invalid_argument naming
// the level set's voxel size and the memory needed when it exceeds what the process may use.
double remesh_bytes_estimate(const LevelSet& object);
void check_remesh_memory(const LevelSet& object);

RemeshResult remesh(const LevelSet& object, const RemeshOptions& options,
                    const CancelToken& cancel = CancelToken::current());

// Moves every vertex by `distance` [m] along its angle-weighted vertex normal (outward for an
// outward-oriented mesh; independent of how flat faces and creases are triangulated).
void offset_along_normals(SurfaceMesh& mesh, double distance);

// Deletes the one-ring of every self-intersecting triangle (widening the ring each round), also
// removing the star of any vertex left pinched, and fills the holes; repeats until no pair is
// left or `max_rounds` is reached. Returns the number of rounds used; the caller checks the
// remaining pairs.
int repair_self_intersections(SurfaceMesh& mesh, int max_rounds);

// Drops vertices no triangle uses (indices renumbered).
SurfaceMesh without_unused_vertices(const SurfaceMesh& mesh);

}  // namespace cf
