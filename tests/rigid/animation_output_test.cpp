// The animation writers against independent readers. A synthetic scene with closed-form motion
// (a box that breaks at frame 3 into two halves, and a tetrahedron; ballistic flight under
// gravity with constant spin, 6 frames at 25 fps) is written as .glb and as a transform cache,
// then read back by the Khronos glTF validator (node), VTK's glTF and XML PolyData readers
// (python3-vtk9; tests/rigid/read_*.py) and tinygltf's loader, and compared with crackflow's
// own x_world = position + rotation * x_rest. The readers get the expectation as a JSON file.
#include "nodes/export/number_text.hpp"
#include "nodes/rigid/animation_checks.hpp"
#include "nodes/rigid/animation_gltf.hpp"
#include "nodes/domain/fragment_palette.hpp"
#include "nodes/rigid/piece_colours.hpp"
#include "nodes/rigid/transform_cache.hpp"
#include "nodes/shape/box.hpp"
#include "nodes/shape/icosphere.hpp"

#include "tests/harness/shell_command.hpp"

#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

using namespace cf;
using namespace cf::rigid;
using cf::testing::CommandResult;
using cf::testing::run_command;
using cf::testing::shell_quote;
namespace fs = std::filesystem;

namespace {

const Vec3 kGravity(0, 0, -9.81);  // [m/s^2], the scene is Z-up
constexpr double kFrameRate = 25;  // [1/s]
constexpr int kFrames = 6;
constexpr int kBreakFrame = 3;
constexpr double kDensity = 2500;  // [kg/m^3]

// ---- the synthetic scene -------------------------------------------------------------------

// Free flight from (p0, v0, q0) at time t0 with constant angular velocity omega (world axes).
struct Flight {
    Vec3 p0, v0;
    Eigen::Quaterniond q0;
    Vec3 omega;
    double t0 = 0;

    PiecePose at(double t) const {
        const double s = t - t0;
        PiecePose p;
        p.position = p0 + v0 * s + 0.5 * kGravity * s * s;
        p.velocity = v0 + kGravity * s;
        p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(omega.norm() * s, omega.normalized())) * q0;
        p.rotation.normalize();
        p.angular_velocity = omega;
        return p;
    }
};

// An irregular tetrahedron (no symmetry a wrong rotation could hide behind), centroid at the
// origin, outward oriented.
std::shared_ptr<SurfaceMesh> tetrahedron() {
    auto m = std::make_shared<SurfaceMesh>();
    m->vertices = {Vec3(0.0, 0.0, 0.0), Vec3(0.5, 0.05, 0.0), Vec3(0.1, 0.3, 0.02), Vec3(0.15, 0.1, 0.4)};
    const Vec3 c = (m->vertices[0] + m->vertices[1] + m->vertices[2] + m->vertices[3]) / 4;
    for (Vec3& v : m->vertices) v -= c;
    m->triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    if (signed_volume(*m) < 0)
        for (Tri& t : m->triangles) std::swap(t[1], t[2]);
    return m;
}

std::shared_ptr<SurfaceMesh> box(const Vec3& size) {
    BoxSpec spec;
    spec.size = size;
    spec.subdivisions = 1;
    return std::make_shared<SurfaceMesh>(make_box(spec));
}

AnimationPiece piece(const std::string& name, int parent, PieceClass c, std::shared_ptr<SurfaceMesh> mesh, int first,
                     int last) {
    AnimationPiece p;
    p.name = name;
    p.parent = parent;
    p.piece_class = c;
    p.volume = signed_volume(*mesh);
    p.mass = kDensity * p.volume;
    p.rest_mesh = std::move(mesh);
    p.first_frame = first;
    p.last_frame = last;
    return p;
}

// Pieces: 0 "box" (frames 0-2), 1 "tet" (all), 2 "box.0" and 3 "box.1" (the box's x halves, from
// frame 3 on). The halves start with the box's pose at the break, moving as rigid parts of it.
Animation synthetic_animation() {
    const Vec3 box_size(0.4, 0.2, 0.1);
    Animation a;
    a.frame_rate = kFrameRate;
    a.pieces.push_back(piece("box", -1, PieceClass::original, box(box_size), 0, kBreakFrame - 1));
    a.pieces.push_back(piece("tet", -1, PieceClass::original, tetrahedron(), 0, -1));
    const Vec3 half(0.2, 0.2, 0.1);
    a.pieces.push_back(piece("box.0", 0, PieceClass::breakable, box(half), kBreakFrame, -1));
    a.pieces.push_back(piece("box.1", 0, PieceClass::hull, box(half), kBreakFrame, -1));

    const Flight box_flight{Vec3(0, 0, 1), Vec3(1, 0.5, 2),
                            Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized())), Vec3(0.3, -1.2, 2.0)};
    const Flight tet_flight{Vec3(1, 0, 0.5), Vec3(-0.5, 0, 3), Eigen::Quaterniond::Identity(), Vec3(2, 0.5, -1)};
    const double t_break = kBreakFrame / kFrameRate;
    const PiecePose at_break = box_flight.at(t_break);
    std::vector<Flight> halves;
    for (double side : {-1.0, 1.0}) {
        const Vec3 c = at_break.position + at_break.rotation * Vec3(side * 0.1, 0, 0);
        const Vec3 v = at_break.velocity + box_flight.omega.cross(c - at_break.position);
        halves.push_back(Flight{c, v, at_break.rotation, box_flight.omega, t_break});
    }
    for (int f = 0; f < kFrames; ++f) {
        AnimationFrame frame;
        frame.time = f / kFrameRate;
        if (f < kBreakFrame) frame.poses.emplace_back(0, box_flight.at(frame.time));
        frame.poses.emplace_back(1, tet_flight.at(frame.time));
        if (f >= kBreakFrame)
            for (int k = 0; k < 2; ++k) frame.poses.emplace_back(2 + k, halves[std::size_t(k)].at(frame.time));
        a.frames.push_back(std::move(frame));
    }
    return a;
}

// The synthetic scene with each half's cut face (the face looking towards the other half) in the
// region "inside", as a fracture run's fragments have their fracture faces, and texture
// coordinates (affine in the position) on box.0.
Animation fractured_animation() {
    Animation a = synthetic_animation();
    for (std::size_t i : {std::size_t(2), std::size_t(3)}) {
        auto m = std::make_shared<SurfaceMesh>(*a.pieces[i].rest_mesh);
        const double towards = i == 2 ? 1.0 : -1.0;  // box.0 is the -x half, its cut face looks along +x
        m->region.assign(m->num_triangles(), 0);
        m->region_names = {"outside", "inside"};
        for (std::size_t t = 0; t < m->num_triangles(); ++t)
            if (triangle_normal(*m, t).x() * towards > 0.99) m->region[t] = 1;
        if (i == 2)  // texture coordinates on one half only, as from an artist's mesh beside a fallen-back piece
            for (const Tri& t : m->triangles) {
                std::array<Vec2, 3> w;
                for (int k = 0; k < 3; ++k) {
                    const Vec3& x = m->vertices[std::size_t(t[std::size_t(k)])];
                    w[std::size_t(k)] = Vec2(0.25 + 2 * x.x() - 0.5 * x.z(), 0.5 + 3 * x.y() + x.z());
                }
                m->corner_uv.push_back(w);
            }
        a.pieces[i].rest_mesh = m;
    }
    return a;
}

// ---- the expectation the python readers compare against ---------------------------------------

// glTF is Y-up: the writer's root node maps the scene's +Z onto +Y, a -90 degree turn about x.
Vec3 z_up_to_gltf(const Vec3& x) { return Vec3(x.x(), x.z(), -x.y()); }

class JsonOut {
public:
    explicit JsonOut(std::ostream& os) : os_(os) {}
    void number(double v) { write_real(os_, v); }
    void vec(const double* v, int n) {
        os_ << '[';
        for (int i = 0; i < n; ++i) {
            if (i) os_ << ',';
            number(v[i]);
        }
        os_ << ']';
    }
    void vec3(const Vec3& v) { vec(v.data(), 3); }
    template <class T, class F>
    void list(const std::vector<T>& items, F&& each) {
        os_ << '[';
        for (std::size_t i = 0; i < items.size(); ++i) {
            if (i) os_ << ',';
            each(items[i]);
        }
        os_ << ']';
    }
    std::ostream& raw() { return os_; }

private:
    std::ostream& os_;
};

// Everything the readers need, in crackflow's own terms: pieces (name, life, rest mesh) and per
// frame the live pieces' poses and world vertices (glTF axes) x = R_up (position + rotation x_rest).
void write_expectation(const Animation& a, const fs::path& path) {
    std::ofstream f(path);
    JsonOut j(f);
    f << "{\"frame_rate\":";
    j.number(a.frame_rate);
    f << ",\"pieces\":";
    j.list(a.pieces, [&](const AnimationPiece& p) {
        f << "{\"name\":\"" << p.name << "\",\"parent\":" << p.parent << ",\"class\":\"" << piece_class_name(p.piece_class)
          << "\",\"first\":" << p.first_frame << ",\"last\":" << last_visible_frame(a, p) << ",\"rest\":";
        j.list(p.rest_mesh->vertices, [&](const Vec3& x) { j.vec3(x); });
        f << ",\"triangles\":";
        j.list(p.rest_mesh->triangles, [&](const Tri& t) { f << '[' << t[0] << ',' << t[1] << ',' << t[2] << ']'; });
        const SurfaceMesh& m = *p.rest_mesh;
        std::vector<std::size_t> tris(m.num_triangles());
        for (std::size_t t = 0; t < tris.size(); ++t) tris[t] = t;
        f << ",\"inside\":";
        j.list(tris, [&](std::size_t t) { f << (m.region_name(m.region_of(t)) == "inside" ? 1 : 0); });
        f << ",\"uv\":";
        if (m.has_uv())
            j.list(tris, [&](std::size_t t) {
                const auto& w = m.corner_uv[t];
                const double corners[6] = {w[0].x(), w[0].y(), w[1].x(), w[1].y(), w[2].x(), w[2].y()};
                j.vec(corners, 6);
            });
        else
            f << "null";
        f << '}';
    });
    f << ",\"frames\":";
    j.list(a.frames, [&](const AnimationFrame& fr) {
        f << "{\"time\":";
        j.number(fr.time);
        f << ",\"poses\":";
        j.list(fr.poses, [&](const std::pair<int, PiecePose>& e) {
            const PiecePose& q = e.second;
            f << "{\"piece\":" << e.first << ",\"position\":";
            j.vec3(q.position);
            f << ",\"orient\":";
            j.vec(q.rotation.coeffs().data(), 4);  // x y z w
            f << ",\"v\":";
            j.vec3(q.velocity);
            f << ",\"w\":";
            j.vec3(q.angular_velocity);
            f << ",\"world_gltf\":";
            j.list(a.pieces[std::size_t(e.first)].rest_mesh->vertices,
                   [&](const Vec3& x) { j.vec3(z_up_to_gltf(q.position + q.rotation * x)); });
            f << '}';
        });
        f << '}';
    });
    f << "}\n";
    ASSERT_TRUE(f.good()) << "cannot write " << path;
}

// ---- running the external readers ----------------------------------------------------------



// The python that imports vtk, or an explanation of what to install.
::testing::AssertionResult vtk_python(std::string& python) {
    python = CRACKFLOW_VTK_PYTHON;
    const CommandResult r = run_command(shell_quote(python) + " -c 'import vtk'");
    if (r.exit_code == 0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << python << " cannot import vtk (" << r.output
           << "): install Debian's python3-vtk9 (apt-get install python3-vtk9, or ./setup.sh), or configure with "
              "-DCRACKFLOW_VTK_PYTHON=<a python3 that imports vtk>";
}

// node and the validator script beside the node_modules the build installed.
::testing::AssertionResult gltf_validator(std::string& command) {
    const std::string node = CRACKFLOW_NODE;
    const fs::path tools = CRACKFLOW_GLTF_TOOLS_DIR;
    if (node.empty() || node.find("NOTFOUND") != std::string::npos)
        return ::testing::AssertionFailure() << "node was not found when CMake configured the build: install Debian's "
                                                "nodejs and npm (apt-get install nodejs npm, or ./setup.sh) and re-run cmake";
    if (!fs::exists(tools / "node_modules" / "gltf-validator" / "package.json") || !fs::exists(tools / "validate_gltf.mjs"))
        return ::testing::AssertionFailure() << "the glTF validator is not installed in " << tools
                                             << ": build the target gltf_tools (npm ci from tests/tools/package-lock.json)";
    command = shell_quote(node) + " " + shell_quote((tools / "validate_gltf.mjs").string());
    return ::testing::AssertionSuccess();
}

// A fresh folder per test, kept after the run for inspection.
fs::path test_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path d = fs::path(CRACKFLOW_BINARY_DIR) / "animation_output" / (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string read_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

const fs::path kScripts = fs::path(CRACKFLOW_SOURCE_DIR) / "tests" / "rigid";

}  // namespace

// ---- glTF ----------------------------------------------------------------------------------

TEST(AnimationGltf, IsByteIdenticalForIdenticalInput) {
    const fs::path d = test_dir();
    const Animation a = synthetic_animation();
    write_animation_glb(a, d / "first.glb");
    write_animation_glb(synthetic_animation(), d / "second.glb");
    write_animation_glb(a, d / "first.glb");  // replaced in place
    const std::string first = read_bytes(d / "first.glb");
    ASSERT_GT(first.size(), 1000u);
    EXPECT_EQ(first.substr(0, 4), "glTF");
    EXPECT_TRUE(first == read_bytes(d / "second.glb"));
}

TEST(AnimationGltf, KhronosValidatorReportsNoErrors) {
    std::string validator;
    ASSERT_TRUE(gltf_validator(validator));
    const fs::path d = test_dir();
    write_animation_glb(synthetic_animation(), d / "scene.glb");
    write_animation_glb(synthetic_animation(), d / "scene_y_up.glb", GltfOptions{Vec3(0, 1, 0)});
    Animation empty;  // no pieces at all: a root node, no buffer, no animation
    empty.frames.resize(2);
    empty.frames[1].time = 0.04;
    write_animation_glb(empty, d / "empty.glb");
    write_animation_glb(fractured_animation(), d / "fractured.glb");
    for (const char* name : {"scene.glb", "scene_y_up.glb", "empty.glb", "fractured.glb"}) {
        const CommandResult r = run_command(validator + " " + shell_quote((d / name).string()));
        std::cout << r.output;  // the summary and any warnings, for the test log
        EXPECT_EQ(r.exit_code, 0) << r.output;
        EXPECT_NE(r.output.find(": 0 errors"), std::string::npos) << r.output;
    }
}

// Fracture faces (region "inside") are a second primitive in the inside shade of the piece's
// colour: box.0 and box.1 each have one cut face (2 triangles of a once-subdivided box face).
TEST(AnimationGltf, FractureFacesAreASecondPrimitiveInTheInsideShade) {
    const fs::path d = test_dir();
    const Animation a = fractured_animation();
    write_animation_glb(a, d / "fractured.glb");
    tinygltf::TinyGLTF loader;
    tinygltf::Model m;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &err, &warn, (d / "fractured.glb").string())) << err;
    const std::vector<Vec3> colours = scene_piece_colours(a);
    std::size_t materials = 0;
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
        const SurfaceMesh& rest = *a.pieces[i].rest_mesh;
        const int inside = region_id(rest, "inside");
        std::size_t inside_triangles = 0;
        for (std::size_t t = 0; t < rest.num_triangles(); ++t) inside_triangles += inside >= 0 && rest.region_of(t) == inside;
        const tinygltf::Mesh& mesh = m.meshes[std::size_t(m.nodes[1 + i].mesh)];
        ASSERT_EQ(mesh.primitives.size(), inside_triangles ? 2u : 1u) << a.pieces[i].name;
        materials += mesh.primitives.size();
        auto check = [&](const tinygltf::Primitive& prim, const std::string& name, const Vec3& rgb, std::size_t triangles) {
            const tinygltf::Material& mat = m.materials[std::size_t(prim.material)];
            EXPECT_EQ(mat.name, name);
            for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(mat.pbrMetallicRoughness.baseColorFactor[std::size_t(k)], rgb[k]);
            EXPECT_EQ(m.accessors[std::size_t(prim.indices)].count, 3 * triangles) << name;
        };
        const std::string& name = a.pieces[i].name;
        check(mesh.primitives[0], name, colours[i], rest.num_triangles() - inside_triangles);
        if (inside_triangles) {
            EXPECT_EQ(inside_triangles, 2u) << name;
            check(mesh.primitives[1], name + ".inside", inside_shade(colours[i]), inside_triangles);
        }
    }
    EXPECT_EQ(m.materials.size(), materials);
    EXPECT_EQ(materials, a.pieces.size() + 2);
}

// tinygltf's own loader: the structure the header promises (names, hierarchy, extras, keys).
TEST(AnimationGltf, StructureAsDocumented) {
    const fs::path d = test_dir();
    const Animation a = synthetic_animation();
    write_animation_glb(a, d / "scene.glb");
    write_animation_glb(a, d / "y_up.glb", GltfOptions{Vec3(0, 2, 0)});
    tinygltf::TinyGLTF loader;
    tinygltf::Model m, y;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &err, &warn, (d / "scene.glb").string())) << err;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&y, &err, &warn, (d / "y_up.glb").string())) << err;

    ASSERT_EQ(m.nodes.size(), 1 + a.pieces.size());
    EXPECT_EQ(m.nodes[0].name, "crackflow_scene");
    ASSERT_EQ(m.nodes[0].rotation.size(), 4u);  // -90 degrees about x: (x, y, z, w)
    EXPECT_NEAR(m.nodes[0].rotation[0], -std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(m.nodes[0].rotation[3], std::sqrt(0.5), 1e-15);
    EXPECT_TRUE(y.nodes[0].rotation.empty()) << "up = +Y needs no root rotation";
    EXPECT_EQ(m.nodes[0].children, (std::vector<int>{1, 2, 3, 4}));
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
        const tinygltf::Node& n = m.nodes[1 + i];
        const AnimationPiece& p = a.pieces[i];
        EXPECT_EQ(n.name, p.name);
        EXPECT_EQ(n.extras.Get("id").Get<int>(), int(i));
        EXPECT_EQ(n.extras.Get("parent").Get<int>(), p.parent);
        EXPECT_EQ(n.extras.Get("volume").GetNumberAsDouble(), p.volume);
        EXPECT_EQ(n.extras.Get("mass").GetNumberAsDouble(), p.mass);
        EXPECT_EQ(n.extras.Get("class").Get<std::string>(), piece_class_name(p.piece_class));
        // One material per piece, named after it, in its scene-preview colour (no fracture faces here).
        const tinygltf::Mesh& mesh = m.meshes[std::size_t(n.mesh)];
        ASSERT_EQ(mesh.primitives.size(), 1u);
        const tinygltf::Material& mat = m.materials[std::size_t(mesh.primitives[0].material)];
        EXPECT_EQ(mat.name, p.name);
        const Vec3 rgb = scene_piece_colours(a)[i];
        for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(mat.pbrMetallicRoughness.baseColorFactor[std::size_t(k)], rgb[k]);
    }
    EXPECT_EQ(m.materials.size(), a.pieces.size());
    ASSERT_EQ(m.animations.size(), 1u);
    const tinygltf::Animation& anim = m.animations[0];
    EXPECT_EQ(anim.name, "simulation");
    ASSERT_EQ(anim.channels.size(), 3 * a.pieces.size());

    // Scale keys (STEP) of each piece: times and values.
    auto scale_keys = [&](int node, std::vector<float>& times, std::vector<float>& values) {
        for (const auto& c : anim.channels) {
            if (c.target_node != node || c.target_path != "scale") continue;
            const auto& s = anim.samplers[std::size_t(c.sampler)];
            EXPECT_EQ(s.interpolation, "STEP");
            auto floats = [&](int accessor, std::size_t stride, std::vector<float>& out) {
                const auto& acc = m.accessors[std::size_t(accessor)];
                const auto& view = m.bufferViews[std::size_t(acc.bufferView)];
                const auto* data = reinterpret_cast<const float*>(m.buffers[0].data.data() + view.byteOffset + acc.byteOffset);
                for (std::size_t k = 0; k < acc.count; ++k) out.push_back(data[k * stride]);
            };
            floats(s.input, 1, times);
            floats(s.output, 3, values);
        }
    };
    auto t = [](int f) { return float(f / kFrameRate); };
    const std::vector<std::pair<std::vector<float>, std::vector<float>>> expected = {
        {{t(0), t(3), t(5)}, {1, 0, 0}},  // box: alive 0-2, gone from frame 3
        {{t(0), t(5)}, {1, 1}},           // tet: alive throughout
        {{t(0), t(3), t(5)}, {0, 1, 1}},  // the halves: born at frame 3
        {{t(0), t(3), t(5)}, {0, 1, 1}}};
    for (int i = 0; i < 4; ++i) {
        std::vector<float> times, values;
        scale_keys(1 + i, times, values);
        EXPECT_EQ(times, expected[std::size_t(i)].first) << a.pieces[std::size_t(i)].name;
        EXPECT_EQ(values, expected[std::size_t(i)].second) << a.pieces[std::size_t(i)].name;
    }
    // Not yet born: static scale 0, so a viewer without animation shows the initial state.
    EXPECT_EQ(m.nodes[3].scale, (std::vector<double>{0, 0, 0}));
    EXPECT_TRUE(m.nodes[1].scale.empty());
}

// Normals: smooth within the 30 degree crease angle (an icosphere's neighbouring faces differ by
// ~12 degrees at level 3: one output vertex per input vertex, normals near the radial direction),
// split across it (a box corner: one vertex per face, each with the face normal).
TEST(AnimationGltf, NormalsAreSmoothWithinTheCreaseAngleAndSplitAcrossIt) {
    const fs::path d = test_dir();
    Animation a = synthetic_animation();
    SphereSpec sphere;
    sphere.radius = 0.3;
    sphere.level = 3;
    a.pieces[1].rest_mesh = std::make_shared<SurfaceMesh>(make_icosphere(sphere));
    write_animation_glb(a, d / "scene.glb");
    tinygltf::TinyGLTF loader;
    tinygltf::Model m;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&m, &err, &warn, (d / "scene.glb").string())) << err;
    auto vec3s = [&](int accessor) {
        const auto& acc = m.accessors[std::size_t(accessor)];
        const auto& view = m.bufferViews[std::size_t(acc.bufferView)];
        const auto* f = reinterpret_cast<const float*>(m.buffers[0].data.data() + view.byteOffset + acc.byteOffset);
        std::vector<Vec3> out;
        for (std::size_t k = 0; k < acc.count; ++k) out.emplace_back(f[3 * k], f[3 * k + 1], f[3 * k + 2]);
        return out;
    };
    auto attributes = [&](int piece) {
        const auto& prim = m.meshes[std::size_t(m.nodes[std::size_t(1 + piece)].mesh)].primitives[0];
        return std::make_pair(vec3s(prim.attributes.at("POSITION")), vec3s(prim.attributes.at("NORMAL")));
    };
    const auto [sphere_x, sphere_n] = attributes(1);
    EXPECT_EQ(sphere_x.size(), a.pieces[1].rest_mesh->num_vertices());
    for (std::size_t k = 0; k < sphere_x.size(); ++k) {
        EXPECT_NEAR(sphere_n[k].norm(), 1, 1e-6);
        EXPECT_GT(sphere_n[k].dot(sphere_x[k].normalized()), std::cos(2 * M_PI / 180)) << "vertex " << k;
    }
    const auto [box_x, box_n] = attributes(0);
    ASSERT_EQ(box_x.size(), 24u);  // 8 corners x 3 faces
    for (std::size_t k = 0; k < box_x.size(); ++k) {
        EXPECT_NEAR(box_n[k].cwiseAbs().maxCoeff(), 1, 1e-7) << "an axis: the normal of one face";
        EXPECT_GT(box_n[k].dot(box_x[k]), 0) << "outward";
    }
}

// VTK's glTF reader plays the animation: at each frame time the vertices of live pieces are at
// crackflow's x_world (to float32 precision), and hidden pieces collapse to a point.
TEST(AnimationGltf, VtkReaderPlaysTheAnimation) {
    std::string python;
    ASSERT_TRUE(vtk_python(python));
    const fs::path d = test_dir();
    const Animation a = synthetic_animation();
    write_animation_glb(a, d / "scene.glb");
    write_expectation(a, d / "expected.json");
    const CommandResult r = run_command(shell_quote(python) + " " + shell_quote((kScripts / "read_gltf_animation.py").string()) +
                                        " " + shell_quote((d / "scene.glb").string()) + " " +
                                        shell_quote((d / "expected.json").string()));
    std::cout << r.output;
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

// ---- transform cache -----------------------------------------------------------------------

TEST(AnimationTransformCache, VtkReadsEveryFrameExactly) {
    std::string python;
    ASSERT_TRUE(vtk_python(python));
    const fs::path d = test_dir();
    const Animation a = fractured_animation();  // fracture faces, and UVs on one piece
    write_transform_cache(a, d / "cache", "scene");
    write_expectation(a, d / "expected.json");
    for (int f = 0; f < kFrames; ++f) EXPECT_TRUE(fs::exists(d / "cache" / transform_cache_frame_name("scene", f)));
    EXPECT_EQ(transform_cache_frame_name("scene", 7), "scene_0007.vtp");
    const CommandResult r = run_command(
        shell_quote(python) + " " + shell_quote((kScripts / "read_transform_cache.py").string()) + " " +
        shell_quote((d / "cache").string()) + " scene " + shell_quote((d / "expected.json").string()) + " --houdini-doc " +
        shell_quote((fs::path(CRACKFLOW_SOURCE_DIR) / "docs" / "animation-output.md").string()));
    std::cout << r.output;
    EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(AnimationTransformCache, IsByteIdenticalAndNeedsAPlainStem) {
    const fs::path d = test_dir();
    write_transform_cache(synthetic_animation(), d / "a", "s");
    write_transform_cache(synthetic_animation(), d / "b", "s");
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(d / "a")) {
        ++files;
        EXPECT_TRUE(read_bytes(e.path()) == read_bytes(d / "b" / e.path().filename())) << e.path();
    }
    EXPECT_EQ(files, std::size_t(kFrames + 2));  // frames, rest, .pvd; no temporary files left
    EXPECT_THROW(write_transform_cache(synthetic_animation(), d, "sub/s"), std::invalid_argument);
    EXPECT_THROW(write_transform_cache(synthetic_animation(), d, ""), std::invalid_argument);
    Animation empty;  // no pieces: frames of zero points
    empty.frames.resize(1);
    write_transform_cache(empty, d / "empty", "s");
    EXPECT_NE(read_bytes(d / "empty" / "s_0000.vtp").find("NumberOfPoints=\"0\""), std::string::npos);
}

// ---- check_animation -----------------------------------------------------------------------

namespace {

// The message of the invalid_argument `f` throws, or "" if it does not throw one.
std::string rejection(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

std::string check_message(const std::function<void(Animation&)>& spoil) {
    Animation a = synthetic_animation();
    spoil(a);
    return rejection([&] { check_animation(a); });
}

PiecePose& pose_of(Animation& a, int frame, int piece) {
    for (auto& e : a.frames[std::size_t(frame)].poses)
        if (e.first == piece) return e.second;
    throw std::logic_error("no such pose in the synthetic animation");
}

}  // namespace

TEST(AnimationChecks, AcceptTheSyntheticScene) {
    EXPECT_NO_THROW(check_animation(synthetic_animation()));
    // Rounding-level quaternion drift is fine.
    EXPECT_EQ(check_message([](Animation& a) { pose_of(a, 1, 1).rotation.coeffs() *= 1 + 1e-10; }), "");
}

TEST(AnimationChecks, RejectEachBadCaseNamingThePieceOrFrame) {
    const std::vector<std::pair<std::function<void(Animation&)>, std::vector<std::string>>> cases = {
        {[](Animation& a) { a.pieces[2].name.clear(); }, {"piece 2 has an empty name"}},
        {[](Animation& a) { a.pieces[3].name = "box.0"; }, {"pieces 2 and 3 are both named \"box.0\""}},
        {[](Animation& a) { a.pieces[2].parent = 7; }, {"piece 2 \"box.0\" has parent 7"}},
        {[](Animation& a) { a.pieces[2].parent = -2; }, {"piece 2 \"box.0\" has parent -2"}},
        {[](Animation& a) { a.pieces[2].parent = 2; }, {"piece 2 \"box.0\" has parent 2"}},
        {[](Animation& a) { a.pieces[1].rest_mesh = nullptr; }, {"piece 1 \"tet\" has no rest mesh"}},
        {[](Animation& a) { a.pieces[1].rest_mesh = std::make_shared<SurfaceMesh>(); }, {"piece 1 \"tet\" has an empty rest mesh"}},
        {[](Animation& a) {
             auto m = std::make_shared<SurfaceMesh>(*a.pieces[1].rest_mesh);
             m->triangles[2][1] = 4;
             a.pieces[1].rest_mesh = m;
         },
         {"piece 1 \"tet\": rest mesh triangle 2 uses vertex 4 of 4"}},
        {[](Animation& a) { pose_of(a, 4, 3).position.x() = std::nan(""); },
         {"frame 4 (t = 0.16 s), piece 3 \"box.1\": the pose is not finite"}},
        {[](Animation& a) { pose_of(a, 2, 0).angular_velocity.z() = INFINITY; },
         {"frame 2 (t = 0.08 s), piece 0 \"box\": the pose is not finite"}},
        {[](Animation& a) { pose_of(a, 1, 1).rotation.coeffs() *= 1 + 1e-8; },
         {"frame 1 (t = 0.04 s), piece 1 \"tet\": the rotation quaternion has norm", "unit quaternion"}},
        {[](Animation& a) { std::swap(a.frames[3].poses[0], a.frames[3].poses[1]); },
         {"frame 3 (t = 0.12 s): the pose of piece 1 \"tet\" comes after piece 2's", "strictly increasing piece index"}},
        {[](Animation& a) { a.frames[4].poses.push_back(a.frames[4].poses.back()); },
         {"frame 4 (t = 0.16 s): the pose of piece 3 \"box.1\" comes after piece 3's"}},
        {[](Animation& a) { a.frames[1].poses[1].first = 9; }, {"frame 1 (t = 0.04 s) has a pose for piece 9, which does not exist"}},
        {[](Animation& a) { a.frame_rate = 0; }, {"frame_rate is 0 1/s"}},
        {[](Animation& a) { a.frame_rate = -25; }, {"frame_rate is -25 1/s"}},
        {[](Animation& a) { a.frames.clear(); }, {"no frames"}},
        {[](Animation& a) { a.frames[2].time = a.frames[1].time; }, {"frame 2 (t = 0.04 s): its time is not after frame 1's"}},
        {[](Animation& a) { a.pieces[2].first_frame = 2; }, {"frame 2 (t = 0.08 s) has no pose for piece 2 \"box.0\""}},
        {[](Animation& a) { a.pieces[2].first_frame = 6; }, {"piece 2 \"box.0\" has first_frame 6 but there are frames 0..5"}},
        {[](Animation& a) { a.pieces[2].first_frame = -1; }, {"piece 2 \"box.0\" has first_frame -1"}},
        {[](Animation& a) { a.pieces[0].last_frame = 9; }, {"piece 0 \"box\" has last_frame 9"}},
        {[](Animation& a) { a.pieces[2].last_frame = 1; }, {"piece 2 \"box.0\" has last_frame 1; it must be -1 or in [first_frame = 3, 5]"}},
        {[](Animation& a) { a.pieces[0].last_frame = 3; }, {"frame 3 (t = 0.12 s) has no pose for piece 0 \"box\""}},
        {[](Animation& a) { a.pieces[0].last_frame = 1; },
         {"frame 2 (t = 0.08 s) has a pose for piece 0 \"box\", which is visible only in frames 0..1"}},
        {[](Animation& a) { a.pieces[1].mass = -1; }, {"piece 1 \"tet\": volume and mass must be finite and >= 0"}},
    };
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const std::string msg = check_message(cases[k].first);
        ASSERT_FALSE(msg.empty()) << "case " << k << " (expected: " << cases[k].second[0] << ") was accepted";
        for (const std::string& part : cases[k].second)
            EXPECT_NE(msg.find(part), std::string::npos) << "case " << k << ": \"" << msg << "\" lacks \"" << part << "\"";
    }
}

TEST(AnimationChecks, WritersRefuseABadAnimationAndWriteNothing) {
    const fs::path d = test_dir();
    Animation a = synthetic_animation();
    a.pieces[3].name = "box.0";
    EXPECT_NE(rejection([&] { write_animation_glb(a, d / "bad.glb"); }).find("both named \"box.0\""), std::string::npos);
    EXPECT_NE(rejection([&] { write_transform_cache(a, d, "bad"); }).find("both named \"box.0\""), std::string::npos);
    EXPECT_TRUE(fs::is_empty(d));
    EXPECT_THROW(write_animation_glb(synthetic_animation(), d / "up.glb", GltfOptions{Vec3::Zero()}), std::invalid_argument);
    EXPECT_THROW(write_animation_glb(synthetic_animation(), d / "up.glb", GltfOptions{Vec3(0, std::nan(""), 1)}),
                 std::invalid_argument);
    Animation early = synthetic_animation();  // glTF times must be >= 0
    for (AnimationFrame& f : early.frames) f.time -= 1;
    EXPECT_NE(rejection([&] { write_animation_glb(early, d / "early.glb"); }).find("t < 0 s"), std::string::npos);
    Animation late = synthetic_animation();  // 1e8 s: float32 cannot tell the frames apart
    for (AnimationFrame& f : late.frames) f.time += 1e8;
    EXPECT_NE(rejection([&] { write_animation_glb(late, d / "late.glb"); }).find("frames 0 and 1 have the same time in float32"),
              std::string::npos);
    EXPECT_FALSE(fs::exists(d / "early.glb") || fs::exists(d / "late.glb"));
    EXPECT_EQ(std::string(piece_class_name(PieceClass::large)), "large");
    EXPECT_EQ(std::string(piece_class_name(PieceClass::hull)), "hull");
}
