#include "nodes/rigid/rigid_world.hpp"

#include "graph/cancel_token.hpp"
#include "graph/diagnostics.hpp"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

static_assert(sizeof(btScalar) == sizeof(double), "crackflow links Bullet in double precision (bullet-float64)");

namespace cf::rigid {

namespace {
btVector3 bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 cf_vec(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// Bullet's narrow phase cannot be interrupted, and one step of a heap of fragments with mesh shapes
// can take seconds. Once the run is cancelled, the remaining pairs of the step are skipped (the
// world is discarded anyway), so the step ends at once and step() reports the cancellation. The
// world is single-threaded: the callback runs on the thread that called step(), whose token it reads.
void cancellable_near_callback(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info) {
    if (CancelToken::current().requested()) return;
    btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
}
// The points of a hull body's shape in the body frame (rotation R, centre c): the vertices of the
// convex hull of `mesh`, at most `hull_directions` of them. GJK's support search visits every point of
// a btConvexHullShape in every query; a dual-contoured fragment has thousands of vertices, almost all
// inside its hull, and a rounded chip still hundreds on it, so a heap of a thousand hull fragments
// spent seconds per rigid step there. Beyond the bound, the hull keeps the support vertex of each of
// `hull_directions` directions spread evenly over the sphere (every direction within 13.5 degrees
// of one of them): an inner hull whose faces lie within 1 - cos(13.5 deg) = 2.8 % of the piece's
// radius of the exact hull, for the small pieces that collide as hulls (ch. 7.3 class (a), at most
// 0.5 % of the original volume). Flat point sets keep all points.
constexpr int hull_directions = 128;

btAlignedObjectArray<btVector3> hull_vertices(const SurfaceMesh& mesh, const Eigen::Matrix3d& R, const Vec3& c) {
    std::vector<double> coords;
    coords.reserve(3 * mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) {
        const Vec3 b = R.transpose() * (v - c);
        coords.insert(coords.end(), {b.x(), b.y(), b.z()});
    }
    btConvexHullComputer hull;
    const int n = static_cast<int>(mesh.vertices.size());
    if (n >= 4) hull.compute(coords.data(), 3 * static_cast<int>(sizeof(double)), n, 0, 0);
    if (hull.vertices.size() < 4) {
        btAlignedObjectArray<btVector3> all;
        for (int i = 0; i < n; ++i) all.push_back(btVector3(coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]));
        return all;
    }
    if (hull.vertices.size() <= hull_directions) return hull.vertices;
    std::vector<char> kept(static_cast<std::size_t>(hull.vertices.size()), 0);
    const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
    for (int k = 0; k < hull_directions; ++k) {  // a Fibonacci sphere: even spacing, deterministic
        const double z = 1.0 - (2.0 * k + 1.0) / hull_directions, r = std::sqrt(1.0 - z * z);
        const btVector3 d(r * std::cos(golden_angle * k), r * std::sin(golden_angle * k), z);
        int best = 0;
        for (int i = 1; i < hull.vertices.size(); ++i)
            if (hull.vertices[i].dot(d) > hull.vertices[best].dot(d)) best = i;
        kept[static_cast<std::size_t>(best)] = 1;
    }
    btAlignedObjectArray<btVector3> out;
    for (int i = 0; i < hull.vertices.size(); ++i)
        if (kept[static_cast<std::size_t>(i)]) out.push_back(hull.vertices[i]);
    return out;
}
}  // namespace

struct RigidWorld::Impl {
    WorldSettings settings;
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    // Triangle data of GImpact shapes: Bullet keeps pointers into these arrays.
    struct TriangleData {
        std::vector<double> vertices;
        std::vector<int> indices;
        std::unique_ptr<btTriangleIndexVertexArray> array;
    };
    std::vector<std::unique_ptr<TriangleData>> triangle_data;
    std::vector<char> removed;
    std::vector<std::unique_ptr<btRigidBody>> bodies;  // [0, n): crackflow bodies in id order
    std::vector<std::unique_ptr<btRigidBody>> planes;
    std::vector<MassProperties> mass;
    double time = 0;

    explicit Impl(const WorldSettings& s) : settings(s) {
        world.setGravity(bt(s.gravity));
        world.getSolverInfo().m_numIterations = s.solver_iterations;
        world.getSolverInfo().m_solverMode &= ~SOLVER_RANDMIZE_ORDER;
        // Penetration is always resolved by split impulses (a pseudo-velocity that moves bodies apart
        // without adding momentum), never by Baumgarte terms in the contact impulse. Fragments are
        // born overlapping (their hulls, and siblings a gap of sqrt(3) r_f apart); with Baumgarte,
        // pushing them apart fed them kinetic energy and reported impulses that are no impact, and a
        // shot bunny's core kept breaking from its own debris. Contact impulses are then what the
        // bodies' velocities demand (ch. 7.1), which is what the fracture thresholds compare.
        world.getSolverInfo().m_splitImpulse = 1;
        world.getSolverInfo().m_splitImpulsePenetrationThreshold = std::numeric_limits<double>::max();
        world.getDispatchInfo().m_deterministicOverlappingPairs = true;
        btGImpactCollisionAlgorithm::registerAlgorithm(&dispatcher);
        dispatcher.setNearCallback(cancellable_near_callback);
    }
    ~Impl() {
        for (std::size_t i = 0; i < bodies.size(); ++i)
            if (!removed[i]) world.removeRigidBody(bodies[i].get());
        for (auto& b : planes) world.removeRigidBody(b.get());
    }
    // Body ids ride on Bullet's user index (-1, Bullet's default, for ground planes).
    static int id_of(const btCollisionObject* o) { return o->getUserIndex(); }
};

RigidWorld::RigidWorld(const WorldSettings& settings) : impl_(std::make_unique<Impl>(settings)) {
    if (!(settings.time_step > 0)) throw std::invalid_argument("rigid world: the time step must be positive [s]");
}

RigidWorld::~RigidWorld() = default;

int RigidWorld::add_body(const BodySpec& s) {
    for (const Vec3& v : {s.velocity, s.angular_velocity})
        if (!v.allFinite()) throw std::invalid_argument("body '" + s.name + "': velocities must be finite");
    MassProperties mp;
    try {
        mp = s.mass ? *s.mass : mass_properties(s.mesh, s.density);
        if (!(mp.mass > 0) || !mp.principal_moments.allFinite() || !(mp.principal_moments.minCoeff() > 0))
            throw std::invalid_argument("mass " + graph::format_number(mp.mass) + " kg and principal moments must be positive");
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("body '" + s.name + "': " + e.what());
    }
    // Body frame: centre of mass, principal axes. Shape points in that frame.
    const Mat3 R = mp.principal_axes;
    const Box3 box = bounding_box(s.mesh);
    const double margin = s.collision_margin > 0 ? s.collision_margin : 0.01 * box.extent().minCoeff();
    std::unique_ptr<btCollisionShape> shape;
    if (s.collision == CollisionShape::hull) {
        auto hull = std::make_unique<btConvexHullShape>();
        const btAlignedObjectArray<btVector3> points = hull_vertices(s.mesh, R, mp.centre);
        for (int i = 0; i < points.size(); ++i) hull->addPoint(points[i], false);
        hull->setMargin(margin);
        hull->recalcLocalAabb();
        shape = std::move(hull);
    } else {
        const SurfaceMesh& cm = s.collision_mesh.triangles.empty() ? s.mesh : s.collision_mesh;
        auto data = std::make_unique<Impl::TriangleData>();
        for (const Vec3& v : cm.vertices) {
            const Vec3 b = R.transpose() * (v - mp.centre);
            data->vertices.insert(data->vertices.end(), {b.x(), b.y(), b.z()});
        }
        for (const Tri& t : cm.triangles) data->indices.insert(data->indices.end(), {t[0], t[1], t[2]});
        data->array = std::make_unique<btTriangleIndexVertexArray>(
            static_cast<int>(cm.triangles.size()), data->indices.data(), 3 * static_cast<int>(sizeof(int)),
            static_cast<int>(cm.vertices.size()), data->vertices.data(), 3 * static_cast<int>(sizeof(double)));
        auto mesh = std::make_unique<btGImpactMeshShape>(data->array.get());
        mesh->setMargin(margin);
        mesh->updateBound();
        shape = std::move(mesh);
        impl_->triangle_data.push_back(std::move(data));
    }
    const bool dynamic = s.kind == BodyKind::dynamic;
    const double m = dynamic ? mp.mass : 0.0;
    const btVector3 inertia = dynamic ? bt(mp.principal_moments) : btVector3(0, 0, 0);
    btRigidBody::btRigidBodyConstructionInfo info(m, nullptr, shape.get(), inertia);
    const Eigen::Quaterniond q(R);
    info.m_startWorldTransform = btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(mp.centre));
    info.m_friction = s.friction;
    info.m_restitution = s.restitution;
    auto body = std::make_unique<btRigidBody>(info);
    if (s.kind == BodyKind::kinematic) body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setUserIndex(static_cast<int>(impl_->bodies.size()));
    body->setLinearVelocity(bt(s.velocity));
    body->setAngularVelocity(bt(s.angular_velocity));
    impl_->world.addRigidBody(body.get());
    impl_->shapes.push_back(std::move(shape));
    impl_->bodies.push_back(std::move(body));
    impl_->mass.push_back(mp);
    impl_->removed.push_back(0);
    return static_cast<int>(impl_->bodies.size() - 1);
}

void RigidWorld::add_ground_plane(const Vec3& n, double offset, double friction, double restitution) {
    if (!(n.norm() > 0)) throw std::invalid_argument("ground plane: the normal must not be zero");
    auto shape = std::make_unique<btStaticPlaneShape>(bt(n.normalized()), offset);
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
    info.m_friction = friction;
    info.m_restitution = restitution;
    auto body = std::make_unique<btRigidBody>(info);
    impl_->world.addRigidBody(body.get());
    impl_->shapes.push_back(std::move(shape));
    impl_->planes.push_back(std::move(body));
}

void RigidWorld::remove_body(int id) {
    const std::size_t i = static_cast<std::size_t>(id);
    if (i >= impl_->bodies.size() || impl_->removed[i]) throw std::logic_error("rigid world: no active body " + std::to_string(id));
    impl_->world.removeRigidBody(impl_->bodies[i].get());
    impl_->removed[i] = 1;
}

bool RigidWorld::active(int id) const {
    const std::size_t i = static_cast<std::size_t>(id);
    return i < impl_->bodies.size() && !impl_->removed[i];
}

std::vector<BodyState> RigidWorld::snapshot() const {
    std::vector<BodyState> out;
    out.reserve(impl_->bodies.size());
    for (std::size_t i = 0; i < impl_->bodies.size(); ++i) out.push_back(state(static_cast<int>(i)));
    return out;
}

void RigidWorld::restore(const std::vector<BodyState>& states) {
    if (states.size() > impl_->bodies.size()) throw std::logic_error("rigid world: snapshot of more bodies than exist");
    for (std::size_t i = 0; i < states.size(); ++i) {
        btRigidBody& b = *impl_->bodies[i];
        const BodyState& s = states[i];
        const btTransform t(btQuaternion(s.rotation.x(), s.rotation.y(), s.rotation.z(), s.rotation.w()), bt(s.position));
        b.setWorldTransform(t);
        b.setInterpolationWorldTransform(t);
        b.setLinearVelocity(bt(s.velocity));
        b.setAngularVelocity(bt(s.angular_velocity));
        b.setInterpolationLinearVelocity(bt(s.velocity));
        b.setInterpolationAngularVelocity(bt(s.angular_velocity));
        b.clearForces();
        if (!impl_->removed[i] && b.getBroadphaseHandle())
            impl_->world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(b.getBroadphaseHandle(),
                                                                                         &impl_->dispatcher);
    }
    for (auto& p : impl_->planes)
        if (p->getBroadphaseHandle())
            impl_->world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(p->getBroadphaseHandle(),
                                                                                         &impl_->dispatcher);
    impl_->world.updateAabbs();
}

std::vector<std::pair<int, int>> RigidWorld::overlaps(double depth) {
    impl_->world.updateAabbs();
    impl_->world.performDiscreteCollisionDetection();
    std::vector<std::pair<int, int>> out;
    btCollisionDispatcher& d = impl_->dispatcher;
    for (int i = 0; i < d.getNumManifolds(); ++i) {
        const btPersistentManifold* m = d.getManifoldByIndexInternal(i);
        double deepest = 0;
        for (int k = 0; k < m->getNumContacts(); ++k) deepest = std::min(deepest, double(m->getContactPoint(k).getDistance()));
        if (deepest < -depth) {
            int a = impl_->id_of(m->getBody0()), b = impl_->id_of(m->getBody1());
            if (a > b) std::swap(a, b);
            out.emplace_back(a, b);
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void RigidWorld::step() {
    const CancelToken cancel = CancelToken::current();
    cancel.poll();
    impl_->world.stepSimulation(impl_->settings.time_step, 0, impl_->settings.time_step);
    cancel.poll();  // a cancelled step skipped its narrow phase: its state is not a result
    impl_->time += impl_->settings.time_step;
}

double RigidWorld::time() const { return impl_->time; }
std::size_t RigidWorld::num_bodies() const { return impl_->bodies.size(); }
const MassProperties& RigidWorld::mass_properties_of(int id) const { return impl_->mass.at(static_cast<std::size_t>(id)); }

BodyState RigidWorld::state(int id) const {
    const btRigidBody& b = *impl_->bodies.at(static_cast<std::size_t>(id));
    const btTransform& t = b.getWorldTransform();
    const btQuaternion q = t.getRotation();
    BodyState s;
    s.position = cf_vec(t.getOrigin());
    s.rotation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
    s.velocity = cf_vec(b.getLinearVelocity());
    s.angular_velocity = cf_vec(b.getAngularVelocity());
    return s;
}

std::vector<Contact> RigidWorld::contacts() const {
    std::vector<Contact> out;
    btCollisionDispatcher& d = impl_->dispatcher;
    for (int i = 0; i < d.getNumManifolds(); ++i) {
        const btPersistentManifold* m = d.getManifoldByIndexInternal(i);
        for (int k = 0; k < m->getNumContacts(); ++k) {
            const btManifoldPoint& p = m->getContactPoint(k);
            if (!(p.getAppliedImpulse() > 0)) continue;
            Contact c;
            c.body_a = impl_->id_of(m->getBody0());
            c.body_b = impl_->id_of(m->getBody1());
            c.point_a = cf_vec(p.getPositionWorldOnA());
            c.point_b = cf_vec(p.getPositionWorldOnB());
            c.normal_on_b = cf_vec(p.m_normalWorldOnB);
            c.distance = p.getDistance();
            c.impulse = p.getAppliedImpulse();
            out.push_back(c);
        }
    }
    return out;
}

}  // namespace cf::rigid
