// Rigid-body scenes end to end (thesis ch. 7): the collision loads against hand-computed values, a
// shipped scene byte-identical for 1 and 2 threads and valid for the Khronos glTF validator, and
// bad scene inputs rejected with the body and parameter named.
#include "graph/executor.hpp"
#include "graph/pipeline.hpp"
#include "nodes/register_all.hpp"
#include "nodes/rigid/contact_duration.hpp"
#include "nodes/rigid/impact_loads.hpp"
#include "nodes/rigid/scene_simulation.hpp"
#include "nodes/domain/mesh_topology.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/shape/box.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <tiny_gltf.h>

#include <chrono>
#include <cmath>
#include <array>
#include <csignal>
#include <cstring>
#include <map>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

int run_command(const std::string& cmd, std::string& output) {
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    if (!p) return -1;
    char buf[4096];
    output.clear();
    while (std::size_t n = fread(buf, 1, sizeof buf, p)) output.append(buf, n);
    const int status = pclose(p);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Writes `yaml` to dir/scene.yaml and runs it with the crackflow binary into dir/out; returns the
// exit code, the output in `log`.
int run_pipeline_in(const fs::path& dir, const std::string& yaml, std::string& log) {
    { std::ofstream(dir / "scene.yaml") << yaml; }
    return run_command(std::string(CRACKFLOW_EXE) + " run " + (dir / "scene.yaml").string() + " --out " +
                           (dir / "out").string(),
                       log);
}

// Runs a shipped pipeline (pipelines/<name>) at --fast into `out`; returns crackflow's exit code.
int run_shipped_fast(const std::string& name, const fs::path& out, std::string& log) {
    return run_command(std::string(CRACKFLOW_EXE) + " run " + CRACKFLOW_SOURCE_DIR + "/pipelines/" + name +
                           " --fast --out " + out.string(),
                       log);
}

// Loads and runs a scene given as text; returns the error ("" on success).
std::string run_scene_text(const std::string& yaml, const std::string& name) {
    std::vector<cf::graph::Diagnostic> diags;
    const fs::path file = cf::testing::temp_dir("scene-" + name) / "scene.yaml";
    { std::ofstream(file) << yaml; }
    auto plan = cf::graph::load_pipeline_file(file.string(), cf::node_registry(), {}, diags);
    std::string text;
    for (const auto& d : diags) text += cf::graph::format(d) + "\n";
    if (!diags.empty()) return text;
    cf::graph::RunOptions o;
    o.output_dir = file.parent_path() / "out";
    const auto r = cf::graph::execute(plan, o);
    return r.ok ? std::string() : r.error;
}

std::string scene_with(const std::string& box_params, const std::string& extra_nodes = "",
                       const std::string& scene_params = "{time_step: 0.004, frame_rate: 50}",
                       const std::string& bodies = "box.bodies") {
    return "nodes:\n"
           "  weak: {type: material.brittle, params: {E: 1.0e10, nu: 0.2, rho: 1500, tensile_strength: 5.0e4, "
           "toughness: 2.0e3, compressive_factor: 10}}\n"
           "  mesh: {type: shape.box, params: {size: [0.2, 0.2, 0.2], subdivisions: 3}}\n"
           "  box: {type: rigid.body, inputs: {mesh: mesh.mesh, material: weak.material}, params: " + box_params + "}\n" +
           extra_nodes +
           "  scene: {type: rigid.scene, inputs: {bodies: " + bodies + "}, params: " + scene_params + "}\n"
           "  frames:\n"
           "    type: loop\n"
           "    params: {max_iterations: 2}\n"
           "    inputs: {scene: scene.scene}\n"
           "    body: {step: {type: rigid.frame, inputs: {scene: frames.scene}}}\n"
           "    next: {scene: step.scene}\n";
}

}  // namespace

// One contact on a unit-area element: t_c by Hertz (eq. in ch. 7.2), traction J n / (t_c A_e) on the
// closest element only, the duration capped at the rigid step for a slow (resting) contact.
TEST(ImpactLoads, TractionOnTheClosestElementIsImpulseOverDurationAndArea) {
    cf::BoxSpec spec;
    spec.size = cf::Vec3(1, 1, 1);
    spec.subdivisions = 1;  // 12 triangles of area 1/2
    const cf::SurfaceMesh box = cf::make_box(spec);
    const std::vector<double> flat(box.num_triangles(), 0.0);
    cf::rigid::ContactBody self{2e10, 0.2, 10.0, 0.0};
    cf::rigid::BodyContact c;
    c.point = cf::Vec3(0.2, 0.1, -0.5);  // on the bottom face (z = -0.5)
    c.direction = cf::Vec3(0, 0, 1);
    c.impulse = 3.0;
    c.approach_speed = 2.0;
    c.partner = cf::rigid::ContactBody{3e10, 0.2, 0.0, 0.0};
    const auto loads = cf::rigid::impact_loads(box, flat, self, {c}, 1.0);
    // Hand-computed: E = 1 / (0.96/2e10 + 0.96/3e10) = 1.25e10 Pa, R = max_radius = 1 m, m = 10 kg.
    const double E = 1 / (0.96 / 2e10 + 0.96 / 3e10);
    const double tc = 2.87 * std::pow(100.0 / (E * E * 1.0 * 2.0), 0.2);
    EXPECT_NEAR(loads.contact_duration, tc, 1e-12 * tc);
    EXPECT_NEAR(loads.force, 3.0 / tc, 1e-9 * 3.0 / tc);
    int loaded = 0;
    for (std::size_t t = 0; t < box.num_triangles(); ++t) {
        if (loads.traction[t].norm() == 0) continue;
        ++loaded;
        EXPECT_LT(cf::triangle_centroid(box, t).z(), -0.49);
        EXPECT_NEAR(loads.traction[t].z(), 3.0 / (tc * 0.5), 1e-9 * 3.0 / (tc * 0.5));
    }
    EXPECT_EQ(loaded, 1);
    // A rigid step shorter than t_c: the impulse was delivered over the step.
    const auto resting = cf::rigid::impact_loads(box, flat, self, {c}, tc / 4);
    EXPECT_NEAR(resting.force, 3.0 / (tc / 4), 1e-9 * 12.0 / tc);
}

// scene_determinism: the shipped falling_objects scene in fast mode writes the same .glb, byte for
// byte, and the same fracture runs with 1 and 2 threads; the .glb passes the Khronos validator.
// A breakable body's BEM surface encloses its object (crack elements end just inside the object, and
// one crossing the BEM surface fails the run): brick_breaking's brick at r_f 0.5 mm remeshed to 200
// triangles from a 7 mm grid rounds its edges inside the brick by several millimetres, far more than
// the one-voxel offset; the offset grows until no vertex, edge midpoint or centroid lies more than
// half a voxel inside. The price, measured: 30 % more volume than the brick (bar: 35 %).
TEST(BreakableSurface, TheBemSurfaceEnclosesItsObject) {
    cf::BoxSpec b;
    b.size = cf::Vec3(0.2, 0.1, 0.06);
    b.subdivisions = 4;
    const double r_f = 5e-4;
    const cf::LevelSet object = cf::level_set_from_mesh(cf::make_box(b), r_f);
    const cf::SurfaceMesh bem = cf::rigid::coarse_surface(object, 200, 1);
    double deepest = 0;
    for (const cf::Tri& t : bem.triangles) {
        const cf::Vec3 &p = bem.vertices[t[0]], &q = bem.vertices[t[1]], &r = bem.vertices[t[2]];
        for (const cf::Vec3& x : {p, cf::Vec3(0.5 * (p + q)), cf::Vec3((p + q + r) / 3.0)}) deepest = std::max(deepest, -cf::sample(object, x));
    }
    std::printf("BEM triangles %zu, deepest point inside the brick %.3g m, volume %.4g m^3 (brick 1.2e-3)\n",
                bem.num_triangles(), deepest, cf::signed_volume(bem));
    EXPECT_LE(deepest, 0.5 * r_f);
    EXPECT_GT(cf::signed_volume(bem), 1.2e-3);
    EXPECT_LT(cf::signed_volume(bem), 1.35 * 1.2e-3);
    // Without the offset the remesh cuts into the brick: the test would tell.
    const cf::SurfaceMesh plain = cf::rigid::coarse_surface(object, 200, 0);
    double plain_deepest = 0;
    for (const cf::Vec3& x : plain.vertices) plain_deepest = std::max(plain_deepest, -cf::sample(object, x));
    for (const cf::Tri& t : plain.triangles)
        plain_deepest = std::max(plain_deepest, -cf::sample(object, cf::Vec3((plain.vertices[t[0]] + plain.vertices[t[1]] + plain.vertices[t[2]]) / 3.0)));
    EXPECT_GT(plain_deepest, 2 * r_f);
}

// A remeshed BEM surface is one shell: each extra shell adds six rigid modes the pure Neumann system
// (eq. 7.4) does not regularise, and every run on such a fragment failed with an indefinite D_R.
// A speck beside a body is dropped; two bodies of similar size are refused (the scene then keeps the
// fragment as a collision mesh that does not break again).
TEST(BreakableSurface, TheBemSurfaceIsOneShell) {
    auto two_boxes = [](double small_side) {
        cf::BoxSpec a, b;
        a.size = cf::Vec3(0.1, 0.1, 0.1);
        b.size = cf::Vec3(small_side, small_side, small_side);
        b.centre = cf::Vec3(0.2, 0, 0);
        cf::SurfaceMesh m = cf::make_box(a);
        const cf::SurfaceMesh mb = cf::make_box(b);
        const int n = static_cast<int>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), mb.vertices.begin(), mb.vertices.end());
        for (cf::Tri t : mb.triangles) m.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
        return cf::level_set_from_mesh(m, 2e-3);
    };
    const cf::SurfaceMesh one = cf::rigid::coarse_surface(two_boxes(0.02), 300, 1);
    EXPECT_EQ(cf::check_topology(one).components, 1u);
    EXPECT_GT(cf::signed_volume(one), 1e-3);  // the large box's shell is the one kept
    EXPECT_THROW(cf::rigid::coarse_surface(two_boxes(0.09), 300, 1), std::runtime_error);
}

// Ctrl-C in the middle of a scene's frame (its fracture runs, the fragments' preparation or a
// Bullet step with hundreds of pieces) stops the run within 0.5 s, plus a margin for writing the
// report on a busy machine: exit 130, report status "cancelled". A full-resolution bunny used to
// ignore SIGTERM for over 7 s inside one frame.
TEST(Scene, CtrlCStopsASceneInsideAFrame) {
    for (const double delay : {3.0, 6.0}) {
        const fs::path out = cf::testing::temp_dir("scene-ctrl-c");
        int fds[2];
        ASSERT_EQ(pipe(fds), 0);
        const std::string pipeline = std::string(CRACKFLOW_SOURCE_DIR) + "/pipelines/falling_objects.yaml";
        const pid_t pid = fork();
        if (pid == 0) {
            dup2(fds[1], 1);
            dup2(fds[1], 2);
            close(fds[0]);
            execl(CRACKFLOW_EXE, CRACKFLOW_EXE, "run", pipeline.c_str(), "--fast", "--threads", "2", "--out",
                  out.c_str(), static_cast<char*>(nullptr));
            _exit(99);
        }
        close(fds[1]);
        // The frame loop runs for about 15 s (loaded: longer), later frames a second or more each
        // (fracture runs and a heap of fragments); loop lines are rate-limited, so count from its start.
        std::string log;
        char buf[4096];
        ssize_t n;
        while (log.find("start  frames") == std::string::npos && (n = read(fds[0], buf, sizeof buf)) > 0)
            log.append(buf, static_cast<std::size_t>(n));
        std::this_thread::sleep_for(std::chrono::duration<double>(delay));
        const auto t0 = std::chrono::steady_clock::now();
        kill(pid, SIGINT);
        int status = 0;
        waitpid(pid, &status, 0);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        while ((n = read(fds[0], buf, sizeof buf)) > 0) log.append(buf, static_cast<std::size_t>(n));
        close(fds[0]);
        std::printf("SIGINT %.1f s into the frame loop: exit %.3f s later\n", delay, seconds);
        ASSERT_TRUE(WIFEXITED(status)) << log;
        EXPECT_EQ(WEXITSTATUS(status), 130) << log;
        EXPECT_LT(seconds, 0.5 + 0.5) << log;
        EXPECT_NE(read_file(out / "report.json").find("\"cancelled\""), std::string::npos);
    }
}

TEST(Scene, FallingObjectsIsIdenticalForOneAndTwoThreadsAndValidGltf) {
    std::string glb[2], runs[2];
    for (int threads : {1, 2}) {
        const fs::path out = cf::testing::temp_dir("falling-objects-" + std::to_string(threads));
        std::string log;
        const int rc = run_command(std::string(CRACKFLOW_EXE) + " run " + CRACKFLOW_SOURCE_DIR +
                                       "/pipelines/falling_objects.yaml --fast --threads " + std::to_string(threads) +
                                       " --out " + out.string(),
                                   log);
        ASSERT_EQ(rc, 0) << log;
        glb[threads - 1] = read_file(out / "scene.glb");
        // The run listing without its wall-time column.
        std::istringstream csv(read_file(out / "fracture_runs.csv"));
        for (std::string line; std::getline(csv, line);) {
            std::vector<std::string> cols;
            std::stringstream ls(line);
            for (std::string col; std::getline(ls, col, ',');) cols.push_back(col);
            if (cols.size() > 13) cols[13] = "";  // seconds
            for (const auto& col : cols) runs[threads - 1] += col + ",";
            runs[threads - 1] += "\n";
        }
        if (threads == 2) {
            // Later runs of a body reuse its surface blocks and factorisation (ch. 7.3): assemble0 and
            // solve0 of some run count them as reused (the .glb equals the one before reuse existed).
            int reused = 0;
            for (const auto& dir : fs::directory_iterator(out / "fracture_runs")) {
                const std::string run = read_file(dir.path() / "run.json");
                auto node = [&](const std::string& name) {  // the flat object of counts of one node
                    const std::size_t at = run.find("\"" + name + "\":{");
                    return at == std::string::npos ? std::string() : run.substr(at, run.find('}', at) - at);
                };
                reused += node("assemble0").find("\"surface_reused\":1") != std::string::npos &&
                          node("solve0").find("\"surface_factor_reused\":1") != std::string::npos;
            }
            EXPECT_GT(reused, 0) << "no fracture run reused its body's surface blocks and factor";
            std::string report;
            const int v = run_command(std::string(CRACKFLOW_NODE) + " " + CRACKFLOW_GLTF_TOOLS_DIR + "/validate_gltf.mjs " +
                                          (out / "scene.glb").string(),
                                      report);
            EXPECT_EQ(v, 0) << "gltf-validator on the scene: " << report;
        }
    }
    ASSERT_GT(glb[0].size(), 1000u);
    EXPECT_TRUE(glb[0] == glb[1]) << "scene.glb differs between 1 and 2 threads";
    EXPECT_EQ(runs[0], runs[1]);
    EXPECT_NE(runs[0].find(",1,\"\","), std::string::npos) << "no fracture run broke a body:\n" << runs[0];
}

TEST(SceneInputs, BreakableWithoutMaterialIsRejected) {
    const std::string yaml =
        "nodes:\n"
        "  mesh: {type: shape.box, params: {size: [0.2, 0.2, 0.2]}}\n"
        "  box: {type: rigid.body, inputs: {mesh: mesh.mesh}, params: {density: 1000, breakable: true, r_f: 0.005}}\n"
        "  scene: {type: rigid.scene, inputs: {bodies: box.bodies}}\n";
    const std::string e = run_scene_text(yaml, "no-material");
    EXPECT_NE(e.find("body 'box': parameter 'breakable' needs the input 'material'"), std::string::npos) << e;
}

TEST(SceneInputs, OutOfRangeParametersNameTheParameter) {
    for (const auto& [params, scene, what] : std::vector<std::tuple<std::string, std::string, std::string>>{
             {"{density: -5}", "{}", "density"},
             {"{force_threshold: -5}", "{}", "force_threshold"},
             {"{position: [0, 0, 1]}", "{time_step: 0}", "time_step"},
         }) {
        const std::string e = run_scene_text(scene_with(params, "", scene), "range-" + what);
        EXPECT_NE(e.find("'" + what + "'"), std::string::npos) << e;
    }
}

TEST(SceneInputs, AFrameOfPartialStepsIsRejected) {
    const std::string e = run_scene_text(scene_with("{position: [0, 0, 1]}", "", "{time_step: 0.003, frame_rate: 50}"), "partial");
    EXPECT_NE(e.find("whole number of rigid steps"), std::string::npos) << e;
}

TEST(SceneInputs, FrameAndStepLengthsPrintEveryDigit) {
    // Six significant digits would print the time step as 0.00123457.
    const std::string e =
        run_scene_text(scene_with("{position: [0, 0, 1]}", "", "{time_step: 0.0012345678, frame_rate: 50}"), "digits");
    EXPECT_NE(e.find("(1 / frame_rate = 0.02 s)"), std::string::npos) << e;
    EXPECT_NE(e.find("(time_step = 0.0012345678 s)"), std::string::npos) << e;
}

TEST(SceneInputs, ABodyStartingInsideAnotherIsNamed) {
    const std::string other =
        "  other: {type: rigid.body, inputs: {mesh: mesh.mesh, after: box.bodies}, params: {density: 1000, position: [0.05, 0, 1]}}\n";
    const std::string e = run_scene_text(scene_with("{position: [0, 0, 1]}", other, "{time_step: 0.004, frame_rate: 50}", "other.bodies"),
                                         "inside");
    EXPECT_NE(e.find("body 'box' starts inside body 'other'"), std::string::npos) << e;
}

TEST(SceneInputs, AnOpenMeshIsRejectedNamingTheBody) {
    const fs::path dir = cf::testing::temp_dir("scene-open-mesh");
    {
        std::ofstream obj(dir / "open.obj");
        obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n";  // a tetrahedron missing a face
    }
    const std::string yaml =
        "nodes:\n"
        "  mesh: {type: import.mesh, params: {path: " + (dir / "open.obj").string() + "}}\n"
        "  box: {type: rigid.body, inputs: {mesh: mesh.mesh}, params: {density: 1000}}\n"
        "  scene: {type: rigid.scene, inputs: {bodies: box.bodies}}\n";
    const std::string e = run_scene_text(yaml, "open");
    EXPECT_FALSE(e.empty());
    EXPECT_TRUE(e.find("open") != std::string::npos || e.find("closed") != std::string::npos) << e;
}

// A BEM mesh given to a breakable body must be a closed surface of that body, in its frame.
TEST(SceneInputs, ABemMeshOfAnotherShapeOrFrameIsRejected) {
    const std::string base = "{breakable: true, r_f: 0.01, position: [0, 0, 1]}";
    auto with_bem = [&](const std::string& bem) {
        return scene_with(base, "  bem: {type: shape.box, params: " + bem + "}\n");
    };
    // The same box with cells of 5 cm: accepted.
    std::string yaml = with_bem("{size: [0.2, 0.2, 0.2], cell_size: 0.05}");
    const auto insert_input = [](std::string y) {
        const std::string from = "inputs: {mesh: mesh.mesh, material: weak.material}";
        y.replace(y.find(from), from.size(), "inputs: {mesh: mesh.mesh, bem_mesh: bem.mesh, material: weak.material}");
        return y;
    };
    EXPECT_EQ(run_scene_text(insert_input(yaml), "bem-ok"), "");
    // Twice the size, or moved by 5 cm: the vertex and its distance are named.
    for (const std::string& bem : {std::string("{size: [0.4, 0.4, 0.4], cell_size: 0.1}"),
                                   std::string("{size: [0.2, 0.2, 0.2], centre: [0.05, 0, 0], cell_size: 0.05}")}) {
        const std::string e = run_scene_text(insert_input(with_bem(bem)), "bem-bad");
        EXPECT_NE(e.find("body 'box', input 'bem_mesh': vertex "), std::string::npos) << e;
        EXPECT_NE(e.find("from the body's surface"), std::string::npos) << e;
    }
}

// breaking_bar (thesis fig. 30), fast mode: the bar dropped 0.5 mm onto its supports breaks in the
// first frame, between the supports (where it bends): its two largest fragments each hold one end of
// the bar and reach past their support, every other fragment lies between the supports.
TEST(Scene, BreakingBarBreaksBetweenItsSupports) {
    const fs::path out = cf::testing::temp_dir("breaking-bar");
    std::string log;
    const int rc = run_shipped_fast("breaking_bar.yaml", out, log);
    ASSERT_EQ(rc, 0) << log;
    std::istringstream runs(read_file(out / "fracture_runs.csv"));
    std::string header, first;
    std::getline(runs, header);
    std::getline(runs, first);
    EXPECT_EQ(first.rfind("1,bar,", 0), 0u) << first;
    // fragments.csv of that run: index, volume, bbox min xyz, bbox max xyz, centroid xyz, voxels.
    std::vector<std::vector<double>> frags;
    for (const auto& dir : fs::directory_iterator(out / "fracture_runs"))
        if (dir.path().filename().string().find("_bar") != std::string::npos &&
            dir.path().filename().string().rfind("1_0_", 0) == 0) {
            std::istringstream csv(read_file(dir.path() / "fragments.csv"));
            std::string line;
            std::getline(csv, line);
            while (std::getline(csv, line)) {
                std::vector<double> v;
                std::stringstream ls(line);
                for (std::string col; std::getline(ls, col, ',');) v.push_back(std::stod(col));
                frags.push_back(v);
            }
        }
    ASSERT_GE(frags.size(), 3u) << "the bar did not break in its first run";
    std::sort(frags.begin(), frags.end(), [](const auto& a, const auto& b) { return a[1] > b[1]; });
    const double support = 0.65, half_width = 0.05, end = 0.75;
    const auto& left = frags[0][8] < 0 ? frags[0] : frags[1];
    const auto& right = frags[0][8] < 0 ? frags[1] : frags[0];
    EXPECT_NEAR(left[2], -end, 0.01);                      // holds the left end ...
    EXPECT_LT(left[5], -(support - half_width) + 0.5);     // ... ends between the supports ...
    EXPECT_GT(left[5], -(support - half_width));           // ... past its support's inner edge
    EXPECT_NEAR(right[5], end, 0.01);
    EXPECT_GT(right[2], (support - half_width) - 0.5);
    EXPECT_LT(right[2], support - half_width);
    for (std::size_t k = 2; k < frags.size(); ++k) EXPECT_LT(std::abs(frags[k][8]), support - half_width) << k;
}

namespace {

// The artist's box of the surface test: 0.15 m, 4 x 4 cells a face, the z faces in material "paint",
// the others in "stone", and texture coordinates affine in the position, so the UV area of any
// piece of it are one affine map of the position.
cf::SurfaceMesh authored_box() {
    cf::BoxSpec spec;
    spec.size = cf::Vec3(0.15, 0.15, 0.15);
    cf::SurfaceMesh m = cf::make_box(spec);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const int face = m.region_of(t);  // x_min, x_max, y_min, y_max, z_min, z_max
        m.region[t] = face >= 4 ? 1 : 0;
        std::array<cf::Vec2, 3> uv;
        for (int k = 0; k < 3; ++k) {
            const cf::Vec3& x = m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
            uv[k] = cf::Vec2(3 * x.x() + 0.5 * x.y() + 0.25 * x.z() + 0.1, -x.x() + 2 * x.y() + 1.5 * x.z() + 0.2);
        }
        m.corner_uv.push_back(uv);
    }
    m.region_names = {"stone", "paint"};
    return m;
}

// A scene of one breakable body (the box above, dropped from 0.5 m on the ground), written with
// 'fragment_mesh' as given; returns the output directory.
fs::path run_dropped_box(const std::string& fragment_mesh) {
    const fs::path dir = cf::testing::temp_dir("keep-surface-" + fragment_mesh);
    cf::write_mesh_file(dir / "box.obj", authored_box(), cf::MeshFormat::Obj, false);
    const std::string yaml =
        "nodes:\n"
        "  plaster: {type: material.brittle, params: {E: 1.0e10, nu: 0.2, rho: 1500, tensile_strength: 5.0e4, "
        "toughness: 2.0e3, compressive_factor: 10}}\n"
        "  mesh: {type: import.mesh, params: {path: box.obj}}\n"
        "  box:\n"
        "    type: rigid.body\n"
        "    inputs: {mesh: mesh.mesh, material: plaster.material}\n"
        "    params: {breakable: true, r_f: 5.0e-3, r_c: 0.04, bem_triangles: 150, position: [0, 0, 0.5], "
        "rotation: [35, 45, 0], fragment_mesh: " + fragment_mesh + "}\n"
        "  scene: {type: rigid.scene, inputs: {bodies: box.bodies}, params: {time_step: 0.004, frame_rate: 50}}\n"
        "  frames:\n"
        "    type: loop\n"
        "    params: {max_iterations: 20}\n"
        "    inputs: {scene: scene.scene}\n"
        "    body: {step: {type: rigid.frame, inputs: {scene: frames.scene}}}\n"
        "    next: {scene: step.scene}\n"
        "  animation: {type: export.animation, inputs: {scene: frames.final.scene}}\n";
    std::string log;
    const int rc = run_pipeline_in(dir, yaml, log);
    EXPECT_EQ(rc, 0) << log;
    EXPECT_EQ(log.find("level-set mesh"), std::string::npos) << "a fragment fell back:\n" << log;
    return dir / "out";
}

// fracture_runs.csv without its wall-time column.
std::string runs_without_seconds(const fs::path& out) {
    std::istringstream csv(read_file(out / "fracture_runs.csv"));
    std::string runs;
    for (std::string line; std::getline(csv, line);) {
        std::vector<std::string> cols;
        std::stringstream ls(line);
        for (std::string col; std::getline(ls, col, ',');) cols.push_back(col);
        if (cols.size() > 13) cols[13] = "";  // seconds
        for (const auto& col : cols) runs += col + ",";
        runs += "\n";
    }
    return runs;
}

// A primitive's triangles as (positions, optional uvs) per corner.
struct PrimitiveTriangles {
    std::vector<std::array<cf::Vec3, 3>> xyz;
    std::vector<std::array<cf::Vec2, 3>> uv;  // empty without TEXCOORD_0
};

template <class T>
std::vector<T> accessor_values(const tinygltf::Model& m, int index) {
    const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
    const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const unsigned char* p = m.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
    const std::size_t n = a.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
    std::vector<T> out(n);
    std::memcpy(out.data(), p, n * sizeof(T));
    return out;
}

PrimitiveTriangles primitive_triangles(const tinygltf::Model& m, const tinygltf::Primitive& p) {
    PrimitiveTriangles out;
    const auto xyz = accessor_values<float>(m, p.attributes.at("POSITION"));
    const auto idx = accessor_values<std::uint32_t>(m, p.indices);
    std::vector<float> uv;
    if (p.attributes.count("TEXCOORD_0")) uv = accessor_values<float>(m, p.attributes.at("TEXCOORD_0"));
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        std::array<cf::Vec3, 3> x;
        std::array<cf::Vec2, 3> w;
        for (int k = 0; k < 3; ++k) {
            const std::size_t v = idx[t + static_cast<std::size_t>(k)];
            x[k] = cf::Vec3(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
            if (!uv.empty()) w[k] = cf::Vec2(uv[2 * v], uv[2 * v + 1]);
        }
        out.xyz.push_back(x);
        if (!uv.empty()) out.uv.push_back(w);
    }
    return out;
}

}  // namespace

// Issue 14 in a scene: a breakable body's fragments, in every generation, are drawn with its own
// triangles, clipped where the cracks cut them, with its texture coordinates; the fracture faces are
// the second ("inside") primitive. Independent truth: the authored UVs are one affine map of the
// position, so on every fragment's outer faces uv must be an affine map of the rest position whose
// singular values are the authored map's (a rotation does not change them), which no level-set face
// or box projection satisfies; every fragment is closed and manifold (its two primitives welded by
// position). (Volumes against the level set: SurfaceFragments' tests.) And keeping the surface only changes what is drawn: with
// 'fragment_mesh: levelset' every run and every frame of the motion is the same.
TEST(Scene, FragmentsKeepTheBodysTrianglesAndTextureCoordinates) {
    const fs::path kept = run_dropped_box("surface"), levelset = run_dropped_box("levelset");
    const std::string runs = runs_without_seconds(kept);
    ASSERT_NE(runs.find(",1,\"\","), std::string::npos) << "the box did not break:\n" << runs;
    EXPECT_EQ(runs, runs_without_seconds(levelset));
    int frames = 0;
    for (const auto& f : fs::directory_iterator(kept / "pieces"))
        if (f.path().filename().string().find("rest") == std::string::npos) {
            EXPECT_EQ(read_file(f.path()), read_file(levelset / "pieces" / f.path().filename())) << f.path();
            ++frames;
        }
    EXPECT_GT(frames, 10);

    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (kept / "scene.glb").string())) << err;
    // The authored map uv = A x + c (authored_box), v flipped in glTF: its singular values.
    Eigen::Matrix<double, 2, 3> A;
    A << 3, 0.5, 0.25, -1, 2, 1.5;
    const Eigen::Vector2d sigma = Eigen::JacobiSVD<Eigen::Matrix<double, 2, 3>>(A).singularValues();
    int fragments = 0, generations = 0, spanning = 0;
    for (const tinygltf::Node& node : model.nodes) {
        if (node.mesh < 0 || node.name.find('.') == std::string::npos) continue;  // the root, the box itself
        const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(node.mesh)];
        ++fragments;
        generations = std::max(generations, int(std::count(node.name.begin(), node.name.end(), '.')));
        // Outer faces, then fracture faces; a piece from deep inside the body has only the latter.
        ASSERT_GE(mesh.primitives.size(), 1u);
        ASSERT_LE(mesh.primitives.size(), 2u);
        const bool has_outer = mesh.primitives.size() == 2;
        const PrimitiveTriangles outer = has_outer ? primitive_triangles(model, mesh.primitives[0]) : PrimitiveTriangles{};
        const PrimitiveTriangles inside = primitive_triangles(model, mesh.primitives.back());
        EXPECT_EQ(model.materials[static_cast<std::size_t>(mesh.primitives.back().material)].name, node.name + ".inside");
        ASSERT_EQ(outer.uv.size(), outer.xyz.size()) << node.name << ": no TEXCOORD_0 on its outer faces";
        ASSERT_EQ(inside.uv.size(), inside.xyz.size()) << node.name << ": no TEXCOORD_0 on its fracture faces";
        // uv = M x + c by least squares over the outer corners (float32 data: residual <= 1e-5).
        // Where they span the space (not all on one face of the box), M's singular values are the
        // authored map's; on one plane only its restriction to the plane is determined.
        const auto corners = static_cast<Eigen::Index>(3 * outer.xyz.size());
        Eigen::MatrixXd X(corners, 4), W(corners, 2);
        for (std::size_t t = 0; t < outer.xyz.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const auto row = static_cast<Eigen::Index>(3 * t + static_cast<std::size_t>(k));
                X.row(row) << outer.xyz[t][k].transpose(), 1;
                W.row(row) = outer.uv[t][k].transpose();
            }
        if (corners > 0) {
            const Eigen::MatrixXd fit = X.colPivHouseholderQr().solve(W);  // 4 x 2
            EXPECT_LT((X * fit - W).cwiseAbs().maxCoeff(), 1e-5) << node.name << ": outer uvs are not the authored map";
            const Eigen::MatrixXd centred = X.leftCols(3).rowwise() - X.leftCols(3).colwise().mean();
            if (Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues()[2] > 1e-3 * std::sqrt(double(corners))) {
                const Eigen::Matrix<double, 2, 3> M = fit.topRows(3).transpose();
                const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix<double, 2, 3>>(M).singularValues();
                EXPECT_NEAR(s[0], sigma[0], 1e-3 * sigma[0]) << node.name;
                EXPECT_NEAR(s[1], sigma[1], 1e-3 * sigma[1]) << node.name;
                ++spanning;
            }
        }
        // Closed and manifold: welded by float position (slivers that collapse in float32 dropped).
        std::map<std::array<float, 3>, int> weld;
        cf::SurfaceMesh welded;
        double volume = 0, inside_area = 0;  // [m^3, m^2]
        for (const PrimitiveTriangles* part : {&outer, &inside})
            for (const auto& x : part->xyz) {
                volume += x[0].dot(x[1].cross(x[2])) / 6;
                if (part == &inside) inside_area += 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
                cf::Tri tri;
                for (int c = 0; c < 3; ++c) {
                    const std::array<float, 3> key{float(x[c].x()), float(x[c].y()), float(x[c].z())};
                    auto [it, added] = weld.emplace(key, static_cast<int>(welded.vertices.size()));
                    if (added) welded.vertices.push_back(x[c]);
                    tri[c] = it->second;
                }
                if (tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0]) welded.triangles.push_back(tri);
            }
        const cf::MeshTopologyReport topo = cf::check_topology(welded, 0.0);
        EXPECT_TRUE(topo.closed() && topo.manifold() && topo.consistently_oriented()) << node.name << ": " << topo.describe();
        EXPECT_GT(volume, 0) << node.name;
        EXPECT_GT(inside_area, 0) << node.name;
    }
    EXPECT_GE(fragments, 4);
    EXPECT_GE(spanning, 2) << "too few fragments with outer faces on several sides of the box";
    EXPECT_GE(generations, 2) << "no fragment broke again";
}

// The shot bunny (thesis fig. 41) shatters. A guard against a silent regression: after the BEM
// remesh of 2026-12-02 its BEM surface stood off the bunny by 5 r_f (median; r_c / 4 = 2.5 r_f at
// --fast), every element's hexagon was skipped as outside the object, and the ball left it in one
// piece for two days while the docs still said 69 runs. Now initiation places hexagons below the
// object's surface within the body's measured standoff (report: rigid.body bem_standoff_m).
TEST(Scene, TheShotBunnyBreaks) {
    const fs::path out = cf::testing::temp_dir("bunny-shooting");
    std::string log;
    const int rc = run_shipped_fast("bunny_shooting.yaml", out, log);
    ASSERT_EQ(rc, 0) << log;
    const std::string report = read_file(out / "report.json");
    auto number_after = [&](const std::string& key, const std::string& within) {
        const std::size_t from = report.find(within);
        const std::size_t at = from == std::string::npos ? from : report.find("\"" + key + "\":", from);
        return at == std::string::npos ? -1.0 : std::stod(report.substr(at + key.size() + 3));
    };
    const double r_c = 0.01;  // the pipeline's fast value
    EXPECT_GT(number_after("bem_standoff_m", "\"name\":\"bunny\""), 0.25 * r_c) << "the case no longer tests a standoff beyond r_c / 4";
    EXPECT_GE(number_after("breaks", "\"scene\":{"), 3) << report.substr(report.find("\"scene\":{"), 400);
}

// A breakable body whose mesh the surface mesher cannot clip (two overlapping boxes in one mesh:
// closed, outward, intersecting itself) still runs: a warning names the body and the way to silence
// it, and its fragments would be drawn with their level-set meshes.
TEST(SceneInputs, AnUnclippableMeshFallsBackToLevelSetMeshesWithAWarning) {
    const fs::path dir = cf::testing::temp_dir("scene-overlapping-boxes");
    cf::BoxSpec a, b;
    a.size = b.size = cf::Vec3(0.1, 0.1, 0.1);
    b.centre = cf::Vec3(0.07, -0.07, 0.0);  // overlapping a along one edge, neither inside the other
    cf::SurfaceMesh m = cf::make_box(a);
    const cf::SurfaceMesh second = cf::make_box(b);
    const int base = static_cast<int>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), second.vertices.begin(), second.vertices.end());
    for (cf::Tri t : second.triangles) {
        for (int& v : t) v += base;
        m.triangles.push_back(t);
        m.region.push_back(0);
    }
    cf::write_mesh_file(dir / "overlap.obj", m, cf::MeshFormat::Obj, false);
    const std::string yaml =
        "nodes:\n"
        "  weak: {type: material.brittle, params: {E: 1.0e10, nu: 0.2, rho: 1500, tensile_strength: 5.0e4, "
        "toughness: 2.0e3, compressive_factor: 10}}\n"
        "  mesh: {type: import.mesh, params: {path: overlap.obj}}\n"
        "  lump: {type: rigid.body, inputs: {mesh: mesh.mesh, material: weak.material}, params: {breakable: true, "
        "r_f: 5.0e-3, bem_triangles: 150, position: [0, 0, 0.2]}}\n"
        "  scene: {type: rigid.scene, inputs: {bodies: lump.bodies}}\n";
    std::string log;
    const int rc = run_pipeline_in(dir, yaml, log);
    EXPECT_EQ(rc, 0) << log;
    EXPECT_NE(log.find("warning: rigid.body 'lump'"), std::string::npos) << log;
    EXPECT_NE(log.find("fragment_mesh"), std::string::npos) << log;
    EXPECT_NE(log.find("intersects itself"), std::string::npos) << log;
}
