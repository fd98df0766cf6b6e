// Issue 16: nothing lost and no silent garbage when the disk fills, the user interrupts, or the
// input is extreme. The crackflow binary end to end, in a child process with limits set.
#include "nodes/levelset/level_set.hpp"
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <iostream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace {

struct Child {
    int status = -1;
    std::string output;  // stdout and stderr
    int code() const { return WIFEXITED(status) ? WEXITSTATUS(status) : -1; }
    bool signalled() const { return WIFSIGNALED(status); }
};

std::string src(const std::string& rel) { return std::string(CRACKFLOW_SOURCE_DIR) + "/" + rel; }

// Runs crackflow with `args`; a file-size limit of `fsize` bytes (0: none) as `ulimit -f` sets it,
// with SIGXFSZ ignored so that a write past it fails with EFBIG (as on a full disk) instead of
// killing the process.
// Starts crackflow with `args`, its stdout and stderr into a pipe; returns the child's pid (-1 if
// it could not start) and the read end in `out`. `in_child` runs in the child before the exec.
pid_t spawn_crackflow(const std::vector<std::string>& args, int& out, const std::function<void()>& in_child = {}) {
    int fds[2];
    if (pipe(fds) != 0) return -1;
    const pid_t pid = fork();
    if (pid == 0) {
        dup2(fds[1], 1);
        dup2(fds[1], 2);
        close(fds[0]);
        if (in_child) in_child();
        std::vector<char*> argv{const_cast<char*>(CRACKFLOW_EXE)};
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(CRACKFLOW_EXE, argv.data());
        _exit(99);
    }
    close(fds[1]);
    out = fds[0];
    return pid;
}

Child run_limited(const std::vector<std::string>& args, rlim_t fsize = 0) {
    int fds[2];
    const pid_t pid = spawn_crackflow(args, fds[0], [fsize] {
        if (fsize > 0) {
            rlimit lim{fsize, fsize};
            setrlimit(RLIMIT_FSIZE, &lim);
        }
        std::signal(SIGXFSZ, SIG_IGN);
    });
    if (pid < 0) return {};
    Child c;
    char buf[4096];
    ssize_t n;
    while ((n = read(fds[0], buf, sizeof buf)) > 0) c.output.append(buf, std::size_t(n));
    close(fds[0]);
    waitpid(pid, &c.status, 0);
    return c;
}

std::map<std::string, std::uintmax_t> files_in(const std::filesystem::path& dir) {
    std::map<std::string, std::uintmax_t> out;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
        if (e.is_regular_file()) out[std::filesystem::relative(e.path(), dir).string()] = e.file_size();
    return out;
}

// Grid names and active voxel counts as Debian's python3-openvdb (pyopenvdb) reads the file: a
// reader that is not ours.
std::string pyopenvdb_listing(const std::filesystem::path& file) {
    const std::string cmd = "/usr/bin/python3 -c \"import sys, pyopenvdb as vdb\n"
                            "grids, meta = vdb.readAll(sys.argv[1])\n"
                            "print(' '.join('%s:%d' % (g.name, g.activeVoxelCount()) for g in grids))\" " +
                            file.string() + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    std::string out;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
    pclose(p);
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
}

}  // namespace

// .vdb files are written through the checked atomic writer: under a file-size limit the run fails
// with exit 1 naming the file and the OS error, and no truncated file is left under the final name
// (object.vdb and fragments.vdb were left at 8000 bytes, exit 0). Whatever is written reads back
// with OpenVDB's io::File and with pyopenvdb.
TEST(Reliability, VdbWritesUnderAFileSizeLimitFailCleanly) {
    const auto base = cf::testing::temp_dir("reliability-vdb");
    const std::string pipeline = src("pipelines/cut_box.yaml");

    // Unlimited: both VDB files are complete and readable by two independent readers.
    const Child full = run_limited({"run", pipeline, "--fast", "--out", (base / "full").string()});
    ASSERT_EQ(full.code(), 0) << full.output;
    const auto sizes = files_in(base / "full");
    ASSERT_TRUE(sizes.count("object.vdb") && sizes.count("fragments.vdb")) << full.output;
    const auto object = cf::read_vdb(base / "full" / "object.vdb");
    ASSERT_EQ(object.size(), 1u);
    EXPECT_EQ(object[0].first, "object");
    const auto fragments = cf::read_vdb(base / "full" / "fragments.vdb");
    EXPECT_GE(fragments.size(), 2u);
    const std::string py_object = pyopenvdb_listing(base / "full" / "object.vdb");
    EXPECT_EQ(py_object.rfind("object:", 0), 0u) << py_object;
    EXPECT_GT(std::stol(py_object.substr(7)), 1000) << py_object;
    const std::string py_fragments = pyopenvdb_listing(base / "full" / "fragments.vdb");
    EXPECT_EQ(std::count(py_fragments.begin(), py_fragments.end(), ':'), long(fragments.size())) << py_fragments;

    auto expect_clean_failure = [&](const std::string& tag, rlim_t limit, const std::string& victim) {
        const auto dir = base / tag;
        std::filesystem::create_directories(dir);
        const Child c = run_limited({"run", pipeline, "--fast", "--threads", "2", "--out", dir.string()}, limit);
        EXPECT_FALSE(c.signalled()) << c.output;
        EXPECT_EQ(c.code(), 1) << c.output;
        EXPECT_NE(c.output.find(victim), std::string::npos) << c.output;
        EXPECT_NE(c.output.find("File too large"), std::string::npos) << c.output;
        const auto written = files_in(dir);
        EXPECT_EQ(written.count(victim), 0u) << tag << ": a file under the final name";
        for (const auto& [name, bytes] : written) {
            EXPECT_NE(name.rfind('.', 0), 0u) << tag << ": temporary left behind: " << name;
            // Every file that is there is complete: as large as in the unlimited run.
            if (sizes.count(name) && name != "report.json") {
                EXPECT_EQ(bytes, sizes.at(name)) << tag << ": " << name;
            }
        }
    };
    // The object grid is the first file written: a limit below its size fails it.
    expect_clean_failure("object", sizes.at("object.vdb") / 2, "object.vdb");
    // A limit that every other output fits in fails only the fragment grids.
    std::uintmax_t others = 0;
    for (const auto& [name, bytes] : sizes)
        if (name != "fragments.vdb" && name != "report.json") others = std::max(others, bytes);
    ASSERT_LT(others, sizes.at("fragments.vdb")) << "fragments.vdb is no longer the largest output; pick another limit";
    expect_clean_failure("fragments", (others + sizes.at("fragments.vdb")) / 2, "fragments.vdb");
}

// Output paths: an absolute path is refused by validate and run unless --allow-absolute-paths is
// given; two outputs naming the same file, or report.json, are caught by validate.
TEST(Reliability, OutputPathsAreCheckedBeforeTheRun) {
    const auto dir = cf::testing::temp_dir("reliability-paths");
    const std::string demo = src("pipelines/loop_demo.yaml");
    const std::string absolute = (dir / "elsewhere" / "final.txt").string();

    const Child v = run_limited({"validate", demo, "--set", "write_final.path=" + absolute});
    EXPECT_EQ(v.code(), 2) << v.output;
    EXPECT_NE(v.output.find("absolute"), std::string::npos) << v.output;
    EXPECT_NE(v.output.find("--allow-absolute-paths"), std::string::npos) << v.output;
    const Child r = run_limited({"run", demo, "--fast", "--set", "write_final.path=" + absolute, "--out", (dir / "a").string()});
    EXPECT_EQ(r.code(), 2) << r.output;
    EXPECT_FALSE(std::filesystem::exists(absolute));
    const Child ok = run_limited({"run", demo, "--fast", "--allow-absolute-paths", "--set", "write_final.path=" + absolute,
                                  "--out", (dir / "b").string()});
    EXPECT_EQ(ok.code(), 0) << ok.output;
    EXPECT_TRUE(std::filesystem::exists(absolute));

    const auto file = dir / "collide.yaml";
    std::ofstream(file) << "nodes:\n"
                           "  a: {type: core.real, params: {value: 1}}\n"
                           "  w1: {type: core.write_real, inputs: {value: a.value}, params: {path: out/value.txt}}\n"
                           "  w2: {type: core.write_real, inputs: {value: a.value}, params: {path: ./out//value.txt}}\n"
                           "  w3: {type: core.write_real, inputs: {value: a.value}, params: {path: sub/../report.json}}\n";
    const Child c = run_limited({"validate", file.string()});
    EXPECT_EQ(c.code(), 2) << c.output;
    EXPECT_NE(c.output.find("'w2.path' names the same file as 'w1.path'"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("'w3.path' names report.json"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("collide.yaml:4"), std::string::npos) << "the line of the node: " << c.output;
}

// `validate /dev/zero` stops after 16 MiB instead of reading 4.2 GB; a loop of many short
// iterations neither grows per iteration in the report's bookkeeping nor floods the log.
TEST(Reliability, InputSizesAndLongLoopsAreBounded) {
    const Child z = run_limited({"validate", "/dev/zero"});
    EXPECT_EQ(z.code(), 2) << z.output;
    EXPECT_NE(z.output.find("larger than 16 MiB"), std::string::npos) << z.output;

    const auto dir = cf::testing::temp_dir("reliability-loop");
    const Child l = run_limited({"run", src("pipelines/loop_demo.yaml"), "--fast", "--set", "grow.max_iterations=12000",
                                 "--set", "step.value=0", "--set", "write_step.path=steps/length.txt", "--out", dir.string()});
    ASSERT_EQ(l.code(), 0) << l.output.substr(0, 2000);
    // 12000 iterations of 4 nodes: without the rate limit 96000 progress lines.
    const auto lines = std::count(l.output.begin(), l.output.end(), '\n');
    EXPECT_LT(lines, 2000) << l.output.substr(0, 2000);
    EXPECT_NE(l.output.find("loop lines not shown"), std::string::npos);
    YAML::Node report = YAML::LoadFile((dir / "report.json").string());
    for (const auto& n : report["nodes"]) {
        if (n["name"].as<std::string>() != "advance") continue;
        EXPECT_EQ(n["runs"].as<int>(), 12000);
        EXPECT_LE(n["iteration_counts"].size(), 10000u) << "per-iteration records are capped";
    }
}

namespace {

struct Interrupted {
    int status = -1;
    double seconds = -1;  // from the signal to the exit
    std::string output;
};

// Starts crackflow, waits until its log says `marker` (a node started) and then `delay` seconds,
// sends `sig` and measures how long the process takes to exit.
Interrupted interrupt_when(const std::vector<std::string>& args, const std::string& marker, double delay, int sig) {
    int fds[2];
    const pid_t pid = spawn_crackflow(args, fds[0]);
    if (pid < 0) return {};
    Interrupted r;
    char buf[4096];
    ssize_t n;
    while (r.output.find(marker) == std::string::npos && (n = read(fds[0], buf, sizeof buf)) > 0)
        r.output.append(buf, std::size_t(n));
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    const auto t0 = std::chrono::steady_clock::now();
    kill(pid, sig);
    waitpid(pid, &r.status, 0);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    while ((n = read(fds[0], buf, sizeof buf)) > 0) r.output.append(buf, std::size_t(n));
    close(fds[0]);
    return r;
}

}  // namespace

// Ctrl-C takes effect inside long nodes, not only between them (it was ignored for over 120 s in a
// propagate step with many sub-steps, and took 11 s in a 15 s assembly): the run exits with 130
// and its report within 0.5 s of the signal (plus a margin for writing the report on a busy machine).
TEST(Reliability, CtrlCStopsLongNodesWithinHalfASecond) {
    struct Case {
        std::string what, marker;
        std::vector<std::string> sets;
        std::string pipeline = "pipelines/edge_crack_mode1.yaml";
    };
    const std::vector<Case> cases = {
        {"propagate with a million sub-steps", "start  fracture/propagate#0", {"fracture/propagate.substeps=1000000"}},
        {"assembly of 1200 triangles", "start  fracture/assemble0", {"cube.subdivisions=10"}},
        {"level set of a fine grid", "start  object", {"object.voxel_size=1.5e-4"}},
        // An imported mesh goes through OpenVDB's mesh-to-volume, which asks its interrupter only
        // between phases (up to a second apart here); the triangle reads poll in between.
        {"level set of the armadillo on a fine grid", "start  body/object", {"body.r_f=1.2e-4"},
         "pipelines/armadillo_tearing.yaml"},
    };
    for (const Case& c : cases) {
        const auto dir = cf::testing::temp_dir("reliability-ctrlc");
        std::vector<std::string> args{"run", src(c.pipeline), "--fast", "--threads", "2", "--out", dir.string()};
        for (const auto& s : c.sets) args.insert(args.end(), {"--set", s});
        const Interrupted r = interrupt_when(args, c.marker, 1.0, SIGINT);
        ASSERT_TRUE(WIFEXITED(r.status)) << c.what << "\n" << r.output;
        EXPECT_EQ(WEXITSTATUS(r.status), 130) << c.what << "\n" << r.output;
        std::printf("%s: exit %.3f s after SIGINT\n", c.what.c_str(), r.seconds);
        EXPECT_LT(r.seconds, 0.5 + 0.5) << c.what;
        YAML::Node report = YAML::LoadFile((dir / "report.json").string());
        EXPECT_EQ(report["status"].as<std::string>(), "cancelled") << c.what;
    }
}

// Interior evaluation (export.probes) polls per block of points: a 1000 x 1000 slice through the
// pressure_sphere ball (10^6 points against 320 elements, tens of seconds) stops within the bound.
TEST(Reliability, CtrlCStopsInteriorEvaluationWithinHalfASecond) {
    const auto dir = cf::testing::temp_dir("reliability-ctrlc-probes");
    const std::vector<std::string> args{"run", src("pipelines/pressure_sphere.yaml"), "--threads", "2", "--out", dir.string(),
                                        "--set", "slice.slice_u_points=1000", "--set", "slice.slice_v_points=1000"};
    const Interrupted r = interrupt_when(args, "start  slice", 1.0, SIGINT);
    ASSERT_TRUE(WIFEXITED(r.status)) << r.output;
    EXPECT_EQ(WEXITSTATUS(r.status), 130) << r.output;
    std::printf("slice of 10^6 probe points: exit %.3f s after SIGINT\n", r.seconds);
    EXPECT_LT(r.seconds, 0.5 + 0.5);
    EXPECT_EQ(r.output.find("done   slice"), std::string::npos) << r.output;
    YAML::Node report = YAML::LoadFile((dir / "report.json").string());
    EXPECT_EQ(report["status"].as<std::string>(), "cancelled");
}

// Memory: the loop's assembly honours its own memory_budget (it used the first assembly's when
// 'previous' was connected); a budget above the memory the process may use is refused; a remesh
// whose dense mesh would not fit is refused naming the voxel size, instead of a bare bad_alloc.
TEST(Reliability, MemoryIsEstimatedBeforeItIsAllocated) {
    const auto dir = cf::testing::temp_dir("reliability-memory");
    const std::string mode1 = src("pipelines/edge_crack_mode1.yaml");
    const Child loop = run_limited({"run", mode1, "--fast", "--set", "fracture/assemble.memory_budget=0.001", "--out", (dir / "a").string()});
    EXPECT_EQ(loop.code(), 1) << loop.output;
    EXPECT_NE(loop.output.find("node 'fracture/assemble'"), std::string::npos) << loop.output;
    EXPECT_NE(loop.output.find("above the memory budget of 0.001 GB"), std::string::npos) << loop.output;

    const Child huge = run_limited({"run", mode1, "--fast", "--set", "fracture.memory_budget=1e6", "--out", (dir / "b").string()});
    EXPECT_EQ(huge.code(), 1) << huge.output;
    EXPECT_NE(huge.output.find("'memory_budget' is 1e+06 GB, more than the"), std::string::npos) << huge.output;

#ifdef CRACKFLOW_SANITIZED_BUILD
    std::cout << "[ sanitizer build ] the part under a 1 GB address-space cap runs in the Release build only\n";
    return;
#endif
    // Under a 1 GB address-space cap (ulimit -v), a 2 mm level set of the 1 x 0.6 x 0.4 m box would
    // dual-contour (adaptivity 0) to about a million triangles, about 0.5 GB measured, 1 GB estimated.
    const std::string cut_box = src("pipelines/cut_box.yaml");
    const pid_t pid = fork();
    if (pid == 0) {
        rlimit lim{rlim_t(1) << 30, rlim_t(1) << 30};
        setrlimit(RLIMIT_AS, &lim);
        const std::string out = (dir / "c").string();
        const std::string log = (dir / "c.log").string();
        std::freopen(log.c_str(), "w", stderr);
        execl(CRACKFLOW_EXE, CRACKFLOW_EXE, "run", cut_box.c_str(), "--set", "object.voxel_size=0.002", "--set",
              "object.write_vdb=false", "--set", "bem_mesh.adaptivity=0", "--threads", "2", "--out", out.c_str(), static_cast<char*>(nullptr));
        _exit(99);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    std::ifstream in(dir / "c.log");
    const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_TRUE(WIFEXITED(status)) << log;
    EXPECT_EQ(WEXITSTATUS(status), 1) << log;
    EXPECT_NE(log.find("node 'bem_mesh'"), std::string::npos) << log;
    EXPECT_NE(log.find("remeshing this level set"), std::string::npos) << log;
    EXPECT_NE(log.find("voxel_size"), std::string::npos) << log;
    EXPECT_EQ(log.find("bad_alloc"), std::string::npos) << log;
}

namespace {

// A box cut in two by a planar crack, its fragments, and their preview only: the level set, the
// fragment search and the preview renderer are the only long nodes, each sized by a --set.
std::filesystem::path cut_box_pipeline(const std::filesystem::path& dir) {
    const auto file = dir / "cut.yaml";
    std::ofstream(file) << "nodes:\n"
                           "  box: {type: shape.box, params: {size: [1, 0.6, 0.4]}}\n"
                           "  object: {type: levelset.from_mesh, inputs: {mesh: box.mesh}, params: {voxel_size: 0.02}}\n"
                           "  crack:\n"
                           "    type: levelset.crack_planar\n"
                           "    inputs: {object: object.level_set}\n"
                           "    params: {centre: [0.1, 0, 0], normal: [1, 0.3, 0.2], radius: 0.8}\n"
                           "  fragments: {type: segment.fragments, inputs: {object: object.level_set, cracks: crack.cracks}}\n"
                           "  export:\n"
                           "    type: export.fragments\n"
                           "    inputs: {fragments: fragments.fragments}\n"
                           "    params: {meshes: false, vdb: false, width: 64, height: 64}\n";
    return file;
}

}  // namespace

// Ctrl-C inside the fragment search (component labelling and the fragment grids) and inside the
// preview renderer (ray tracing polled per image row), which had no poll: exit 130 with a report
// within 0.5 s of the signal (plus the same margin as above).
TEST(Reliability, CtrlCStopsSegmentationAndPreviewWithinHalfASecond) {
    struct Case {
        std::string what, marker;
        std::vector<std::string> sets;
    };
    // On the shared 2-core machine the fragment search on 1.5 mm voxels took 0.8 s quiet and 2.8 s
    // loaded (after 1.5-6 s of level sets) until the search by pieces (issue 17) made it ~3x faster,
    // so that it could end before the signal: 1 mm voxels now. The 3072 x 3072 preview took 3.8 s
    // loaded but 0.44 s on the idle machine, where the signal 0.3 s in fell after its last row,
    // in the PNG encoding, and the node finished: 6144 x 6144 now (1.8 s idle). The signal comes
    // 0.3 s into each.
    const std::vector<Case> cases = {
        {"fragment search on 1 mm voxels", "start  fragments", {"object.voxel_size=0.001"}},
        {"preview of 6144 x 6144 pixels", "start  export", {"export.width=6144", "export.height=6144"}},
        // OpenVDB's volumeToMesh of a fragment has no poll (about 1 s here): the run is abandoned
        // 0.3 s after the signal (runtime/cancel_deadline.hpp) with its report and no temporaries.
        {"meshing fragments on 1 mm voxels", "start  export", {"object.voxel_size=0.001", "export.meshes=true"}},
    };
    for (const Case& c : cases) {
        const auto dir = cf::testing::temp_dir("reliability-ctrlc-segment");
        std::vector<std::string> args{"run", cut_box_pipeline(dir).string(), "--threads", "2", "--out", (dir / "out").string()};
        for (const auto& s : c.sets) args.insert(args.end(), {"--set", s});
        const Interrupted r = interrupt_when(args, c.marker, 0.3, SIGINT);
        ASSERT_TRUE(WIFEXITED(r.status)) << c.what << "\n" << r.output;
        EXPECT_EQ(WEXITSTATUS(r.status), 130) << c.what << "\n" << r.output;
        std::printf("%s: exit %.3f s after SIGINT\n", c.what.c_str(), r.seconds);
        EXPECT_LT(r.seconds, 0.5 + 0.5) << c.what;
        // Cancelled inside the node: it never finished.
        EXPECT_EQ(r.output.find("done   " + c.marker.substr(7)), std::string::npos) << c.what << "\n" << r.output;
        YAML::Node report = YAML::LoadFile((dir / "out" / "report.json").string());
        EXPECT_EQ(report["status"].as<std::string>(), "cancelled") << c.what;
        for (const auto& [name, size] : files_in(dir / "out"))
            EXPECT_EQ(name.find(".tmp"), std::string::npos) << c.what << ": " << name;
    }
}

// Files nodes write under names of their own (object.vdb, fragments.csv, <prefix>s.vdb ...) are
// checked by validate against the names parameters give and against each other, at FILE:LINE.
TEST(Reliability, FixedOutputNamesAreCheckedByValidate) {
    const auto dir = cf::testing::temp_dir("reliability-fixed-names");
    const std::string head = "nodes:\n"
                             "  box: {type: shape.box}\n"
                             "  object: {type: levelset.from_mesh, inputs: {mesh: box.mesh}, params: {voxel_size: 0.05, write_vdb: true}}\n"
                             "  fragments: {type: segment.fragments, inputs: {object: object.level_set}}\n"
                             "  export: {type: export.fragments, inputs: {fragments: fragments.fragments}}\n"
                             "  a: {type: core.real, params: {value: 1}}\n";
    auto validate = [&](const std::string& name, const std::string& rest, const std::vector<std::string>& extra = {}) {
        const auto file = dir / name;
        std::ofstream(file) << head << rest;
        std::vector<std::string> args{"validate", file.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_limited(args);
    };
    // The pipeline alone is valid: a node's own fixed names do not collide with each other.
    const Child ok = validate("ok.yaml", "");
    EXPECT_EQ(ok.code(), 0) << ok.output;

    const Child c = validate("collide.yaml",
                             "  w1: {type: core.write_real, inputs: {value: a.value}, params: {path: object.vdb}}\n"
                             "  w2: {type: core.write_real, inputs: {value: a.value}, params: {path: ./fragment_007.obj}}\n"
                             "  w3: {type: core.write_real, inputs: {value: a.value}, params: {path: fragments.json}}\n"
                             "  again: {type: export.fragments, inputs: {fragments: fragments.fragments}, params: {meshes: false}}\n");
    EXPECT_EQ(c.code(), 2) << c.output;
    EXPECT_NE(c.output.find("collide.yaml:7"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("parameter 'w1.path' ('object.vdb') names a file that node 'object' (levelset.from_mesh) writes "
                            "under the fixed name 'object.vdb'"),
              std::string::npos)
        << c.output;
    EXPECT_NE(c.output.find("set 'object.write_vdb' to false"), std::string::npos) << c.output;
    // '*' of fragment_*.obj stands for the fragment index.
    EXPECT_NE(c.output.find("collide.yaml:8"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("'w2.path' ('fragment_007.obj') names a file that node 'export' (export.fragments) writes under "
                            "the fixed name 'fragment_*.obj'"),
              std::string::npos)
        << c.output;
    EXPECT_NE(c.output.find("'w3.path' ('fragments.json') names a file that node 'fragments' (segment.fragments)"),
              std::string::npos)
        << c.output;
    // Two nodes with the same fixed name: the later one is named, with its line.
    EXPECT_NE(c.output.find("collide.yaml:10"), std::string::npos) << c.output;
    EXPECT_NE(c.output.find("node 'again' (export.fragments) writes 'fragments.vdb', a file that node 'export' "
                            "(export.fragments) writes as 'fragments.vdb'"),
              std::string::npos)
        << c.output;

    // What the parameters turn off or rename is not written, so it does not collide.
    const Child off = validate("off.yaml",
                               "  w1: {type: core.write_real, inputs: {value: a.value}, params: {path: object.vdb}}\n"
                               "  w2: {type: core.write_real, inputs: {value: a.value}, params: {path: fragment_x.obj}}\n"
                               "  again: {type: export.fragments, inputs: {fragments: fragments.fragments}, params: {prefix: piece}}\n",
                               {"--set", "object.write_vdb=false"});
    EXPECT_EQ(off.code(), 0) << off.output;
}

// Memory of the solve and of a mesh import is estimated before it is allocated: the surface
// factor and the crack Schur complement against solve.sgbem's memory_budget, a mesh file against
// the memory the process may use (a 3 GB file under a 2 GB cap was read whole, then bad_alloc).
TEST(Reliability, SolveAndImportMemoryIsEstimatedFirst) {
    const auto dir = cf::testing::temp_dir("reliability-memory-solve");
    const std::string mode1 = src("pipelines/edge_crack_mode1.yaml");
    // The first solve factorises the surface (about 2 MB for 300 triangles): refused at 10 kB.
    const Child factor = run_limited({"run", mode1, "--fast", "--set", "fracture/solve0.memory_budget=1e-5", "--out", (dir / "a").string()});
    EXPECT_EQ(factor.code(), 1) << factor.output;
    EXPECT_NE(factor.output.find("node 'fracture/solve0'"), std::string::npos) << factor.output;
    EXPECT_NE(factor.output.find("factorising the surface system"), std::string::npos) << factor.output;
    EXPECT_NE(factor.output.find("above the memory budget of 1e-05 GB"), std::string::npos) << factor.output;
    EXPECT_NE(factor.output.find("'memory_budget' of this node"), std::string::npos) << factor.output;
    // The loop's solve reuses that factor; its crack Schur complement is what is refused.
    const Child schur = run_limited({"run", mode1, "--fast", "--set", "fracture/solve.memory_budget=1e-5", "--out", (dir / "b").string()});
    EXPECT_EQ(schur.code(), 1) << schur.output;
    EXPECT_NE(schur.output.find("node 'fracture/solve'"), std::string::npos) << schur.output;
    EXPECT_NE(schur.output.find("crack Schur complement (eq. 4.3)"), std::string::npos) << schur.output;
    EXPECT_NE(schur.output.find("above the memory budget of 1e-05 GB"), std::string::npos) << schur.output;
    EXPECT_EQ(schur.output.find("factorising the surface system"), std::string::npos) << schur.output;
    // A budget above the machine is refused for the solve as for the assembly.
    const Child huge = run_limited({"run", mode1, "--fast", "--set", "fracture/solve0.memory_budget=1e6", "--out", (dir / "c").string()});
    EXPECT_EQ(huge.code(), 1) << huge.output;
    EXPECT_NE(huge.output.find("'memory_budget' is 1e+06 GB, more than the"), std::string::npos) << huge.output;

#ifdef CRACKFLOW_SANITIZED_BUILD
    std::cout << "[ sanitizer build ] the part under a 2 GB address-space cap runs in the Release build only\n";
    return;
#endif
    // A sparse 3 GB binary STL (header and triangle count consistent with its size, no disk used)
    // imported under a 2 GB address-space cap.
    const auto stl = dir / "huge.stl";
    {
        const std::uint64_t triangles = 60'000'000;  // 84 + 50 n bytes = 3.0 GB
        std::ofstream out(stl, std::ios::binary);
        const char header[80] = "binary STL";
        out.write(header, 80);
        const std::uint32_t n = std::uint32_t(triangles);
        out.write(reinterpret_cast<const char*>(&n), 4);
    }
    std::filesystem::resize_file(stl, 84 + 50 * std::uint64_t(60'000'000));
    const auto yaml = dir / "import.yaml";
    std::ofstream(yaml) << "nodes:\n  mesh: {type: import.mesh, params: {path: " << stl.string() << "}}\n";
    int fd = -1;
    const pid_t pid = spawn_crackflow({"run", yaml.string(), "--out", (dir / "d").string()}, fd, [] {
        rlimit lim{rlim_t(2) << 30, rlim_t(2) << 30};
        setrlimit(RLIMIT_AS, &lim);
    });
    ASSERT_GT(pid, 0);
    Child imp;
    char buf[4096];
    ssize_t got;
    while ((got = read(fd, buf, sizeof buf)) > 0) imp.output.append(buf, std::size_t(got));
    close(fd);
    waitpid(pid, &imp.status, 0);
    EXPECT_EQ(imp.code(), 1) << imp.output;
    EXPECT_NE(imp.output.find("node 'mesh'"), std::string::npos) << imp.output;
    EXPECT_NE(imp.output.find("huge.stl: error: importing this 3 GB file needs about"), std::string::npos) << imp.output;
    EXPECT_NE(imp.output.find("more than the 2.15 GB this process may use"), std::string::npos) << imp.output;
    EXPECT_EQ(imp.output.find("bad_alloc"), std::string::npos) << imp.output;
    std::filesystem::remove(stl);
}
