#pragma once
// A rigid-body scene whose breakable bodies fracture on impact (thesis ch. 7): a deterministic
// Bullet world advanced frame by frame; after every rigid step the contacts of each breakable body
// become collision tractions (impact_loads), and a body whose summed impulse or force reaches its
// thresholds gets a fracture run. The runs of one step are independent and run concurrently; the
// fracture itself is not here: a FractureRunner (the rigid.frame node runs the body's fracture
// pipeline) returns the fragments. A body that broke is replaced by its fragments (ch. 7.3: four
// volume classes, exact mass properties, the parent's motion) and the step is repeated from the
// state before it, without new fracture runs.
//
// Frames: every piece carries its fracture model (level set, BEM mesh) in the material frame of
// the body it came from, so level sets, cracks and material fields never move; a piece's
// material_to_body places that frame in its body frame (centre of mass, principal axes), and
// Bullet's pose places the body frame in the world. SI units throughout.
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/domain/material.hpp"
#include "nodes/fields/scalar_field.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_state.hpp"
#include "nodes/rigid/animation.hpp"
#include "nodes/rigid/fragment_motion.hpp"
#include "nodes/rigid/impact_loads.hpp"
#include "nodes/rigid/rigid_world.hpp"
#include "nodes/segment/fragments.hpp"

#include <Eigen/Geometry>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace cf {
class SurfaceClipper;  // nodes/segment/surface_fragments.hpp
}  // namespace cf

namespace cf::rigid {

// What a breakable body fractures with (rigid.body parameters). Shared by its fragments.
struct FractureSettings {
    Material material;
    ScalarField strength, toughness;
    double r_c = 0;                    // target crack element edge [m]
    long long bem_triangles = 300;     // BEM triangle target of remeshed fragments
    std::string method = "full";       // full | estimator | hybrid (assemble.sgbem)
    long long switch_elements = 3000;  // hybrid switch [elements]
    double impulse_threshold = 0;      // a run starts when sum J >= this [N s] ...
    double force_threshold = 0;        // ... or sum J / t_c >= this [N]
    double min_fragment_fraction = 1e-6;  // fragments below this fraction of the original volume are dropped
    double collision_mesh_factor = 5;  // non-convex collision meshes: this many times bem_triangles
    std::filesystem::path fracture_pipeline;  // the pipeline a collision runs (absolute)
    ContactDurationLimits limits;
};

// The fracture model of a breakable piece, in its original body's material frame.
struct BreakableModel {
    std::shared_ptr<const FractureSettings> settings;
    LevelSet object;                        // voxel size r_f
    // The authored body's object (same material frame and r_f; empty: `object` is it): its
    // fragments' faces deeper inside it are fracture faces (region "inside", fracture_faces.hpp),
    // whichever generation made them.
    LevelSet authored;
    std::shared_ptr<const SurfaceMesh> bem_mesh;
    // [m] How far the BEM surface stands off the object: the 90th percentile of its elements'
    // centroids' distances outside it along their inward normals, measured when the mesh was made
    // (a class (d) fragment keeps its parent's mesh and this value; where a chip broke off, its mesh
    // stands off farther, and no hexagon starts there). Initiation places hexagons below the
    // object's surface within 1.25 times this distance (impact_plan).
    double bem_standoff = 0;
    // The authored mesh (material frame) its fragments are drawn with, prepared once for the
    // surface mesher (issue 14), which clips it to each fragment's cell: its triangles outside,
    // fracture faces in region "inside". Null (rigid.body fragment_mesh: levelset, or a mesh that
    // cannot be clipped): the fragments are drawn with their level-set meshes. Their motion is the
    // same either way: mass, inertia and collision shapes come from the level-set meshes.
    std::shared_ptr<const SurfaceClipper> surface;
    // A fragment's cell (FragmentCells: the region its mesh was clipped to, within its parent's
    // cell); its own fragments' cells stay within it, so every generation keeps the fracture
    // faces of the ones before. Empty for an authored body.
    LevelSet cell;
    std::vector<double> curvature;          // |H| per BEM triangle [1/m] (Hertz radius)
    double volume = 0;                      // level-set volume [m^3]
    double original_volume = 0;             // of the authored body it descends from [m^3]
    // Incomplete cracks from earlier runs (ch. 7.3, fig. 43): the next run starts from them, so old
    // cracks grow again. Null: the body has none.
    std::shared_ptr<const propagate::FractureState> cracks;
    // The BEM surface blocks and their pure Neumann factorisation (D_R, eq. 7.4) from an earlier run
    // on bem_mesh: later runs of the body, and its class (d) fragment that keeps bem_mesh (ch. 7.3),
    // reuse them instead of assembling and factorising again. Null before the first run.
    std::shared_ptr<const bem::SurfaceOperators> surface_blocks;
    std::shared_ptr<const bem::SurfaceSystem> surface_factor;
};

// A fragment as a rigid body (ch. 7.3): `material_mesh` is its surface in the parent's material frame,
// `volume` its level-set volume [m^3]. Mass = volume * density; centre of mass and inertia exactly
// from the mesh (scaled to that mass); body frame at the centre of mass on the principal axes; the
// motion is the parent's rigid velocity field at the fragment's centre (fragment_motion).
struct FragmentBody {
    MassProperties mass;                    // world axes
    Eigen::Isometry3d material_to_body = Eigen::Isometry3d::Identity();
    RigidMotion motion;
};
FragmentBody fragment_body(const SurfaceMesh& material_mesh, double volume, double density,
                           const Eigen::Isometry3d& material_to_world, const RigidMotion& parent);

// A closed surface of about `target_triangles` for `object` (BEM or collision mesh): remeshed
// (simplify.remesh's algorithm) from a grid about a quarter of the target edge length, offset
// outward by `offset_voxels` voxels of r_f (retried without offset when the offset folds it). With an
// offset, it is grown further until the surface encloses the object within half a voxel of r_f
// (sampled at vertices, edge midpoints and centroids): crack elements end just inside the object.
SurfaceMesh coarse_surface(const LevelSet& object, std::size_t target_triangles, double offset_voxels);

// Why `bem_mesh` cannot be a breakable body's BEM surface for `mesh` (both in the material frame),
// or "" when it can: it must be a closed, consistently oriented 2-manifold enclosing positive
// volume, with every vertex within a quarter of its mean edge length of `mesh` (a remesh offset by a
// voxel passes; a mesh of another object, scale or placement does not).
std::string bem_mesh_problem(const SurfaceMesh& bem_mesh, const SurfaceMesh& mesh);

// Remeshes `object` to the settings' BEM target (coarse_surface, one voxel outward and enclosing),
// or keeps `bem_mesh` when given (class (d) fragments keep their parent's). `volume` [m^3]: the
// fragment's volume from segmentation (OpenVDB's LevelSetMeasure misreads fragment grids, by up to
// 7 %); 0: measured on `object` (a level set made from a mesh).
BreakableModel make_breakable_model(std::shared_ptr<const FractureSettings> settings, LevelSet object,
                                    double original_volume, std::shared_ptr<const SurfaceMesh> bem_mesh = nullptr,
                                    double volume = 0);

// A body as authored (rigid.body).
struct BodyDescription {
    std::string name;
    BodyKind kind = BodyKind::dynamic;
    CollisionShape collision = CollisionShape::hull;
    SurfaceMesh mesh;                        // closed, outward; material frame [m]
    Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  // material frame -> world at the start
    double density = 1000;                   // [kg/m^3]
    double E = 1e10, nu = 0.25;              // elastic constants for the Hertz contact [Pa, -]
    Vec3 velocity = Vec3::Zero();            // of the centre of mass [m/s]
    Vec3 angular_velocity = Vec3::Zero();    // [rad/s], world axes
    double friction = 0.5, restitution = 0.0;
    std::shared_ptr<const BreakableModel> breakable;  // null: never breaks
};
using BodyList = std::vector<std::shared_ptr<const BodyDescription>>;

struct SceneSettings {
    WorldSettings world;
    double frame_rate = 50;         // [1/s]; steps per frame = round(1 / (frame_rate * time_step))
    bool ground = true;             // a static plane through ground_point, normal -gravity direction
    Vec3 ground_point = Vec3::Zero();
    double ground_friction = 0.5, ground_restitution = 0.0;
    double ground_E = 3e10, ground_nu = 0.2;  // the ground's elastic constants (Hertz) [Pa, -]
    double overlap_tolerance = 0;   // [m] deeper initial overlaps are errors; 0: 2 % of the smallest body
    long long max_pieces = 100000;  // a scene that exceeds this many pieces stops with an error
};

// What the fracture pipeline of one run receives (rigid.impact outputs it).
struct ImpactRun {
    std::string body;                // the piece's name
    int frame = 0, step = 0;         // frame being computed, rigid step within the run
    std::shared_ptr<const BreakableModel> model;
    bem::BoundaryConditions conditions;  // balanced per-element tractions (eq. 7.5), traction 0 elsewhere
    long long max_steps = 1;         // BEM time steps whose simulated time fits min(dt, t_c)
    std::filesystem::path output_dir;  // where the run writes (relative to the scene's output directory)
};
// What a fracture run returns: the fragments and the run's final fracture state (its cracks).
struct ImpactOutcome {
    Fragments fragments;
    std::shared_ptr<const propagate::FractureState> state;  // may be null (a pipeline without one)
    // The run's first surface assembly and factorisation (BreakableModel::surface_blocks/factor); may be null.
    std::shared_ptr<const bem::SurfaceOperators> surface_blocks;
    std::shared_ptr<const bem::SurfaceSystem> surface_factor;
};
using FractureRunner = std::function<ImpactOutcome(const ImpactRun&)>;

struct FractureRunRecord {
    int frame = 0;
    std::string body;
    double impulse = 0, force = 0;   // [N s], [N]
    double contact_duration = 0;     // [s]
    long long max_steps = 0;
    std::size_t bem_triangles = 0;
    int fragments = 0, dropped = 0;  // kept fragments (1: did not break), specks dropped
    std::size_t crack_triangles = 0;  // in the run's final state (all cracks, complete or not)
    std::size_t carried_triangles = 0;  // incomplete-crack triangles carried into the pieces it left
    // Incomplete cracks the run started from (carried in from earlier runs): their triangles at the
    // start and at the end of the run (growth of old cracks, ch. 7.3).
    std::size_t old_crack_triangles_start = 0, old_crack_triangles_end = 0;
    double seconds = 0;              // wall time of the run
    bool broke = false;
    std::string error;               // non-empty: the run failed and the body stayed whole
};

struct FrameReport {
    int fracture_runs = 0, breaks = 0, new_pieces = 0;
    // Per fragment drawn with its level-set mesh although its parent keeps its surface (the
    // surface mesher could not clip it): which and why.
    std::vector<std::string> warnings;
    // Fragments drawn with the authored surface but with folds in their fracture faces that could
    // not be mended (closed and manifold, a few fracture faces crossing).
    int surface_folded = 0;
    double rigid_seconds = 0, fracture_seconds = 0;
};

class SceneSimulation {
public:
    // Throws std::invalid_argument naming the body for a bad body or settings (an open mesh, a
    // non-positive density, a body starting inside another).
    SceneSimulation(const SceneSettings& settings, const BodyList& bodies, FractureRunner runner);
    ~SceneSimulation();
    SceneSimulation(const SceneSimulation&) = delete;
    SceneSimulation& operator=(const SceneSimulation&) = delete;

    // Advances one frame (steps_per_frame rigid steps with their fracture runs). `cancelled` is
    // polled between steps and may throw.
    FrameReport advance_frame(const std::function<void()>& check_cancelled = {});

    int frame() const { return frame_; }
    double time() const;
    int steps_per_frame() const { return steps_per_frame_; }
    const SceneSettings& settings() const { return settings_; }
    AnimationFrame current_frame() const;             // poses of the live pieces now
    const std::vector<AnimationPiece>& pieces() const;  // every piece so far (animation order)
    const std::vector<FractureRunRecord>& runs() const;
    std::size_t live_pieces() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    SceneSettings settings_;
    int frame_ = 0;
    int steps_per_frame_ = 1;
};

}  // namespace cf::rigid

CF_GRAPH_TYPE(cf::rigid::BodyList, "BodyList");
