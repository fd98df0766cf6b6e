#include "nodes/rigid/animation_gltf.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/rigid/animation_checks.hpp"
#include "nodes/rigid/piece_colours.hpp"

#include "nodes/export/glb_builder.hpp"  // tinygltf: the declarations, Debian's compiled library linked

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>

namespace cf::rigid {

namespace {

// Triangles meeting at a vertex whose normals differ by more than this angle are shaded apart.
const double kCreaseCos = std::cos(30.0 * M_PI / 180.0);

// One glTF primitive's arrays, ready to be copied into the buffer.
struct RenderMesh {
    std::vector<float> positions;  // x y z per output vertex [m], body frame
    std::vector<float> normals;    // unit, per output vertex
    std::vector<float> uvs;        // u v per output vertex (v flipped: glTF's origin is the top left); empty: none
    std::vector<std::uint32_t> indices;
};

// The triangles around every vertex, compressed: tris[start[v] .. start[v + 1]).
struct VertexTriangles {
    std::vector<std::size_t> start;
    std::vector<std::size_t> tris;
};

VertexTriangles vertex_triangles(const SurfaceMesh& m) {
    VertexTriangles vt;
    vt.start.assign(m.num_vertices() + 1, 0);
    for (const Tri& t : m.triangles)
        for (int v : t) ++vt.start[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < m.num_vertices(); ++v) vt.start[v + 1] += vt.start[v];
    vt.tris.resize(vt.start.back());
    std::vector<std::size_t> fill(vt.start.begin(), vt.start.end() - 1);
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        for (int v : m.triangles[t]) vt.tris[fill[static_cast<std::size_t>(v)]++] = t;
    return vt;
}

// The normal of triangle t's corner at vertex v: the area-weighted sum of the normals of the
// triangles at v that lie within the crease angle of t. A degenerate t (no direction of its
// own) takes all triangles at v; a vertex with only degenerate triangles gets +z, since glTF
// requires unit normals even where they cannot matter.
Vec3 corner_normal(const SurfaceMesh& m, const VertexTriangles& vt, const std::vector<Vec3>& unit, std::size_t v,
                   std::size_t t) {
    Vec3 sum = Vec3::Zero();
    const bool degenerate = unit[t].isZero();
    for (std::size_t k = vt.start[v]; k < vt.start[v + 1]; ++k) {
        const std::size_t s = vt.tris[k];
        if (degenerate || unit[s].dot(unit[t]) >= kCreaseCos) sum += triangle_normal_unnormalised(m, s);
    }
    const double n = sum.norm();
    return n > 0 ? Vec3(sum / n) : Vec3::UnitZ();
}

// The triangles of m that are (want_inside) or are not in region `inside` (all of them when
// inside < 0). Normals: the mesh's own corner normals where it has them (an artist's surface kept by
// the surface mesher), else from all of m's triangles within the crease angle, so the parts shade
// alike where they meet. Texture coordinates where the mesh has them.
RenderMesh render_mesh(const SurfaceMesh& m, int inside, bool want_inside) {
    const VertexTriangles vt = vertex_triangles(m);
    std::vector<Vec3> unit(m.num_triangles());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) unit[t] = triangle_normal(m, t);
    const bool own_normals = m.has_normals(), uv = m.has_uv();

    RenderMesh r;
    // Output vertices made so far for each input vertex, by their float32 normal and uv: corners
    // whose attributes round to the same floats share one output vertex.
    using Key = std::array<float, 5>;
    std::vector<std::vector<std::pair<Key, std::uint32_t>>> made(m.num_vertices());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        if (inside >= 0 && (m.region_of(t) == inside) != want_inside) continue;
        for (int k = 0; k < 3; ++k) {
            const auto v = static_cast<std::size_t>(m.triangles[t][k]);
            Vec3 n = own_normals ? m.corner_normal[t][k].normalized() : corner_normal(m, vt, unit, v, t);
            if (!n.allFinite() || !(n.squaredNorm() > 0.5)) n = Vec3::UnitZ();  // a zero normal from the file: glTF needs unit ones
            const Vec2 w = uv ? m.corner_uv[t][k] : Vec2::Zero();
            const Key key{float(n.x()), float(n.y()), float(n.z()), float(w.x()), float(1.0 - w.y())};
            auto it = std::find_if(made[v].begin(), made[v].end(), [&](const auto& e) { return e.first == key; });
            if (it == made[v].end()) {
                const auto index = static_cast<std::uint32_t>(r.positions.size() / 3);
                const Vec3& x = m.vertices[v];
                r.positions.insert(r.positions.end(), {float(x.x()), float(x.y()), float(x.z())});
                r.normals.insert(r.normals.end(), key.begin(), key.begin() + 3);
                if (uv) r.uvs.insert(r.uvs.end(), key.begin() + 3, key.end());
                made[v].emplace_back(key, index);
                r.indices.push_back(index);
            } else {
                r.indices.push_back(it->second);
            }
        }
    }
    return r;
}

void add_primitive(GlbBuilder& b, tinygltf::Mesh& mesh, const RenderMesh& r, int material) {
    tinygltf::Primitive prim;
    prim.attributes["POSITION"] = b.add_floats(r.positions, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    prim.attributes["NORMAL"] = b.add_floats(r.normals, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    if (!r.uvs.empty())
        prim.attributes["TEXCOORD_0"] = b.add_floats(r.uvs, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    prim.indices = b.add_indices(r.indices);
    prim.material = material;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(std::move(prim));
}

// Piece p's mesh in its colour (material "<name>"); its fracture faces (region "inside"), if it has
// any, in a second primitive with the inside shade of that colour (material "<name>.inside"), as in
// the scene previews and the fragment files.
int add_mesh(GlbBuilder& b, const AnimationPiece& p, const Vec3& colour) {
    const SurfaceMesh& m = *p.rest_mesh;
    const int inside = region_id(m, "inside");
    bool has_inside = false, has_outside = m.num_triangles() == 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t) (inside >= 0 && m.region_of(t) == inside ? has_inside : has_outside) = true;
    tinygltf::Mesh mesh;
    mesh.name = p.name;
    if (has_outside) add_primitive(b, mesh, render_mesh(m, inside, false), b.add_material(p.name, colour));
    if (has_inside)
        add_primitive(b, mesh, render_mesh(m, inside, true), b.add_material(p.name + ".inside", inside_shade(colour)));
    b.model.meshes.push_back(std::move(mesh));
    return static_cast<int>(b.model.meshes.size()) - 1;
}

tinygltf::Value piece_extras(const AnimationPiece& p, int index) {
    tinygltf::Value::Object x;
    x["id"] = tinygltf::Value(index);
    x["parent"] = tinygltf::Value(p.parent);
    x["volume"] = tinygltf::Value(p.volume);
    x["mass"] = tinygltf::Value(p.mass);
    x["class"] = tinygltf::Value(std::string(piece_class_name(p.piece_class)));
    return tinygltf::Value(std::move(x));
}

// The frames a piece's keys sit at. Pose keys: every frame it is alive, plus the first and last
// frame of the animation when it is born later or dies earlier (holding its first / last pose).
// Scale keys (STEP): 0 from frame 0 if it is born later, 1 at first_frame, 0 at the frame after
// last_frame, and the value in force repeated at the last frame so the keys span the whole range.
struct PieceKeys {
    std::vector<int> pose_frames;   // key times are these frames' times
    std::vector<int> pose_sources;  // the frame whose pose each key holds
    std::vector<int> scale_frames;
    std::vector<float> scale_values;
};

PieceKeys piece_keys(const Animation& a, const AnimationPiece& p) {
    const int first = p.first_frame, last = last_visible_frame(a, p);
    const int end = static_cast<int>(a.frames.size()) - 1;
    PieceKeys k;
    if (first > 0) k.pose_frames.push_back(0);
    for (int f = first; f <= last; ++f) k.pose_frames.push_back(f);
    if (last < end) k.pose_frames.push_back(end);
    for (int f : k.pose_frames) k.pose_sources.push_back(std::clamp(f, first, last));

    auto scale_key = [&](int f, float s) {
        k.scale_frames.push_back(f);
        k.scale_values.push_back(s);
    };
    if (first > 0) scale_key(0, 0.0f);
    scale_key(first, 1.0f);
    if (last < end) scale_key(last + 1, 0.0f);
    if (k.scale_frames.back() < end) scale_key(end, k.scale_values.back());
    return k;
}

class AnimationBuilder {
public:
    AnimationBuilder(GlbBuilder& b, const Animation& a) : b_(b), a_(a) { anim_.name = "simulation"; }

    void add_piece(int piece, int node) {
        const AnimationPiece& p = a_.pieces[static_cast<std::size_t>(piece)];
        const PieceKeys k = piece_keys(a_, p);
        std::vector<float> translation, rotation, scale;
        Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
        for (std::size_t i = 0; i < k.pose_sources.size(); ++i) {
            const PiecePose& pose = *find_pose(a_.frames[static_cast<std::size_t>(k.pose_sources[i])], piece);
            translation.insert(translation.end(), {float(pose.position.x()), float(pose.position.y()), float(pose.position.z())});
            Eigen::Quaterniond q = pose.rotation;
            if (i > 0 && q.dot(previous) < 0) q.coeffs() = -q.coeffs();
            previous = q;
            // Eigen's coeffs() are (x, y, z, w), glTF's order.
            for (int c = 0; c < 4; ++c) rotation.push_back(float(q.coeffs()[c]));
        }
        for (float s : k.scale_values) scale.insert(scale.end(), {s, s, s});

        const int pose_times = times(k.pose_frames);
        channel(node, "translation", pose_times, b_.add_floats(translation, 3, TINYGLTF_TYPE_VEC3, 0, false), "LINEAR");
        channel(node, "rotation", pose_times, b_.add_floats(rotation, 4, TINYGLTF_TYPE_VEC4, 0, false), "LINEAR");
        channel(node, "scale", times(k.scale_frames), b_.add_floats(scale, 3, TINYGLTF_TYPE_VEC3, 0, false), "STEP");
    }

    void finish() { b_.model.animations.push_back(std::move(anim_)); }

private:
    // Input accessors are shared by all samplers keyed at the same frames (pieces alive throughout).
    int times(const std::vector<int>& frames) {
        auto it = inputs_.find(frames);
        if (it != inputs_.end()) return it->second;
        std::vector<float> t;
        for (int f : frames) t.push_back(float(a_.frames[static_cast<std::size_t>(f)].time));
        const int acc = b_.add_floats(t, 1, TINYGLTF_TYPE_SCALAR, 0, true);
        inputs_.emplace(frames, acc);
        return acc;
    }

    void channel(int node, const char* path, int input, int output, const char* interpolation) {
        tinygltf::AnimationSampler s;
        s.input = input;
        s.output = output;
        s.interpolation = interpolation;
        anim_.samplers.push_back(std::move(s));
        tinygltf::AnimationChannel c;
        c.sampler = static_cast<int>(anim_.samplers.size()) - 1;
        c.target_node = node;
        c.target_path = path;
        anim_.channels.push_back(std::move(c));
    }

    GlbBuilder& b_;
    const Animation& a_;
    tinygltf::Animation anim_;
    std::map<std::vector<int>, int> inputs_;
};

tinygltf::Node piece_node(const Animation& a, int piece, int mesh) {
    const AnimationPiece& p = a.pieces[static_cast<std::size_t>(piece)];
    const PiecePose& pose = *find_pose(a.frames[static_cast<std::size_t>(p.first_frame)], piece);
    tinygltf::Node n;
    n.name = p.name;
    n.mesh = mesh;
    n.translation = {pose.position.x(), pose.position.y(), pose.position.z()};
    const Eigen::Quaterniond& q = pose.rotation;
    n.rotation = {q.x(), q.y(), q.z(), q.w()};
    if (p.first_frame > 0) n.scale = {0.0, 0.0, 0.0};
    n.extras = piece_extras(p, piece);
    return n;
}

tinygltf::Node root_node(const Vec3& up, int pieces) {
    if (!up.allFinite() || up.norm() == 0)
        throw std::invalid_argument("cannot write .glb: the up axis must be a finite non-zero vector");
    tinygltf::Node root;
    root.name = "crackflow_scene";
    const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(up.normalized(), Vec3::UnitY());
    if (!q.vec().isZero()) root.rotation = {q.x(), q.y(), q.z(), q.w()};
    for (int i = 0; i < pieces; ++i) root.children.push_back(1 + i);
    return root;
}

tinygltf::Model build_model(const Animation& a, const GltfOptions& o) {
    GlbBuilder b;
    const int pieces = static_cast<int>(a.pieces.size());
    b.model.nodes.push_back(root_node(o.up, pieces));
    const std::vector<Vec3> colours = scene_piece_colours(a);  // the scene previews' colours
    AnimationBuilder anim(b, a);
    for (int i = 0; i < pieces; ++i) {
        const int mesh = add_mesh(b, a.pieces[static_cast<std::size_t>(i)], colours[static_cast<std::size_t>(i)]);
        b.model.nodes.push_back(piece_node(a, i, mesh));
        anim.add_piece(i, 1 + i);
    }
    if (pieces > 0) anim.finish();  // glTF forbids an animation without channels
    tinygltf::Scene scene;
    scene.name = "crackflow";
    scene.nodes = {0};
    b.model.scenes.push_back(std::move(scene));
    b.model.defaultScene = 0;
    if (b.model.buffers[0].data.empty()) b.model.buffers.clear();  // glTF forbids an empty buffer
    return std::move(b.model);
}

// glTF key times are float32 and must not be negative; frames closer than float32 resolves (at
// late times) would give keys that do not increase, which glTF forbids.
void check_key_times(const Animation& a) {
    if (a.frames.front().time < 0)
        throw std::invalid_argument("cannot write .glb: frame 0 is at t < 0 s; glTF animation times must be >= 0");
    for (std::size_t f = 1; f < a.frames.size(); ++f)
        if (!(float(a.frames[f].time) > float(a.frames[f - 1].time)))
            throw std::invalid_argument("cannot write .glb: frames " + std::to_string(f - 1) + " and " + std::to_string(f) +
                                        " have the same time in float32, glTF's precision for key times");
}

}  // namespace

void write_animation_glb(const Animation& a, const std::filesystem::path& path, const GltfOptions& o) {
    check_animation(a);
    check_key_times(a);
    const tinygltf::Model model = build_model(a, o);
    // A .glb states its length in 32 bits.
    if (!model.buffers.empty() && model.buffers[0].data.size() > std::numeric_limits<std::uint32_t>::max() / 2)
        throw std::invalid_argument("cannot write " + path.string() + ": the meshes and keys need more than 2 GiB, too much for one .glb");
    graph::write_atomically(path, [&](std::ostream& os) {
        tinygltf::TinyGLTF gltf;
        if (!gltf.WriteGltfSceneToStream(&model, os, false, true))
            throw std::runtime_error("cannot write " + path.string() + ": tinygltf failed to serialise the scene");
    });
}

}  // namespace cf::rigid
