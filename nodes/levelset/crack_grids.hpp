#pragma once
// Implicit fracture surfaces (thesis ch. 6.2): each crack is its own narrow-band grid holding
// Phi_f = (unsigned distance to the swept crack surface) - sqrt(3) r_f / 2, so the thin volume
// Phi_f < 0 encloses the surface without sampling holes. Recording after a crack-propagation
// sub-step voxelises only the new strip swept by the front and unions it in (min, eq. 6.1).
// No OpenVDB here: the grids sit behind cf::LevelSet / a pimpl.
#include "nodes/levelset/level_set.hpp"

#include <Eigen/Geometry>

#include <array>
#include <memory>
#include <vector>

namespace cf {

// All crack grids of one object, same voxel size; immutable once published.
struct CrackLevelSets {
    double voxel_size = 0;
    double half_width = 3;
    std::vector<LevelSet> cracks;
};

using Triangle3 = std::array<Vec3, 3>;

// Half the thickness of a recorded crack: sqrt(3) r_f / 2, half a cell diagonal (ch. 6.2).
inline double crack_half_thickness(double r_f) { return 0.8660254037844386 * r_f; }

// One crack front's motion in a sub-step: marker i moves p0[i] -> p1[i]; marker i is joined to
// i+1 (and the last to the first if `closed`). Deactivated markers have p1 == p0.
struct FrontMotion {
    std::vector<Vec3> p0, p1;
    bool closed = false;
};

// Which case of fig. 27 stopped a marker.
enum class MarkerHit { none, left_object, crossed_crack, self_intersection };
const char* to_string(MarkerHit h);

struct MarkerTest {
    MarkerHit hit = MarkerHit::none;
    int other_crack = -1;  // crossed_crack: index of the crack that was crossed
    double alpha = 1;      // where along p0 -> p1 the hit was found, in (0, 1]
};

// The strip swept by a front between two sub-steps, as triangles (two per joined marker pair;
// one fan triangle where one of the pair stopped, p1 == p0; none for a pair of stopped markers,
// whose segment an earlier strip already holds).
std::vector<Triangle3> strip_triangles(const FrontMotion& m);

// Closes the crack onto the object's surface across corners. Fig. 27 stops a marker once it leaves
// the object, and a neighbour that stopped earlier stays where it stopped; the fan between them
// (strip_triangles) then ends at the chord from the stopped marker to the other's new position,
// which cuts across the object's corner where the two left through different faces of an edge.
// Nothing sweeps the part of the crack's plane between that chord and the surface, and along the
// edge it is a bridge of inside voxels that keeps the pieces on both sides of the crack in one
// fragment (edge_crack_mode2 with square-root fronts: a bridge along the cube's vertical edge, up to
// 4 voxels wide). For every fan whose two ends lie within 2 r_f of the surface, the plane is
// continued outwards from its chord (perpendicular to it, away from the fan), every r_f along it,
// to r_f past the surface where that lies within half the chord's length (the widest a convex
// corner can be); nothing is added where the surface is not reached.
std::vector<Triangle3> surface_closure_triangles(const FrontMotion& m, const LevelSet& object);

// Marker tests of fig. 27 against grids holding the state up to the previous sub-step:
// (a) Phi_o(p1) > 0; (b) Phi_f(x) < 0 for some x on p0 -> p1 and another crack f, sampled every
// r_f/4 so no crossing of the sqrt(3) r_f thick crack volume is missed; (c) eq. (6.2) on the
// marker's own crack, for a marker starting on it (Phi_f(p0) < 0) only after its path has left
// the crack (Phi_f >= phi at an earlier sample). `object` may be null (no test (a)); `own` < 0
// skips (c).
MarkerTest test_marker(const LevelSet* object, const std::vector<LevelSet>& cracks, int own, const Vec3& p0,
                       const Vec3& p1);

// Mutable crack grids during a fracture run. Not thread-safe per crack; record_substep
// parallelises across cracks itself (oneTBB; results independent of the thread count).
class CrackRecorder {
public:
    CrackRecorder(double r_f, double half_width = 3);
    explicit CrackRecorder(const CrackLevelSets& start);  // deep-copies the grids
    ~CrackRecorder();
    CrackRecorder(CrackRecorder&&) noexcept;
    CrackRecorder& operator=(CrackRecorder&&) noexcept;

    int add_crack();  // a new empty crack grid; returns its index
    std::size_t num_cracks() const;
    double voxel_size() const;

    // Unions the thickened unsigned distance of the triangles into crack c (only voxels within
    // the band of these triangles are visited; leaf-sized blocks in parallel, oneTBB, results
    // independent of the thread count). Returns the number of voxels it set or lowered (each
    // counted once, however many triangles reach it): on an empty grid, the band voxels.
    std::size_t add_triangles(int crack, const std::vector<Triangle3>& tris);

    // One sub-step for all cracks: motions[c] is crack c's front motion (p0 = previous front).
    // First tests every moving marker against the grids as they were (fig. 27), then records
    // each crack's new strip (with its surface_closure_triangles when `object` is given), in
    // parallel across cracks. Returns tests[c][i].
    std::vector<std::vector<MarkerTest>> record_substep(const std::vector<FrontMotion>& motions,
                                                        const LevelSet* object, std::size_t* voxels_written = nullptr);

    // Grids as they are now: snapshot() deep-copies, release() hands them over (recorder empty).
    CrackLevelSets snapshot() const;
    CrackLevelSets release();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A user-given planar crack: the disk of `radius` [m] around `center` with unit `normal`,
// triangulated finely enough (chord sag below r_f/10) and recorded as one crack grid.
LevelSet planar_disk_crack(const Vec3& center, const Vec3& normal, double radius, double r_f, double half_width = 3);

// Independent reference: the same thickened distance computed by OpenVDB's
// meshToUnsignedDistanceField (used by tests and the recording benchmark).
LevelSet reference_strip_level_set(const std::vector<Triangle3>& tris, double r_f, double half_width = 3);

}  // namespace cf

CF_GRAPH_TYPE(cf::CrackLevelSets, "CrackLevelSets");
CF_GRAPH_TYPE(std::vector<cf::FrontMotion>, "FrontMotions");  // one per crack, same order
CF_GRAPH_TYPE(std::vector<std::vector<cf::MarkerTest>>, "MarkerTests");  // [crack][marker]
