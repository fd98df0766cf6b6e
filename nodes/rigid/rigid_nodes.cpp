// Node adapters for nodes/rigid (thesis ch. 7): rigid.body (a body of a scene, chained into a body
// list), rigid.scene (the Bullet world at frame 0), rigid.frame (one frame of the scene's frame loop,
// with the fracture runs its collisions start), rigid.impact and rigid.fragments (the two ends of a
// fracture pipeline that a collision runs), export.animation (glTF and the points cache).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/bem/bem_types.hpp"
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/registration.hpp"
#include "nodes/rigid/animation_gltf.hpp"
#include "nodes/rigid/impact_pipeline.hpp"
#include "nodes/rigid/scene_state.hpp"
#include "nodes/rigid/scene_preview.hpp"
#include "nodes/rigid/scene_report.hpp"
#include "nodes/rigid/transform_cache.hpp"
#include "nodes/segment/surface_fragments.hpp"
#include "nodes/vec3_param.hpp"

#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <stdexcept>

namespace cf {
namespace {

using rigid::BodyList;

Eigen::Matrix3d rotation_from_degrees(const Vec3& deg) {
    const double k = M_PI / 180;
    return (Eigen::AngleAxisd(k * deg.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(k * deg.y(), Vec3::UnitY()) *
            Eigen::AngleAxisd(k * deg.x(), Vec3::UnitX()))
        .toRotationMatrix();
}

std::filesystem::path resolve_pipeline(const graph::NodeContext& c, const std::string& file) {
    std::filesystem::path p(file);
    if (p.is_relative() && !c.run_options().pipeline_dir.empty()) p = c.run_options().pipeline_dir / p;
    return std::filesystem::absolute(p).lexically_normal();
}

// rigid.body's declaration and run, in steps.

void declare_body_ports(graph::NodeType& t) {
    t.input<SurfaceMesh>("mesh", "closed, outward-oriented surface (material frame) [m]");
    t.optional_input<Material>("material", "material.brittle: density, E and nu, strength and toughness; required when breakable");
    t.optional_input<ScalarField>("strength", "tensile strength field [Pa] (default: homogeneous, the material's)");
    t.optional_input<ScalarField>("toughness", "toughness field [Pa*sqrt(m)] (default: homogeneous, the material's)");
    t.optional_input<SurfaceMesh>("bem_mesh", "breakable: the coarse BEM surface to use instead of remeshing the level set "
                                  "to 'bem_triangles' (material frame, on the body's surface: e.g. shape.box with "
                                  "'cell_size' for a slender bar); fragments are remeshed as usual");
    t.optional_input<BodyList>("after", "the bodies inserted before this one");
    t.output<BodyList>("bodies", "'after' with this body appended");
}

void declare_body_params(graph::NodeType& t) {
    t.param_string("name", "", "body name in outputs (unique in the scene); empty: the node's name");
    t.param_choice("kind", "dynamic", {"dynamic", "kinematic", "static"},
                   "dynamic (moves under gravity and contacts), kinematic (moves at its velocity, not pushed), static");
    t.param_choice("collision", "hull", {"hull", "mesh"},
                   "collision shape: the convex hull, or the triangle mesh itself (non-convex: tori, bowls)");
    t.param_reals("position", {0, 0, 0}, "m", "translation applied to the mesh after 'rotation'").size(3);
    t.param_reals("rotation", {0, 0, 0}, "deg", "rotation of the mesh about the origin: x, then y, then z axis").size(3);
    t.param_reals("velocity", {0, 0, 0}, "m/s", "initial velocity of the centre of mass").size(3);
    t.param_reals("angular_velocity", {0, 0, 0}, "rad/s", "initial angular velocity (world axes)").size(3);
    t.param_real("density", 0, "kg/m^3", "density; 0: the material's rho (required without material)").range(0, 1e5);
    t.param_real("E", 0, "Pa", "Young's modulus for the Hertz contact duration; 0: the material's, else 1e10")
        .range(0, 1e13);
    t.param_real("nu", 0.25, "", "Poisson's ratio for the Hertz contact (without material)").at_least(0).below(0.5);
    t.param_real("friction", 0.5, "", "Coulomb friction coefficient").range(0, 10);
    t.param_real("restitution", 0.1, "", "coefficient of restitution").range(0, 1);
    t.param_bool("breakable", false, "the body fractures on impact (needs 'material')");
    t.param_real("r_f", 0, "m", "breakable: fine resolution (level-set voxel size)").at_least(0);
    t.param_real("r_c", 0, "m", "breakable: crack element edge in the BEM mesh (> r_f; 0: 20 r_f)").at_least(0);
    t.param_int("bem_triangles", 400, "breakable: BEM triangle target (this body and its large fragments)").range(20, 200000);
    t.param_choice("method", "full", {"full", "estimator", "hybrid"}, "breakable: crack unknowns (ch. 5), as assemble.sgbem");
    t.param_int("switch_elements", 3000, "breakable, hybrid: BEM elements above which growth is estimated").at_least(0);
    t.param_real("impulse_threshold", -1, "N s", "breakable: summed normal impulse of a step that starts a fracture run; "
                 "-1: the body's mass times 1 m/s").at_least(-1);
    t.param_real("force_threshold", -1, "N", "breakable: summed contact force sum J / t_c that starts a fracture run; "
                 "-1: threshold_fraction * tensile strength * mean BEM element area").at_least(-1);
    t.param_real("threshold_fraction", 0.25, "", "breakable: see force_threshold").above(0).at_most(1);
    t.param_real("min_fragment_fraction", 1e-6, "", "breakable: fragments below this fraction of the original volume are "
                 "dropped (counted)").range(0, 0.01);
    t.param_choice("fragment_mesh", "surface", {"surface", "levelset"},
                   "breakable: what fragments are drawn with: surface keeps the body's own triangles (clipped where "
                   "cracks cut them; fracture faces in the material 'inside'), levelset draws each fragment's "
                   "level-set mesh. Their motion is the same either way");
    t.param_string("fracture", "",
                   "breakable: the fracture pipeline a collision runs (relative to this pipeline's file); empty: the "
                   "built-in one, pipelines/impact/fracture.yaml");
}

// The body's kind, shape, placement, motion, contact and mass properties from the parameters
// (and the material where a parameter is 0).
std::shared_ptr<rigid::BodyDescription> describe_body(graph::NodeContext& c, const Material* m) {
    auto b = std::make_shared<rigid::BodyDescription>();
    b->name = c.string("name").empty() ? c.node_name() : c.string("name");
    const std::string kind = c.string("kind");
    b->kind = kind == "dynamic" ? rigid::BodyKind::dynamic
              : kind == "kinematic" ? rigid::BodyKind::kinematic : rigid::BodyKind::fixed;
    b->collision = c.string("collision") == "mesh" ? rigid::CollisionShape::mesh : rigid::CollisionShape::hull;
    b->mesh = c.in<SurfaceMesh>("mesh");
    b->placement = Eigen::Isometry3d::Identity();
    b->placement.linear() = rotation_from_degrees(vec3_param(c, "rotation"));
    b->placement.translation() = vec3_param(c, "position");
    b->velocity = vec3_param(c, "velocity");
    b->angular_velocity = vec3_param(c, "angular_velocity");
    b->friction = c.real("friction");
    b->restitution = c.real("restitution");
    b->density = c.real("density") > 0 ? c.real("density") : m ? m->rho : 0.0;
    if (!(b->density > 0) && b->kind == rigid::BodyKind::dynamic)
        c.fail("body '" + b->name + "': parameter 'density' [kg/m^3] is needed (or connect 'material')");
    if (!(b->density > 0)) b->density = 1000;  // static and kinematic bodies: mass unused
    b->E = c.real("E") > 0 ? c.real("E") : m ? m->E : 1e10;
    b->nu = m && c.real("E") == 0 ? m->nu : c.real("nu");
    const double signed_vol = signed_volume(b->mesh);
    if (!(signed_vol > 0))
        c.fail("body '" + b->name + "': the mesh encloses no positive volume; it must be closed and outward oriented");
    return b;
}

// A breakable body's fracture settings: material, fields, r_c, method and its fracture pipeline,
// loaded here so a bad pipeline fails now, not at the first impact.
std::shared_ptr<rigid::FractureSettings> fracture_settings(graph::NodeContext& c, const rigid::BodyDescription& b,
                                                           const Material& m, double r_f) {
    auto fs = std::make_shared<rigid::FractureSettings>();
    fs->material = m;
    fs->material.rho = b.density;
    fs->strength = c.has("strength") ? c.in<ScalarField>("strength")
                                     : make_field(std::make_shared<HomogeneousField>(m.tensile_strength),
                                                  FieldQuantity::strength, m.compressive_factor);
    fs->toughness = c.has("toughness") ? c.in<ScalarField>("toughness")
                                       : make_field(std::make_shared<HomogeneousField>(m.toughness),
                                                    FieldQuantity::toughness, m.compressive_factor);
    fs->r_c = c.real("r_c") > 0 ? c.real("r_c") : 20 * r_f;
    if (!(fs->r_c > r_f)) c.fail("body '" + b.name + "': parameter 'r_c' must exceed r_f");
    fs->bem_triangles = c.integer("bem_triangles");
    fs->method = c.string("method");
    fs->switch_elements = c.integer("switch_elements");
    fs->min_fragment_fraction = c.real("min_fragment_fraction");
    if (!c.string("fracture").empty()) fs->fracture_pipeline = resolve_pipeline(c, c.string("fracture"));
    if (!c.run_options().registry) c.fail("no node registry to load the fracture pipeline with");
    try {
        rigid::load_impact_pipeline(fs->fracture_pipeline, *c.run_options().registry);  // fail early, not at impact
    } catch (const std::invalid_argument& e) {
        c.fail("body '" + b.name + "', parameter 'fracture': " + e.what());
    }
    return fs;
}

// A breakable body's model: level set at r_f, BEM mesh (given or remeshed) and the thresholds
// that start a fracture run (defaults from the body's mass and mean BEM element area).
std::shared_ptr<const rigid::BreakableModel> breakable_model(graph::NodeContext& c, const rigid::BodyDescription& b,
                                                             const Material& m, double r_f) {
    auto fs = fracture_settings(c, b, m, r_f);
    std::shared_ptr<const SurfaceMesh> bem_mesh;
    if (c.has("bem_mesh")) {
        bem_mesh = c.in_ptr<SurfaceMesh>("bem_mesh");
        const std::string problem = rigid::bem_mesh_problem(*bem_mesh, b.mesh);
        if (!problem.empty()) c.fail("body '" + b.name + "', input 'bem_mesh': " + problem);
    }
    rigid::BreakableModel model;
    try {
        model = rigid::make_breakable_model(fs, level_set_from_mesh(b.mesh, r_f), 0, bem_mesh);
    } catch (const std::exception& e) {
        c.fail("body '" + b.name + "' (parameters 'r_f', 'bem_triangles'): " + e.what());
    }
    const double mass = model.volume * b.density;
    const double mean_area = surface_area(*model.bem_mesh) / double(model.bem_mesh->num_triangles());
    fs->impulse_threshold = c.real("impulse_threshold") >= 0 ? c.real("impulse_threshold") : mass * 1.0;
    fs->force_threshold = c.real("force_threshold") >= 0 ? c.real("force_threshold")
                                                         : c.real("threshold_fraction") * m.tensile_strength * mean_area;
    model.settings = fs;
    if (c.string("fragment_mesh") == "surface") {
        // A mesh the surface mesher cannot clip (one that intersects itself, e.g. overlapping parts
        // of a scan) still fractures: its fragments are drawn with their level-set meshes.
        try {
            model.surface = std::make_shared<const SurfaceClipper>(b.mesh);  // prepared once for every break
        } catch (const std::invalid_argument& e) {
            std::cerr << "warning: rigid.body '" << b.name << "': its fragments are drawn with their level-set meshes, "
                      << "not its own triangles: " << e.what() << " (set 'fragment_mesh' to levelset to silence this)\n";
            c.count("surface_unclippable", 1);
        }
    }
    c.count("bem_triangles", double(model.bem_mesh->num_triangles()));
    c.count("volume_m3", model.volume);
    c.count("bem_standoff_m", model.bem_standoff);
    c.count("impulse_threshold_Ns", fs->impulse_threshold);
    c.count("force_threshold_N", fs->force_threshold);
    return std::make_shared<const rigid::BreakableModel>(std::move(model));
}

void run_body(graph::NodeContext& c) {
    const Material* m = c.has("material") ? &c.in<Material>("material") : nullptr;
    auto b = describe_body(c, m);
    if (c.boolean("breakable")) {
        if (!m) c.fail("body '" + b->name + "': parameter 'breakable' needs the input 'material' (material.brittle)");
        if (b->kind != rigid::BodyKind::dynamic)
            c.fail("body '" + b->name + "': only dynamic bodies can be breakable (parameter 'kind')");
        const double r_f = c.real("r_f");
        if (!(r_f > 0)) c.fail("body '" + b->name + "': parameter 'r_f' [m] must be positive for a breakable body");
        b->breakable = breakable_model(c, *b, *m, r_f);
    }
    BodyList list = c.has("after") ? c.in<BodyList>("after") : BodyList{};
    for (const auto& other : list)
        if (other->name == b->name) c.fail("body '" + b->name + "' is already in the list ('after'); names must be unique");
    list.push_back(b);
    c.count("bodies", double(list.size()));
    c.out("bodies", std::move(list));
}

graph::NodeType body_node() {
    graph::NodeType t(
        "rigid.body",
        "A rigid body of a scene (thesis ch. 7): its mesh placed by 'position' and 'rotation', its motion, contact "
        "properties and, when 'breakable', its fracture settings. Bodies chain through 'after' into the list "
        "rigid.scene takes, in a fixed order (Bullet's insertion order, so the scene is deterministic). A breakable "
        "body gets its level set at r_f and a BEM mesh of 'bem_triangles' here, once; each collision above a "
        "threshold runs the fracture pipeline 'fracture' on them (ch. 7.2). Thresholds default to finite values "
        "from the body: the force at which the contact traction on one BEM element of mean area reaches "
        "'threshold_fraction' of the tensile strength, and the impulse that would stop the body at 1 m/s.");
    declare_body_ports(t);
    declare_body_params(t);
    t.run(run_body);
    return t;
}

// Plans of fracture pipelines, loaded once per file for the whole scene.
class PlanCache {
public:
    explicit PlanCache(const graph::NodeRegistry* r) : registry_(r) {}
    std::shared_ptr<const graph::Plan> get(const std::filesystem::path& file) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto& p = plans_[file.string()];
        if (!p) p = rigid::load_impact_pipeline(file, *registry_);
        return p;
    }

private:
    const graph::NodeRegistry* registry_;
    std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const graph::Plan>> plans_;
};

graph::NodeType scene_node() {
    graph::NodeType t("rigid.scene",
                      "A rigid-body scene at frame 0 (thesis ch. 7): a deterministic Bullet world in double precision "
                      "(single-threaded, fixed step, bodies in list order) with the bodies and an optional ground plane "
                      "normal to gravity. A frame loop of rigid.frame nodes advances it.");
    t.input<BodyList>("bodies", "from the last rigid.body of the chain");
    t.output<rigid::SceneState>("scene", "the scene at frame 0");
    t.param_reals("gravity", {0, 0, -9.81}, "m/s^2", "gravitational acceleration").size(3);
    t.param_real("time_step", 1.0 / 250, "s", "rigid-body step (the thesis used 1/250 to 1/2000)").above(0).at_most(1);
    t.param_real("frame_rate", 50, "1/s", "animation frames per second; a frame must be a whole number of steps").above(0).at_most(1e5);
    t.param_int("solver_iterations", 20, "Bullet's constraint solver iterations per step").range(1, 1000);
    t.param_bool("ground", true, "a static ground plane through 'ground_point', normal to gravity");
    t.param_reals("ground_point", {0, 0, 0}, "m", "a point of the ground plane").size(3);
    t.param_real("ground_friction", 0.5, "", "friction coefficient of the ground").range(0, 10);
    t.param_real("ground_restitution", 0.1, "", "restitution of the ground").range(0, 1);
    t.param_real("ground_E", 3e10, "Pa", "Young's modulus of the ground (Hertz contact duration; concrete)").range(1e3, 1e13);
    t.param_real("ground_nu", 0.2, "", "Poisson's ratio of the ground").at_least(0).below(0.5);
    t.param_int("max_pieces", 100000, "stop with an error when the scene holds more pieces").range(1, 10000000);
    t.run([](graph::NodeContext& c) {
        rigid::SceneSettings s;
        s.world.gravity = vec3_param(c, "gravity");
        s.world.time_step = c.real("time_step");
        s.world.solver_iterations = static_cast<int>(c.integer("solver_iterations"));
        s.frame_rate = c.real("frame_rate");
        s.ground = c.boolean("ground");
        s.ground_point = vec3_param(c, "ground_point");
        s.ground_friction = c.real("ground_friction");
        s.ground_restitution = c.real("ground_restitution");
        s.ground_E = c.real("ground_E");
        s.ground_nu = c.real("ground_nu");
        s.max_pieces = c.integer("max_pieces");
        if (!c.run_options().registry) c.fail("no node registry to load fracture pipelines with");
        auto cache = std::make_shared<PlanCache>(c.run_options().registry);
        rigid::FractureRunner runner = rigid::pipeline_runner(
            c.run_options(), [cache](const rigid::ImpactRun& run) { return cache->get(run.model->settings->fracture_pipeline); });
        std::shared_ptr<rigid::SceneSimulation> sim;
        try {
            sim = std::make_shared<rigid::SceneSimulation>(s, c.in<BodyList>("bodies"), std::move(runner));
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.count("bodies", double(sim->live_pieces()));
        c.count("steps_per_frame", sim->steps_per_frame());
        c.out("scene", rigid::record_frame(sim, nullptr));
    });
    return t;
}

graph::NodeType frame_node() {
    graph::NodeType t("rigid.frame",
                      "One animation frame of a scene (thesis ch. 7): its rigid steps; after each, every breakable body "
                      "whose collisions reach its thresholds gets a fracture run (its 'fracture' pipeline; runs of one "
                      "step run concurrently), a body that broke is replaced by its fragments (ch. 7.3: hull below 0.5 % "
                      "of the original volume, collision mesh up to 2 %, breakable above, parent's BEM mesh above 95 % "
                      "of the parent) moving as the parent did, and the step is repeated without new runs. A body that "
                      "withstood a load is run again only for a load 25 % larger.");
    t.input<rigid::SceneState>("scene", "the scene after the previous frame (from rigid.scene or the loop)");
    t.output<rigid::SceneState>("scene", "the scene one frame later");
    t.run([](graph::NodeContext& c) {
        const rigid::SceneState& in = c.in<rigid::SceneState>("scene");
        rigid::FrameReport r;
        try {
            r = in.simulation->advance_frame([&c] { c.check_cancelled(); });
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        } catch (const graph::Cancelled&) {
            throw;
        } catch (const std::runtime_error& e) {
            c.fail(e.what());
        }
        rigid::SceneState out = rigid::record_frame(in.simulation, &in);
        out.rigid_seconds += r.rigid_seconds;
        out.fracture_seconds += r.fracture_seconds;
        c.count("frame", out.frame);
        c.count("pieces", double(in.simulation->live_pieces()));
        c.count("fracture_runs", r.fracture_runs);
        c.count("breaks", r.breaks);
        c.count("new_pieces", r.new_pieces);
        c.count("surface_fallbacks", double(r.warnings.size()));
        c.count("surface_folded", r.surface_folded);
        for (const std::string& w : r.warnings) std::cerr << "warning: rigid.frame: " << w << '\n';
        c.count("rigid_seconds", r.rigid_seconds);
        c.count("fracture_seconds", r.fracture_seconds);
        c.out("scene", std::move(out));
    });
    return t;
}

graph::NodeType impact_node() {
    graph::NodeType t("rigid.impact",
                      "The start of a fracture pipeline that a collision runs (rigid.frame hands in the body and its "
                      "loads): the body's BEM mesh and level set in its material frame, its material and fields, and "
                      "the balanced collision tractions (eq. 7.5) for solve.sgbem's 'conditions' (a pure Neumann "
                      "problem, eq. 7.4). Not for running on its own.");
    t.output<SurfaceMesh>("mesh", "the body's BEM surface (material frame)");
    t.output<LevelSet>("object", "the body's level set at r_f");
    t.output<Material>("material", "the body's material");
    t.output<ScalarField>("strength", "tensile strength field [Pa]");
    t.output<ScalarField>("toughness", "toughness field [Pa*sqrt(m)]");
    t.output<bem::BoundaryConditions>("conditions", "per-element tractions [Pa] on every element");
    t.output<bem::BemOperators>("surface", "the body's BEM surface blocks from its last run (for assemble.sgbem's "
                                           "'reuse'; empty before the first run)");
    t.output<bem::BemSolution>("factor", "their pure Neumann factorisation (for solve.sgbem's 'reuse'; empty before "
                                         "the first run)");
    t.run([](graph::NodeContext& c) {
        const graph::Value* v = c.pipeline_input("impact");
        if (!v)
            c.fail("this pipeline is a fracture pipeline for rigid-body scenes: rigid.frame runs it per collision and "
                   "hands in the body and its loads; run a scene (e.g. pipelines/falling_objects.yaml) instead");
        const rigid::ImpactRun& run = v->get<rigid::ImpactRun>();
        const rigid::BreakableModel& m = *run.model;
        c.count("bem_triangles", double(m.bem_mesh->num_triangles()));
        c.count("max_steps", double(run.max_steps));
        c.out_shared("mesh", m.bem_mesh);
        c.out("object", m.object);
        c.out("material", m.settings->material);
        c.out("strength", m.settings->strength);
        c.out("toughness", m.settings->toughness);
        c.out("conditions", run.conditions);
        bem::BemOperators surface;
        surface.surface = m.surface_blocks;
        c.out("surface", std::move(surface));
        bem::BemSolution factor;
        factor.surface = m.surface_blocks;
        factor.system = m.surface_factor;
        c.out("factor", std::move(factor));
        c.count("surface_cached", m.surface_blocks ? 1 : 0);
    });
    return t;
}

graph::NodeType carried_cracks_node() {
    graph::NodeType t("rigid.cracks",
                      "The fracture state a collision's run starts from (ch. 7.3): the incomplete cracks the body "
                      "carries from earlier runs (those that did not separate it, or that a large fragment kept), "
                      "else 'start' (no cracks). Its crack sheets go to the first assembly, so old cracks are solved "
                      "for and grow again (thesis fig. 43).");
    t.input<propagate::FractureState>("start", "the empty state (fracture.start)");
    t.output<propagate::FractureState>("state", "the body's cracks, or 'start'");
    t.output<SurfaceMesh>("cracks", "their BEM crack sheets (empty without cracks)");
    t.run([](graph::NodeContext& c) {
        const graph::Value* v = c.pipeline_input("impact");
        if (!v) c.fail("rigid.cracks belongs to a fracture pipeline that a rigid-body scene runs per collision");
        const auto& cracks = v->get<rigid::ImpactRun>().model->cracks;
        if (cracks) {
            c.count("carried_crack_triangles", double(cracks->cracks.num_triangles()));
            c.out_shared("state", cracks);
            c.out("cracks", cracks->cracks);
        } else {
            c.count("carried_crack_triangles", 0);
            c.set_output("state", c.input_value("start"));
            c.out("cracks", c.in<propagate::FractureState>("start").cracks);
        }
    });
    return t;
}

graph::NodeType fragments_result_node() {
    graph::NodeType t("rigid.fragments",
                      "The result of a fracture pipeline that a collision runs: its fragments go back to the scene "
                      "(rigid.frame), which turns them into rigid bodies.");
    t.input<Fragments>("fragments", "from segment.fragments");
    t.input<propagate::FractureState>("state", "the run's final fracture state: its cracks stay in the pieces they did "
                                               "not separate and grow again in later runs (ch. 7.3)");
    t.output<Fragments>("fragments", "the same, for the scene");
    t.output<propagate::FractureState>("state", "the same, for the scene");
    t.run([](graph::NodeContext& c) {
        c.count("fragments", double(c.in<Fragments>("fragments").fragments.size()));
        c.count("crack_triangles", double(c.in<propagate::FractureState>("state").cracks.num_triangles()));
        c.set_output("fragments", c.input_value("fragments"));
        c.set_output("state", c.input_value("state"));
    });
    return t;
}

graph::NodeType export_animation_node() {
    graph::NodeType t("export.animation",
                      "Writes a scene's animation (thesis ch. 8): a glTF 2.0 binary with one node per body and fragment "
                      "(its high-resolution rest mesh, translation and rotation keyed every frame, appearing and "
                      "disappearing by scale; Blender, any glTF viewer), a points-as-transforms cache for Houdini's "
                      "Transform Pieces (per frame one point per piece with name, P, orient, pivot, v, w; VTK PolyData "
                      "and a .pvd collection for ParaView), and the fracture runs as CSV and JSON.");
    t.input<rigid::SceneState>("scene", "the scene after its last frame (LOOP.final)");
    t.param_string("glb", "scene.glb", "glTF binary; relative to the run's output directory; empty: none").writes_file();
    t.param_string("cache", "pieces/pieces", "points cache: directory and file stem; empty: none").writes_file();
    t.param_string("runs", "fracture_runs", "fracture runs listing: <runs>.csv and <runs>.json; empty: none").writes_file();
    t.param_reals("up", {0, 0, 1}, "", "the scene's up axis, mapped onto glTF's +Y").size(3);
    t.output<std::string>("directory", "the output directory");
    t.run([](graph::NodeContext& c) {
        const rigid::SceneState& s = c.in<rigid::SceneState>("scene");
        const rigid::Animation a = rigid::animation_of(s);
        try {
            if (!c.string("glb").empty()) {
                rigid::GltfOptions o;
                o.up = vec3_param(c, "up");
                if (!(o.up.norm() > 0)) c.fail("parameter 'up': must not be zero");
                rigid::write_animation_glb(a, c.output_path(c.string("glb")), o);
            }
            if (!c.string("cache").empty()) {
                const std::filesystem::path p = c.output_path(c.string("cache"));
                rigid::write_transform_cache(a, p.parent_path(), p.filename().string());
            }
            if (!c.string("runs").empty()) rigid::write_fracture_runs(c.output_path(c.string("runs")), *s.runs);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        std::map<std::string, int> classes;
        for (const rigid::AnimationPiece& p : a.pieces) ++classes[rigid::piece_class_name(p.piece_class)];
        for (const char* k : {"original", "hull", "mesh", "breakable", "large"}) c.count(std::string("pieces_") + k, classes[k]);
        c.count("frames", double(a.frames.size()));
        c.count("pieces", double(a.pieces.size()));
        c.count("fracture_runs", double(s.runs->size()));
        c.count("rigid_seconds", s.rigid_seconds);
        c.count("fracture_seconds", s.fracture_seconds);
        std::size_t largest = 0;
        for (const rigid::FractureRunRecord& r : *s.runs) largest = std::max(largest, r.bem_triangles);
        c.count("largest_bem_triangles", double(largest));
        std::size_t failed = 0, broke = 0;
        for (const rigid::FractureRunRecord& r : *s.runs) {
            failed += r.error.empty() ? 0 : 1;
            broke += r.broke ? 1 : 0;
        }
        c.count("failed_runs", double(failed));
        c.count("breaks", double(broke));
        c.out("directory", c.output_dir().string());
    });
    return t;
}

graph::NodeType scene_preview_node() {
    graph::NodeType t("export.scene_preview",
                      "Renders a scene's latest frame as a PNG (software z-buffer, flat shading, every body in its own "
                      "hue and its fragments in shades of it, the ground as a checkerboard); connect frames.each.scene "
                      "for one image per frame. Deterministic for any thread count.");
    t.input<rigid::SceneState>("scene", "a scene state (frames.each.scene: every frame)");
    t.param_string("path", "preview/frame_{iteration}.png",
                   "PNG file; relative to the run's output directory; '{iteration}' becomes the loop iteration").writes_file();
    t.param_reals("camera", {2.5, -3.0, 1.8}, "m", "camera position").size(3);
    t.param_reals("target", {0, 0, 0.3}, "m", "the point the camera looks at (image centre)").size(3);
    t.param_reals("up", {0, 0, 1}, "", "the scene's vertical (image up)").size(3);
    t.param_real("fov", 40, "deg", "vertical field of view").above(0).below(180);
    t.param_int("width", 640, "image width [pixels]").range(16, 8192);
    t.param_int("height", 480, "image height [pixels]").range(16, 8192);
    t.param_bool("ground", true, "draw the scene's ground plane (when it has one)");
    t.output<std::string>("path", "the file written");
    t.run([](graph::NodeContext& c) {
        rigid::SceneCamera cam;
        cam.position = vec3_param(c, "camera");
        cam.target = vec3_param(c, "target");
        cam.up = vec3_param(c, "up");
        cam.fov_degrees = c.real("fov");
        cam.width = static_cast<int>(c.integer("width"));
        cam.height = static_cast<int>(c.integer("height"));
        if (const std::string problem = rigid::scene_camera_problem(cam); !problem.empty()) c.fail("parameter " + problem);
        const rigid::SceneState& s = c.in<rigid::SceneState>("scene");
        // Only the latest frame: the pieces (rest meshes shared) and that frame's poses.
        rigid::Animation a;
        a.frame_rate = s.frame_rate;
        a.pieces = *s.pieces;
        a.frames.push_back(s.last->frame);
        const rigid::SceneSettings& settings = s.simulation->settings();  // fixed at construction
        const std::filesystem::path png = c.output_path(c.string("path"));
        try {
            rigid::render_scene_preview(a, 0, cam, png, settings.ground_point, -settings.world.gravity.normalized(),
                                        c.boolean("ground") && settings.ground);
        } catch (const std::invalid_argument& e) {
            c.fail(e.what());
        }
        c.count("frame", s.frame);
        c.out("path", png.string());
    });
    return t;
}

}  // namespace

void register_rigid_nodes(graph::NodeRegistry& r) {
    r.add(body_node());
    r.add(scene_node());
    r.add(frame_node());
    r.add(impact_node());
    r.add(carried_cracks_node());
    r.add(fragments_result_node());
    r.add(export_animation_node());
    r.add(scene_preview_node());
}

}  // namespace cf
