#include "nodes/rigid/scene_simulation.hpp"

#include "nodes/segment/fracture_faces.hpp"
#include "nodes/segment/fragment_mesher.hpp"
#include "nodes/segment/surface_fragments.hpp"

#include "graph/diagnostics.hpp"
#include "graph/node_context.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/domain/triangle_closest_point.hpp"
#include "nodes/propagate/fragment_cracks.hpp"
#include "nodes/propagate/propagation_law.hpp"
#include "nodes/rigid/balanced_tractions.hpp"
#include "nodes/rigid/contact_duration.hpp"
#include "nodes/rigid/fragment_motion.hpp"
#include "nodes/rigid/mass_properties.hpp"
#include "nodes/simplify/remesh.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <limits>
#include <stdexcept>

namespace cf::rigid {

namespace {

using graph_cancelled = graph::Cancelled;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Eigen::Isometry3d body_to_world(const BodyState& s) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = s.rotation.normalized().toRotationMatrix();
    T.translation() = s.position;
    return T;
}

// The body frame Bullet gives a body made from these mass properties (rigid_world.hpp).
Eigen::Isometry3d principal_frame(const MassProperties& mp) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = mp.principal_axes;
    T.translation() = mp.centre;
    return T;
}

SurfaceMesh transformed(const SurfaceMesh& m, const Eigen::Isometry3d& T) {
    SurfaceMesh out = m;
    for (Vec3& v : out.vertices) v = T * v;
    return out;
}

}  // namespace

FragmentBody fragment_body(const SurfaceMesh& material_mesh, double volume, double density,
                           const Eigen::Isometry3d& material_to_world, const RigidMotion& parent) {
    FragmentBody b;
    b.mass = mass_properties(transformed(material_mesh, material_to_world), density);
    // Mass from the level-set volume (thesis ch. 7.2), centre and inertia from the mesh.
    const double mass = volume * density;
    b.mass.inertia *= mass / b.mass.mass;
    b.mass.principal_moments *= mass / b.mass.mass;
    b.mass.mass = mass;
    b.mass.volume = volume;
    b.material_to_body = principal_frame(b.mass).inverse() * material_to_world;
    b.motion = fragment_motion(parent, b.mass.centre);
    return b;
}

namespace {

// The largest shell of `m`, when every other shell (edge-connected piece) encloses under 2 % of its
// volume. A fragment joined by a ligament thinner than the coarse grid remeshes into separate
// closed shells, and each shell brings its own six rigid modes into the hypersingular operator, so
// the pure Neumann system D_R (eq. 7.4), regularised for one body's six, is singular: every run on
// such a fragment failed (all of falling_objects' failed runs: shells of 4 to 44 triangles beside
// the main one). Specks are dropped; two large shells are an error (the caller's fallback: the
// fragment collides but does not break again).
SurfaceMesh single_shell(const SurfaceMesh& m) {
    const std::vector<int> piece = triangle_components(m);
    const int n = piece.empty() ? 0 : *std::max_element(piece.begin(), piece.end()) + 1;
    if (n <= 1) return m;
    std::vector<SurfaceMesh> shells(static_cast<std::size_t>(n));
    for (SurfaceMesh& sh : shells) {
        sh.vertices = m.vertices;
        sh.region_names = m.region_names;
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        if (piece[t] < 0) continue;
        SurfaceMesh& sh = shells[static_cast<std::size_t>(piece[t])];
        sh.triangles.push_back(m.triangles[t]);
        if (!m.region.empty()) sh.region.push_back(m.region[t]);
    }
    std::vector<double> volume;
    for (const SurfaceMesh& sh : shells) volume.push_back(std::abs(signed_volume(sh)));
    const std::size_t k = static_cast<std::size_t>(std::max_element(volume.begin(), volume.end()) - volume.begin());
    const auto large = std::count_if(volume.begin(), volume.end(), [&](double v) { return v >= 0.02 * volume[k]; });
    if (large > 1)
        throw std::runtime_error("remeshed fragment falls apart into " + std::to_string(large) + " large shells");
    return without_unused_vertices(shells[k]);
}

// How far `m` lies inside `object` [m]: the largest depth of its vertices, edge midpoints and
// centroids below the object's surface (0 where it encloses them; at most the narrow band).
double depth_inside(const SurfaceMesh& m, const LevelSet& object) {
    double depth = 0;
    auto at = [&](const Vec3& p) { depth = std::max(depth, -sample(object, p)); };
    for (const Tri& t : m.triangles) {
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        for (const Vec3& p : {a, Vec3(0.5 * (a + b)), Vec3(0.5 * (b + c)), Vec3(0.5 * (c + a)), Vec3((a + b + c) / 3.0)}) at(p);
    }
    return depth;
}

// A breakable body's BEM surface must enclose its object: crack elements end where their markers
// stop, just inside the object's surface, and a crack triangle that crosses the BEM surface makes
// the assembly fail. Remeshed from a grid of a quarter BEM edge, the surface cuts inside the object
// along rounded edges and curved parts by up to a coarse voxel (7 mm on a brick of 200 triangles),
// far more than the one-voxel (r_f) offset. So the offset grows by the depth the surface still lies
// inside the object, a few times, until it encloses it within half a voxel of r_f. (The thesis, ch.
// 6.2, inflates its BEM meshes by a user distance for the same reason, there against cracks stopping
// short of the surface.) The price is a BEM surface larger than the object where it is flat: a
// brick of 0.2 x 0.1 x 0.06 m encloses 30 % more volume; the fine surface, the fragments and the
// rigid bodies keep the object's true shape.
template <class Check>
SurfaceMesh enclosing(SurfaceMesh m, const LevelSet& object, const LevelSet& coarse, RemeshOptions o, const Check& checked) {
    for (int round = 0; round < 4; ++round) {
        const double depth = depth_inside(m, object);
        if (depth <= 0.5 * object.voxel_size) break;
        o.offset_voxels += 1.25 * depth / coarse.voxel_size;  // a little more: the sag moves with the offset
        m = checked(remesh(coarse, o).mesh);
    }
    return m;
}

}  // namespace

SurfaceMesh coarse_surface(const LevelSet& object, std::size_t target_triangles, double offset_voxels) {
    // Fragments carry sharp, thin wedges where cracks meet the surface; simplified straight from r_f
    // they fold into self-intersections. Remesh from a grid about a quarter of the target element
    // size instead (as the shipped pipelines remesh from a coarse level set), on no finer than r_f.
    const SurfaceMesh fine = level_set_to_mesh(object, 0);
    const double area = surface_area(fine);
    const double edge = std::sqrt(4 * area / (std::sqrt(3.0) * double(target_triangles)));
    const double thinnest = bounding_box(fine).extent().minCoeff();
    const double voxel = std::max(object.voxel_size, std::min(edge / 4, thinnest / 5));
    const LevelSet coarse = voxel > 1.5 * object.voxel_size ? level_set_from_mesh(fine, voxel) : object;
    RemeshOptions o;
    o.target_triangles = target_triangles;
    // The offset is in voxels of r_f (App. A item 14), not of the coarser grid remeshed from: one
    // coarse voxel (up to a quarter of the BEM edge) made the BEM surface that much larger than the
    // object, so hexagons initiated under it (ch. 4.4) lay outside the object and never grew.
    o.offset_voxels = offset_voxels * object.voxel_size / coarse.voxel_size;
    // The remesh checks closedness and self-intersections; a mesh that still encloses no positive
    // volume (a sliver folded inside out) would make the BEM system indefinite: refuse it too.
    auto checked = [](SurfaceMesh m) {
        m = single_shell(m);
        if (!(signed_volume(m) > 0)) throw std::runtime_error("remeshed fragment encloses no positive volume");
        return m;
    };
    try {
        SurfaceMesh m = checked(remesh(coarse, o).mesh);
        return offset_voxels > 0 ? enclosing(std::move(m), object, coarse, o, checked) : m;
    } catch (const std::exception&) {
        if (offset_voxels == 0) throw;
        o.offset_voxels = 0;  // the outward offset is what folds thin wedges most often
        return checked(remesh(coarse, o).mesh);
    }
}

std::string bem_mesh_problem(const SurfaceMesh& bem_mesh, const SurfaceMesh& mesh) {
    if (bem_mesh.num_triangles() < 4) return "it has " + std::to_string(bem_mesh.num_triangles()) + " triangles";
    const MeshTopologyReport topo = check_topology(bem_mesh);
    if (!topo.is_closed_manifold()) return "it is not a closed 2-manifold: " + topo.describe();
    if (!(signed_volume(bem_mesh) > 0)) return "it encloses no positive volume (inward normals?)";
    double edges = 0;
    for (std::size_t t = 0; t < bem_mesh.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k)
            edges += (bem_mesh.vertices[bem_mesh.triangles[t][k]] - bem_mesh.vertices[bem_mesh.triangles[t][(k + 1) % 3]]).norm();
    const double tolerance = 0.25 * edges / (3.0 * double(bem_mesh.num_triangles()));
    std::vector<double> distance(bem_mesh.num_vertices());
    tbb::parallel_for(std::size_t(0), bem_mesh.num_vertices(), [&](std::size_t v) {
        const Vec3& p = bem_mesh.vertices[v];
        const Tri& t = mesh.triangles[static_cast<std::size_t>(closest_triangle(mesh, p))];
        distance[v] = std::sqrt(closest_point_on_triangle(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]).distance2);
    });
    const auto worst = std::max_element(distance.begin(), distance.end());
    if (*worst > tolerance)
        return "vertex " + std::to_string(worst - distance.begin()) + " lies " + graph::format_quantity(*worst, "m") +
               " from the body's surface (allowed: a quarter of the mean BEM edge, " + graph::format_quantity(tolerance, "m") +
               "); give a BEM mesh of this body in its material frame (the frame of input 'mesh')";
    return "";
}

BreakableModel make_breakable_model(std::shared_ptr<const FractureSettings> settings, LevelSet object,
                                    double original_volume, std::shared_ptr<const SurfaceMesh> bem_mesh, double volume) {
    BreakableModel m;
    m.settings = std::move(settings);
    m.volume = volume > 0 ? volume : level_set_volume(object);
    m.original_volume = original_volume > 0 ? original_volume : m.volume;
    if (!bem_mesh)
        bem_mesh = std::make_shared<const SurfaceMesh>(
            coarse_surface(object, static_cast<std::size_t>(m.settings->bem_triangles), 1));
    m.object = std::move(object);
    m.bem_mesh = std::move(bem_mesh);
    m.curvature = triangle_mean_curvature(*m.bem_mesh);
    // The standoff: 90 % of the elements lie within it (the rest: rays along the normal that cross a
    // concave gap, ears or legs, before they meet the object).
    std::vector<double> standoff;
    for (std::size_t t = 0; t < m.bem_mesh->num_triangles(); ++t) {
        const double d = distance_along(m.object, triangle_centroid(*m.bem_mesh, t), -triangle_normal(*m.bem_mesh, t));
        standoff.push_back(std::isfinite(d) ? std::max(d, 0.0) : std::numeric_limits<double>::infinity());
    }
    if (!standoff.empty()) {
        const auto at = standoff.begin() + static_cast<std::ptrdiff_t>((standoff.size() - 1) * 9 / 10);
        std::nth_element(standoff.begin(), at, standoff.end());
        if (std::isfinite(*at)) m.bem_standoff = *at;
    }
    return m;
}

// --- the pieces of a scene -----------------------------------------------------------------------

struct Piece {
    int body = -1;          // RigidWorld id
    int animation = -1;     // index into pieces (AnimationPiece)
    bool alive = true;
    bool dynamic = true;
    Eigen::Isometry3d material_to_body = Eigen::Isometry3d::Identity();
    std::shared_ptr<const BreakableModel> breakable;
    double E = 1e10, nu = 0.25, density = 1000, mass = 0;
    double friction = 0.5, restitution = 0;
    // Surface used for the partner's curvature in the Hertz model (body frame), and |H| per
    // triangle; empty: |H| from the volume-equivalent sphere (small hull fragments).
    std::shared_ptr<const SurfaceMesh> contact_mesh;
    std::vector<double> contact_curvature;
    double sphere_curvature = 0;
    int children = 0;       // fragments made from it so far (names)
    // The largest loads it withstood in a run that did not break it: a body resting on its supports
    // is not run again every step for the same load, only for one 25 % larger.
    double withstood_impulse = 0, withstood_force = 0;
    // A run on it failed (e.g. its remeshed BEM surface gave an indefinite D_R, eq. 7.4): its surface
    // and model are unchanged, so every later run would fail the same way. It stays whole for good.
    bool run_failed = false;
    int parent = -1;             // piece it broke from
    int root = -1;               // the authored body it descends from (itself for an authored body)
    long long born_step = 0;     // rigid step it was made in
};
// Fragments of one break start a gap of sqrt(3) r_f apart, closer than Bullet's collision margins,
// and their convex hulls overlap: the impulses that push them apart in their first steps are contact
// resolution, not impacts, and start no fracture runs. This holds across breaks in quick succession
// too: when a fragment breaks again a few steps after its parent did, the debris of the first break
// still overlaps the new pieces (a shot bunny's core was otherwise re-run every step, chipped by its
// own debris). So contacts between two pieces of the same authored body that were both made in the
// last `fresh_debris_steps` steps are not impacts.
constexpr long long fresh_debris_steps = 10;
constexpr double rerun_factor = 1.25;

struct SceneSimulation::Impl {
    SceneSettings settings;
    RigidWorld world;
    FractureRunner runner;
    std::vector<Piece> pieces;            // by RigidWorld id
    std::vector<AnimationPiece> animation;
    std::vector<FractureRunRecord> runs;
    long long step_index = 0;

    Impl(const SceneSettings& s, FractureRunner r) : settings(s), world(s.world), runner(std::move(r)) {}

    double curvature_at(const Piece& p, const BodyState& s, const Vec3& world_point) const {
        if (p.breakable) {
            const Vec3 x = p.material_to_body.inverse() * (body_to_world(s).inverse() * world_point);
            return p.breakable->curvature[static_cast<std::size_t>(closest_triangle(*p.breakable->bem_mesh, x))];
        }
        if (p.contact_mesh && !p.contact_curvature.empty()) {
            const Vec3 x = body_to_world(s).inverse() * world_point;
            return p.contact_curvature[static_cast<std::size_t>(closest_triangle(*p.contact_mesh, x))];
        }
        return p.sphere_curvature;
    }

    ContactBody contact_body(const Piece& p, double curvature) const {
        ContactBody b;
        b.E = p.E;
        b.nu = p.nu;
        b.mass = p.dynamic ? p.mass : 0.0;
        b.mean_curvature = curvature;
        return b;
    }

    int add_piece(Piece piece, const BodySpec& spec, AnimationPiece anim) {
        const int id = world.add_body(spec);
        if (id != static_cast<int>(pieces.size())) throw std::logic_error("scene: body ids out of step with pieces");
        piece.body = id;
        piece.mass = spec.kind == BodyKind::dynamic ? world.mass_properties_of(id).mass : 0.0;
        piece.animation = static_cast<int>(animation.size());
        anim.mass = piece.mass;
        animation.push_back(std::move(anim));
        pieces.push_back(std::move(piece));
        if (static_cast<long long>(pieces.size()) > settings.max_pieces)
            throw std::runtime_error("scene: more than " + std::to_string(settings.max_pieces) +
                                     " pieces; raise 'max_pieces' of rigid.scene or coarsen the fracture (r_f, min volumes)");
        return id;
    }

    // Contacts of the last step, grouped by the breakable piece they load (material frame).
    std::map<int, std::vector<BodyContact>> breakable_contacts(const std::vector<BodyState>& before) const {
        std::map<int, std::vector<BodyContact>> out;
        const std::vector<BodyState> now = world.snapshot();
        auto velocity_at = [&](int id, const Vec3& x) -> Vec3 {
            if (id < 0) return Vec3::Zero();
            const BodyState& s = before[static_cast<std::size_t>(id)];
            return s.velocity + s.angular_velocity.cross(x - s.position);
        };
        for (const Contact& c : world.contacts()) {
            const Vec3 n = c.normal_on_b.normalized();  // from b towards a: the impulse on a is +n
            const double approach = (velocity_at(c.body_b, c.point_b) - velocity_at(c.body_a, c.point_a)).dot(n);
            const int ids[2] = {c.body_a, c.body_b};
            const Vec3 points[2] = {c.point_a, c.point_b};
            for (int side = 0; side < 2; ++side) {
                const int id = ids[side], other = ids[1 - side];
                if (id < 0 || !pieces[static_cast<std::size_t>(id)].breakable) continue;
                const Piece& p = pieces[static_cast<std::size_t>(id)];
                if (other >= 0 && p.parent >= 0) {
                    const Piece& q = pieces[static_cast<std::size_t>(other)];
                    if (q.parent >= 0 && q.root == p.root && step_index - std::min(p.born_step, q.born_step) < fresh_debris_steps)
                        continue;
                }
                const Eigen::Isometry3d world_to_material =
                    p.material_to_body.inverse() * body_to_world(now[static_cast<std::size_t>(id)]).inverse();
                BodyContact bc;
                bc.point = world_to_material * points[side];
                bc.direction = world_to_material.linear() * (side == 0 ? n : Vec3(-n));
                bc.impulse = c.impulse;
                bc.approach_speed = std::abs(approach);
                if (other < 0) {
                    bc.partner.E = settings.ground_E;
                    bc.partner.nu = settings.ground_nu;
                    bc.partner.mass = 0;
                    bc.partner.mean_curvature = 0;
                } else {
                    const Piece& q = pieces[static_cast<std::size_t>(other)];
                    bc.partner = contact_body(q, curvature_at(q, now[static_cast<std::size_t>(other)], points[1 - side]));
                }
                out[id].push_back(bc);
            }
        }
        return out;
    }

    // BEM time steps whose simulated time (r_c / c_R each, ch. 4.5.2) fits in the contact (ch. 8).
    static long long fracture_step_bound(const BreakableModel& m, double duration) {
        const Material& mat = m.settings->material;
        const double r_f = m.object.voxel_size;
        const double substeps = std::ceil(m.settings->r_c / r_f);
        const double step_time = substeps * propagate::substep_duration(r_f, propagate::rayleigh_speed(mat.mu(), mat.rho));
        return std::max(1LL, static_cast<long long>(std::llround(duration / step_time)));
    }

    struct Candidate {
        int piece = -1;
        ImpactLoads loads;
        ImpactRun run;
        ImpactOutcome outcome;
        double seconds = 0;
        std::string error;
    };

    std::vector<Candidate> fracture_candidates(const std::vector<BodyState>& before, int frame) const {
        std::vector<Candidate> out;
        for (auto& [id, contacts] : breakable_contacts(before)) {
            const Piece& p = pieces[static_cast<std::size_t>(id)];
            const FractureSettings& fs = *p.breakable->settings;
            Candidate c;
            c.piece = id;
            c.loads = impact_loads(*p.breakable->bem_mesh, p.breakable->curvature, contact_body(p, 0), contacts,
                                   settings.world.time_step, fs.limits);
            if (p.run_failed) continue;
            const bool impulse = c.loads.impulse >= fs.impulse_threshold && c.loads.impulse > rerun_factor * p.withstood_impulse;
            const bool force = c.loads.force >= fs.force_threshold && c.loads.force > rerun_factor * p.withstood_force;
            if (!impulse && !force) continue;
            c.run.body = animation[static_cast<std::size_t>(p.animation)].name;
            c.run.frame = frame;
            c.run.step = static_cast<int>(step_index);
            c.run.model = p.breakable;
            c.run.conditions.others = bem::RegionCondition{bem::RegionCondition::Kind::traction, Vec3::Zero()};
            c.run.conditions.element_tractions = balance_tractions(*p.breakable->bem_mesh, c.loads.traction).traction;
            c.run.max_steps = fracture_step_bound(*p.breakable, c.loads.contact_duration);
            c.run.output_dir = std::filesystem::path("fracture_runs") /
                               (std::to_string(frame) + "_" + std::to_string(step_index) + "_" + c.run.body);
            out.push_back(std::move(c));
        }
        return out;
    }

    // A fragment of piece `parent_id` made ready to become a piece (ch. 7.3), placed by the parent's
    // state `s`: its class, meshes, mass properties, motion and fracture model. Reads only the parent
    // (no shared state is written), so the fragments of a step are prepared concurrently.
    struct PreparedFragment {
        Piece piece;
        BodySpec spec;
        AnimationPiece anim;
        std::size_t carried = 0;  // incomplete-crack triangles it carries
        LevelSet cell;            // the cell its mesh was clipped to; empty when its parent keeps no surface
        std::string warning;      // the surface mesher fell back to the level-set mesh: why
        bool folded = false;      // drawn with folds in its fracture faces that could not be mended
    };
    // The volume class of a fragment (ch. 7.3): (d) large, keeps the parent's BEM mesh; (c)
    // breakable; (b) collides as a mesh; (a) collides as its convex hull.
    static PieceClass fragment_class(const BreakableModel& model, const Fragment& f) {
        const double V0 = model.original_volume;
        PieceClass cls = PieceClass::breakable;
        if (f.volume > 0.95 * model.volume) cls = PieceClass::large;
        else if (f.volume <= 0.005 * V0) cls = PieceClass::hull;
        else if (f.volume <= 0.02 * V0) cls = PieceClass::mesh;
        return cls;
    }

    // A breakable fragment's model: remeshed (class (d): the parent's BEM mesh, operators and
    // factor), with the incomplete cracks of the parent's run that it keeps. False when it is too
    // thin to remesh at the BEM target (it then collides as a mesh and never breaks again).
    static bool make_breakable(const BreakableModel& model, const Fragment& f, PieceClass cls,
                               const std::shared_ptr<const propagate::FractureState>& cracks,
                               const Eigen::Isometry3d& material_to_world, PreparedFragment& out) {
        try {
            BreakableModel bm = make_breakable_model(model.settings, f.grid, model.original_volume,
                                                     cls == PieceClass::large ? model.bem_mesh : nullptr, f.volume);
            bm.authored = model.authored.empty() ? model.object : model.authored;
            bm.surface = model.surface;  // its fragments are clipped from the authored surface too ...
            bm.cell = out.cell;          // ... to cells within its own
            if (cls == PieceClass::large) {  // the parent's BEM mesh, so its operators and factor too (ch. 7.3 (d))
                bm.bem_standoff = model.bem_standoff;  // measured on the parent: chips stand off farther
                bm.surface_blocks = model.surface_blocks;
                bm.surface_factor = model.surface_factor;
            }
            if (cracks && cracks->cracks.num_triangles() > 0) {
                propagate::FragmentCracks fc = propagate::restrict_to_fragment(*cracks, f.grid, *bm.bem_mesh);
                if (fc.state.cracks.num_triangles() > 0) {
                    out.carried = fc.state.cracks.num_triangles();
                    // The fragment's object without the slits of the cracks it keeps (they grow from it).
                    bm.object = fill_crack_slits(f.grid, model.object, fc.state.grids.cracks);
                    bm.cracks = std::make_shared<const propagate::FractureState>(std::move(fc.state));
                }
            }
            auto m = std::make_shared<const BreakableModel>(std::move(bm));
            out.piece.breakable = m;
            out.spec.collision = CollisionShape::mesh;
            out.spec.collision_mesh = transformed(*m->bem_mesh, material_to_world);
            return true;
        } catch (const std::exception&) {
            out.carried = 0;
            return false;
        }
    }

    // A coarse collision mesh of the fragment; false when it cannot be made (then: the hull).
    static bool make_mesh_collider(const FractureSettings& fs, const Fragment& f, const Eigen::Isometry3d& material_to_world,
                                   PreparedFragment& out) {
        try {
            const SurfaceMesh coarse = coarse_surface(
                f.grid, static_cast<std::size_t>(fs.collision_mesh_factor * double(fs.bem_triangles)), 0);
            out.spec.collision = CollisionShape::mesh;
            out.spec.collision_mesh = transformed(coarse, material_to_world);
            out.piece.contact_mesh = std::make_shared<const SurfaceMesh>(transformed(coarse, out.piece.material_to_body));
            out.piece.contact_curvature = triangle_mean_curvature(*out.piece.contact_mesh);
            return true;
        } catch (const std::exception&) {
            return false;
        }
    }

    PreparedFragment prepare_fragment(int parent_id, const BodyState& s, const Fragment& f, int frame,
                                      const std::shared_ptr<const propagate::FractureState>& cracks,
                                      const FragmentMesher* mesher, std::size_t index) const {
        const Piece& parent = pieces[static_cast<std::size_t>(parent_id)];
        const BreakableModel& model = *parent.breakable;
        const std::shared_ptr<const FractureSettings> fs = model.settings;
        PieceClass cls = fragment_class(model, f);
        PreparedFragment out;

        const Eigen::Isometry3d material_to_world = body_to_world(s) * parent.material_to_body;
        SurfaceMesh material_mesh = level_set_to_mesh(f.grid, 0);
        tag_fracture_faces(material_mesh, model.authored.empty() ? model.object : model.authored,
                           kFractureFaceDepthVoxels * model.object.voxel_size);
        // Drawn with the authored surface clipped to the fragment's cell (the motion below still
        // comes from the level-set mesh, so keeping the surface changes no trajectory); where the
        // clip fails, with the level-set mesh (its own fragments still clip the authored surface).
        SurfaceMesh drawn;
        if (mesher) {
            drawn = mesher->mesh(index, &out.warning, &out.folded, &out.cell);
            // The mesher gives flat normals where the surface has none; drawn like its parent
            // instead (normals by crease angle), so a piece does not change its shading as it breaks.
            if (!model.surface->input().has_normals()) drawn.corner_normal.clear();
            if (!out.warning.empty()) drawn = material_mesh;
        }
        const FragmentBody fb = fragment_body(material_mesh, f.volume, model.settings->material.rho, material_to_world,
                                              RigidMotion{s.position, s.velocity, s.angular_velocity});

        Piece& piece = out.piece;
        piece.dynamic = true;
        piece.parent = parent_id;
        piece.root = parent.root;
        piece.born_step = step_index;
        piece.E = parent.E;
        piece.nu = parent.nu;
        piece.density = parent.density;
        piece.friction = parent.friction;
        piece.restitution = parent.restitution;
        piece.material_to_body = fb.material_to_body;

        BodySpec& spec = out.spec;
        spec.kind = BodyKind::dynamic;
        spec.mesh = transformed(material_mesh, material_to_world);
        spec.mass = fb.mass;
        spec.friction = parent.friction;
        spec.restitution = parent.restitution;
        spec.velocity = fb.motion.velocity;
        spec.angular_velocity = fb.motion.angular_velocity;

        if (cls == PieceClass::large || cls == PieceClass::breakable)
            if (!make_breakable(model, f, cls, cracks, material_to_world, out)) cls = PieceClass::mesh;
        if (cls == PieceClass::mesh)
            if (!make_mesh_collider(*fs, f, material_to_world, out)) cls = PieceClass::hull;
        if (cls == PieceClass::hull) spec.collision = CollisionShape::hull;
        piece.sphere_curvature = std::cbrt(4.0 * M_PI / (3.0 * f.volume));

        AnimationPiece& anim = out.anim;
        anim.parent = parent.animation;
        anim.piece_class = cls;
        anim.volume = f.volume;
        anim.dynamic = true;
        anim.rest_mesh = std::make_shared<const SurfaceMesh>(
            transformed(mesher ? drawn : material_mesh, piece.material_to_body));
        anim.first_frame = frame;
        return out;
    }

    // Names it "<parent>.<k>" (k counts the parent's fragments) and inserts it, in a fixed order.
    void add_fragment(PreparedFragment f) {
        Piece& parent = pieces[static_cast<std::size_t>(f.piece.parent)];
        f.spec.name = animation[static_cast<std::size_t>(parent.animation)].name + "." + std::to_string(parent.children++);
        f.anim.name = f.spec.name;
        add_piece(std::move(f.piece), f.spec, std::move(f.anim));
    }

    // The bodies a step's runs broke: each with its kept fragments, the index of its run record
    // and the run's final fracture state.
    struct Breaks {
        std::vector<std::pair<int, std::vector<const Fragment*>>> broken;
        std::vector<std::size_t> run_of_break;  // index into runs per entry of broken
        std::vector<std::shared_ptr<const propagate::FractureState>> state_of_break;
        std::vector<const Fragments*> fragments_of_break;  // the run's fragments, kept ones and dropped
    };

    // The runs' records (appended to `runs`) and their effect on the bodies that did not break:
    // surface blocks and factor kept, withstood loads raised, incomplete cracks kept (ch. 7.3).
    Breaks record_runs(std::vector<Candidate>& candidates, int frame) {
        Breaks out;
        for (Candidate& c : candidates) {
            // The run's surface blocks and factor stay with the body (and a class (d) fragment of it).
            if (c.outcome.surface_blocks && c.outcome.surface_blocks != pieces[static_cast<std::size_t>(c.piece)].breakable->surface_blocks) {
                Piece& q = pieces[static_cast<std::size_t>(c.piece)];
                BreakableModel m = *q.breakable;
                m.surface_blocks = c.outcome.surface_blocks;
                m.surface_factor = c.outcome.surface_factor;
                q.breakable = std::make_shared<const BreakableModel>(std::move(m));
            }
            const Piece& p = pieces[static_cast<std::size_t>(c.piece)];
            FractureRunRecord r;
            r.frame = frame;
            r.body = c.run.body;
            r.impulse = c.loads.impulse;
            r.force = c.loads.force;
            r.contact_duration = c.loads.contact_duration;
            r.max_steps = c.run.max_steps;
            r.bem_triangles = p.breakable->bem_mesh->num_triangles();
            r.seconds = c.seconds;
            r.error = c.error;
            std::vector<const Fragment*> kept;
            for (const Fragment& f : c.outcome.fragments.fragments) {
                if (f.volume < p.breakable->settings->min_fragment_fraction * p.breakable->original_volume) ++r.dropped;
                else kept.push_back(&f);
            }
            r.fragments = static_cast<int>(kept.size());
            r.broke = kept.size() > 1;
            const auto& state = c.outcome.state;
            r.crack_triangles = state ? state->cracks.num_triangles() : 0;
            if (const auto& old = p.breakable->cracks; old && old->cracks.num_triangles() > 0) {
                r.old_crack_triangles_start = old->cracks.num_triangles();
                if (state)
                    for (std::size_t t = 0; t < state->cracks.num_triangles(); ++t)
                        r.old_crack_triangles_end += state->cracks.region_of(t) < old->num_cracks() ? 1 : 0;
            }
            if (r.broke) {
                out.broken.emplace_back(c.piece, std::move(kept));
                out.run_of_break.push_back(runs.size());
                out.state_of_break.push_back(state);
                out.fragments_of_break.push_back(&c.outcome.fragments);
            } else {
                Piece& q = pieces[static_cast<std::size_t>(c.piece)];
                q.withstood_impulse = std::max(q.withstood_impulse, c.loads.impulse);
                q.withstood_force = std::max(q.withstood_force, c.loads.force);
                q.run_failed = q.run_failed || !r.error.empty();
                // Cracks that did not separate the body stay in it and grow again later (ch. 7.3).
                if (state && state->cracks.num_triangles() > 0 && r.error.empty()) {
                    BreakableModel m = *q.breakable;
                    m.cracks = state;
                    q.breakable = std::make_shared<const BreakableModel>(std::move(m));
                    r.carried_triangles = state->cracks.num_triangles();
                }
            }
            runs.push_back(r);
        }
        return out;
    }

    // The broken bodies removed and their fragments prepared (concurrently) and added, in a fixed
    // order; the world is already back at the state `before` the step.
    void replace_broken(const Breaks& breaks, const std::vector<BodyState>& before, int frame, FrameReport& report) {
        struct Job {
            std::size_t broken;      // index into breaks.broken
            const Fragment* fragment;
        };
        std::vector<Job> jobs;
        for (std::size_t b = 0; b < breaks.broken.size(); ++b)
            for (const Fragment* f : breaks.broken[b].second) jobs.push_back({b, f});
        std::vector<PreparedFragment> prepared(jobs.size());
        const CancelToken cancel = CancelToken::current();  // read here: workers have no node of their own
        // One surface mesher per broken body that keeps its surface: the cells of all its run's
        // fragments (dropped ones too: they fill their part of the object) and its clipper.
        std::vector<std::unique_ptr<FragmentMesher>> meshers(breaks.broken.size());
        tbb::parallel_for(std::size_t(0), breaks.broken.size(), [&](std::size_t b) {
            cancel.poll();
            const CancelScope scope(cancel);
            const BreakableModel& model = *pieces[static_cast<std::size_t>(breaks.broken[b].first)].breakable;
            if (!model.surface) return;
            FragmentMesherOptions o;
            o.kind = FragmentMesherKind::surface;
            o.clipper = model.surface;
            o.keep_folds = true;  // a mesh to draw: a fold in a fracture face beats losing the artist's surface
            o.bound = model.cell.empty() ? nullptr : &model.cell;
            meshers[b] = std::make_unique<FragmentMesher>(*breaks.fragments_of_break[b], o);
        });
        tbb::parallel_for(std::size_t(0), jobs.size(), [&](std::size_t k) {
            cancel.poll();
            const CancelScope scope(cancel);  // the remesh and meshing inside poll it too
            const std::size_t b = jobs[k].broken;
            const int id = breaks.broken[b].first;
            const Fragments& all = *breaks.fragments_of_break[b];
            const auto index = static_cast<std::size_t>(jobs[k].fragment - all.fragments.data());
            prepared[k] = prepare_fragment(id, before[static_cast<std::size_t>(id)], *jobs[k].fragment, frame,
                                           breaks.state_of_break[b], meshers[b].get(), index);
        });
        for (std::size_t b = 0; b < breaks.broken.size(); ++b) {
            const int id = breaks.broken[b].first;
            Piece& parent = pieces[static_cast<std::size_t>(id)];
            parent.alive = false;
            world.remove_body(id);
            animation[static_cast<std::size_t>(parent.animation)].last_frame = frame - 1;
            report.breaks += 1;
            report.new_pieces += static_cast<int>(breaks.broken[b].second.size());
        }
        for (std::size_t k = 0; k < jobs.size(); ++k) {
            runs[breaks.run_of_break[jobs[k].broken]].carried_triangles += prepared[k].carried;
            const std::string warning = std::move(prepared[k].warning);
            const bool folded = prepared[k].folded;
            add_fragment(std::move(prepared[k]));
            if (!warning.empty())
                report.warnings.push_back(animation.back().name + " (drawn with its level-set mesh): " + warning);
            report.surface_folded += folded ? 1 : 0;
        }
    }

    // One rigid step; fracture runs after it unless `repeat` (the repeated step of ch. 7.3).
    void rigid_step(int frame, FrameReport& report) {
        const std::vector<BodyState> before = world.snapshot();
        const auto t0 = Clock::now();
        world.step();
        report.rigid_seconds += seconds_since(t0);
        std::vector<Candidate> candidates = fracture_candidates(before, frame);
        if (candidates.empty()) {
            ++step_index;
            return;
        }
        const auto t1 = Clock::now();
        // Independent runs (one per body) run concurrently; each is deterministic by itself.
        tbb::parallel_for(std::size_t(0), candidates.size(), [&](std::size_t k) {
            const auto tk = Clock::now();
            // A run that fails (e.g. a fragment's BEM mesh too degenerate to solve on) leaves the body
            // whole; the failure is recorded with the run, and the scene goes on. Cancellation stops it.
            try {
                candidates[k].outcome = runner(candidates[k].run);
            } catch (const graph_cancelled&) {
                throw;
            } catch (const std::exception& e) {
                candidates[k].error = e.what();
            }
            candidates[k].seconds = seconds_since(tk);
        });
        report.fracture_seconds += seconds_since(t1);
        report.fracture_runs += static_cast<int>(candidates.size());

        Breaks breaks = record_runs(candidates, frame);
        if (breaks.broken.empty()) {
            ++step_index;
            return;
        }
        // Replace the broken bodies by their fragments at the state before the step, then repeat it.
        // Making the fragments' bodies (meshes, remeshing, mass properties) counts as fracture time.
        const auto t_fragments = Clock::now();
        world.restore(before);
        replace_broken(breaks, before, frame, report);
        report.fracture_seconds += seconds_since(t_fragments);
        const auto t2 = Clock::now();
        world.step();
        report.rigid_seconds += seconds_since(t2);
        ++step_index;
    }
};

namespace {

// The constructor's steps, in the order it calls them.

// Rigid steps per frame: one frame must be a whole number of them.
int rigid_steps_per_frame(const SceneSettings& settings) {
    if (!(settings.world.time_step > 0) || !std::isfinite(settings.world.time_step))
        throw std::invalid_argument("scene: 'time_step' must be positive and finite [s]");
    if (!(settings.frame_rate > 0) || !std::isfinite(settings.frame_rate))
        throw std::invalid_argument("scene: 'frame_rate' must be positive [1/s]");
    const double steps = 1.0 / (settings.frame_rate * settings.world.time_step);
    const int n = static_cast<int>(std::llround(steps));
    if (n < 1 || std::abs(steps - n) > 1e-6 * steps)
        throw std::invalid_argument("scene: one frame (1 / frame_rate = " + graph::format_number(1 / settings.frame_rate) +
                                    " s) must be a whole number of rigid steps (time_step = " +
                                    graph::format_number(settings.world.time_step) + " s)");
    return n;
}

// A body of the scene as a piece at frame 0: its Bullet body, contact data and animation record.
struct InitialPiece {
    Piece piece;
    BodySpec spec;
    AnimationPiece anim;
    double smallest_extent = 0;  // of its world bounding box [m]
};

InitialPiece initial_piece(const BodyDescription& b) {
    InitialPiece out;
    Piece& piece = out.piece;
    piece.dynamic = b.kind == BodyKind::dynamic;
    piece.E = b.E;
    piece.nu = b.nu;
    piece.density = b.density;
    piece.friction = b.friction;
    piece.restitution = b.restitution;
    piece.breakable = b.breakable;
    const SurfaceMesh world_mesh = transformed(b.mesh, b.placement);
    BodySpec& spec = out.spec;
    spec.name = b.name;
    spec.kind = b.kind;
    spec.mesh = world_mesh;
    spec.density = b.density;
    spec.velocity = b.velocity;
    spec.angular_velocity = b.angular_velocity;
    spec.friction = b.friction;
    spec.restitution = b.restitution;
    spec.collision = b.collision;
    MassProperties mp;
    try {
        mp = mass_properties(world_mesh, b.density);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("body '" + b.name + "': " + e.what());
    }
    if (b.breakable) {
        // Mass from the level-set volume (ch. 7.2), as for the fragments it will break into.
        const double mass = b.breakable->volume * b.density;
        mp.inertia *= mass / mp.mass;
        mp.principal_moments *= mass / mp.mass;
        mp.mass = mass;
        mp.volume = b.breakable->volume;
        spec.mass = mp;
    }
    piece.material_to_body = principal_frame(mp).inverse() * b.placement;
    piece.contact_mesh = std::make_shared<const SurfaceMesh>(transformed(b.mesh, piece.material_to_body));
    piece.contact_curvature = triangle_mean_curvature(*piece.contact_mesh);
    AnimationPiece& anim = out.anim;
    anim.name = b.name;
    anim.piece_class = PieceClass::original;
    anim.volume = mp.volume;
    anim.dynamic = piece.dynamic;
    anim.rest_mesh = piece.contact_mesh;
    anim.first_frame = 0;
    out.smallest_extent = bounding_box(world_mesh).extent().minCoeff();
    return out;
}

}  // namespace

SceneSimulation::SceneSimulation(const SceneSettings& settings, const BodyList& bodies, FractureRunner runner)
    : settings_(settings) {
    steps_per_frame_ = rigid_steps_per_frame(settings);
    if (bodies.empty()) throw std::invalid_argument("scene: no bodies");
    impl_ = std::make_unique<Impl>(settings, std::move(runner));
    std::map<std::string, int> names;
    double smallest = std::numeric_limits<double>::infinity();
    for (const auto& b : bodies) {
        if (!names.emplace(b->name, 0).second)
            throw std::invalid_argument("scene: two bodies are named '" + b->name + "'; body names must be unique");
        InitialPiece p = initial_piece(*b);
        p.piece.root = static_cast<int>(impl_->pieces.size());  // its id once added
        impl_->add_piece(std::move(p.piece), p.spec, std::move(p.anim));
        smallest = std::min(smallest, p.smallest_extent);
    }
    if (settings.ground) {
        const Vec3 up = -settings.world.gravity.normalized();
        if (!up.allFinite()) throw std::invalid_argument("scene: a ground plane needs a non-zero gravity (its normal is -gravity)");
        impl_->world.add_ground_plane(up, up.dot(settings.ground_point), settings.ground_friction,
                                      settings.ground_restitution);
    }
    // No body may start inside another or the ground.
    const double depth = settings.overlap_tolerance > 0 ? settings.overlap_tolerance : 0.02 * smallest;
    const auto overlaps = impl_->world.overlaps(depth);
    if (!overlaps.empty()) {
        auto name = [&](int id) { return id < 0 ? std::string("the ground") : "body '" + impl_->animation[static_cast<std::size_t>(id)].name + "'"; };
        throw std::invalid_argument("scene: " + name(overlaps.front().first) + " starts inside " +
                                    name(overlaps.front().second) + " (deeper than " + graph::format_number(depth) +
                                    " m); move them apart with 'position'");
    }
}

SceneSimulation::~SceneSimulation() = default;

FrameReport SceneSimulation::advance_frame(const std::function<void()>& check_cancelled) {
    FrameReport report;
    ++frame_;
    for (int k = 0; k < steps_per_frame_; ++k) {
        if (check_cancelled) check_cancelled();
        impl_->rigid_step(frame_, report);
    }
    return report;
}

double SceneSimulation::time() const { return double(impl_->step_index) * settings_.world.time_step; }

AnimationFrame SceneSimulation::current_frame() const {
    AnimationFrame f;
    f.time = frame_ / settings_.frame_rate;
    std::vector<std::pair<int, PiecePose>> poses;
    for (const Piece& p : impl_->pieces) {
        if (!p.alive) continue;
        const BodyState s = impl_->world.state(p.body);
        PiecePose pose;
        pose.position = s.position;
        pose.rotation = s.rotation.normalized();
        pose.velocity = s.velocity;
        pose.angular_velocity = s.angular_velocity;
        f.poses.emplace_back(p.animation, pose);
    }
    return f;
}

const std::vector<AnimationPiece>& SceneSimulation::pieces() const { return impl_->animation; }
const std::vector<FractureRunRecord>& SceneSimulation::runs() const { return impl_->runs; }
std::size_t SceneSimulation::live_pieces() const {
    std::size_t n = 0;
    for (const Piece& p : impl_->pieces) n += p.alive ? 1 : 0;
    return n;
}

}  // namespace cf::rigid
