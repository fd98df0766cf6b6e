#pragma once
// Finding fragments (thesis ch. 6.3, App. B listing 1): cut the object by all cracks (eq. 6.1),
// then label connected components of the inside voxels (26-neighbourhood) and inside tiles
// (6 face neighbours), optionally after over-segmenting by a threshold s in [0, r_f] that
// removes spindles thinner than s while keeping the surface detail (d-ring copy).
// No OpenVDB here; grids are cf::LevelSet handles.
#include "graph/value.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"

#include <filesystem>
#include <vector>

namespace cf {

struct Fragment {
    LevelSet grid;               // the fragment's own signed distance grid
    double volume = 0;           // [m^3], on the grid: linear Heaviside per voxel + inside tiles
    Box3 bbox;                   // [m], voxels with negative value and inside tiles
    Vec3 centroid = Vec3::Zero();// [m], volume centroid (same weights)
    std::size_t active_voxels = 0;
};

// Sorted by volume, largest first (ties: smaller bbox.min, lexicographically).
struct Fragments {
    double voxel_size = 0;  // r_f [m]
    double threshold = 0;   // s [m] used
    bool used_tiles = true;
    std::vector<Fragment> fragments;
    // The uncut object (segment.fragments sets it; may be empty): the level-set mesher tells fracture
    // faces from outer faces by it (fracture_faces.hpp).
    LevelSet object;
};

// Broken object, eq. (6.1): max(Phi_o, -min_c Phi_c). Throws std::invalid_argument naming the
// crack when it is empty, has another voxel size, or lies entirely outside the object.
LevelSet broken_object(const LevelSet& object, const CrackLevelSets& cracks);

struct SegmentOptions {
    double threshold = -1;  // s [m] in [0, r_f]; negative means s = r_f (the thesis default)
    bool use_tiles = true;  // tile-aware search: keeps cracks deep inside the object
    // [m^3]: a fragment whose volume lies below it is measured (volume, bbox, centroid, active
    // voxels) but keeps no grid, for a caller that drops it next (drop_small_fragments with the
    // same value). Its grid is freed as soon as it is measured: a run with a thousand specks
    // otherwise holds a thousand grids' nodes at once (fresh memory, faulted in page by page).
    double min_volume = 0;
};

// Throws std::invalid_argument when s is outside [0, r_f], with the reason.
Fragments find_fragments(const LevelSet& broken, const SegmentOptions& options = {});

// Removes fragments whose volume is below min_volume [m^3] (specks: slivers where two cracks
// pass close together or a crack runs along the surface); keeps the order. Returns how many were
// removed and adds their volume to *removed_volume if given. Throws std::invalid_argument for a
// negative or non-finite min_volume.
std::size_t drop_small_fragments(Fragments& f, double min_volume, double* removed_volume = nullptr);

// A fragment's object for a later fracture run (ch. 7.3): segmentation cut every crack of the run
// into the fragment as a thin slit; the cracks it keeps (incomplete, to grow again) must not read as
// "outside" ahead of their own fronts. Fills the slits of `cracks` where the fragment surrounds them
// (within 2 r_f of its material) and the parent object is inside: min(Phi_f, max(Phi_c, Phi_f - 2 r_f)).
LevelSet fill_crack_slits(const LevelSet& fragment, const LevelSet& parent, const std::vector<LevelSet>& cracks);

// d = round(1 + s / r_f): the ring of outside voxels copied around an over-segmented fragment.
int over_segmentation_ring(double s, double r_f);

// Listings: one row per fragment (index, volume, bbox, centroid, voxels). Written atomically.
void write_fragments_csv(const std::filesystem::path& path, const Fragments& f);
void write_fragments_json(const std::filesystem::path& path, const Fragments& f);

}  // namespace cf

CF_GRAPH_TYPE(cf::Fragments, "Fragments");
