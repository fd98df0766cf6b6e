// `crackflow batch` with the local backend, end to end: child processes are observed from outside
// (through /proc), so the concurrency bound is measured, not taken from the batch's own word.
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string src(const std::string& rel) { return std::string(CRACKFLOW_SOURCE_DIR) + "/" + rel; }

std::string read_text(const fs::path& f) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct Outcome {
    int code = -1;
    std::string output;
};

Outcome run_batch(const std::string& args) {
    Outcome o;
    const std::string cmd = std::string(CRACKFLOW_EXE) + " batch " + args + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return o;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) o.output.append(buf, n);
    const int status = pclose(p);
    o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return o;
}

// Starts `crackflow batch ARGS...` with its output in `log`; returns its pid.
pid_t start_batch(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<std::string> argv = {CRACKFLOW_EXE, "batch"};
    argv.insert(argv.end(), args.begin(), args.end());
    const pid_t pid = fork();
    if (pid == 0) {
        std::freopen(log.c_str(), "w", stderr);
        std::vector<char*> a;
        for (auto& s : argv) a.push_back(s.data());
        a.push_back(nullptr);
        execv(a[0], a.data());
        _exit(99);
    }
    return pid;
}

struct Proc {
    pid_t pid, ppid;
    std::string cmdline;
};
std::vector<Proc> processes() {
    std::vector<Proc> r;
    for (const auto& e : fs::directory_iterator("/proc")) {
        const std::string name = e.path().filename();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        const std::string stat = read_text(e.path() / "stat");
        const auto close = stat.rfind(')');
        if (close == std::string::npos) continue;
        std::istringstream rest(stat.substr(close + 2));
        char state;
        pid_t ppid = 0;
        rest >> state >> ppid;
        if (state == 'Z') continue;
        std::string cmd = read_text(e.path() / "cmdline");
        for (char& c : cmd)
            if (c == '\0') c = ' ';
        r.push_back({std::stoi(name), ppid, cmd});
    }
    return r;
}
std::vector<Proc> children_of(pid_t parent) {
    std::vector<Proc> r;
    for (auto& p : processes())
        if (p.ppid == parent) r.push_back(p);
    return r;
}
// Processes (other than this test) whose command line mentions `text`.
std::vector<Proc> mentioning(const std::string& text) {
    std::vector<Proc> r;
    for (auto& p : processes())
        if (p.pid != getpid() && p.cmdline.find(text) != std::string::npos) r.push_back(p);
    return r;
}

int wait_exit(pid_t pid, double timeout_s) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    int status = 0;
    while (Clock::now() < end) {
        if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    return -1;
}

// loop_demo runs 8 iterations of settle.seconds each.
std::string demo_rows(const std::vector<std::pair<std::string, double>>& rows) {
    std::string m = "id,pipeline,settle.seconds\n";
    for (const auto& [id, s] : rows) m += id + "," + src("pipelines/loop_demo.yaml") + "," + std::to_string(s) + "\n";
    return m;
}

YAML::Node summary_row(const fs::path& out, const std::string& id) {
    const YAML::Node s = YAML::LoadFile((out / "summary.json").string());
    for (const auto& r : s["results"])
        if (r["id"].as<std::string>() == id) return r;
    return YAML::Node();
}

TEST(BatchLocal, AtMostJobsRowsRunAtOnce) {
    const fs::path dir = cf::testing::temp_dir("batch-jobs");
    std::vector<std::pair<std::string, double>> rows;
    for (int i = 0; i < 7; ++i) rows.push_back({"r" + std::to_string(i), 0.1});  // ~0.8 s each
    std::ofstream(dir / "m.csv") << demo_rows(rows);
    const pid_t pid = start_batch({(dir / "m.csv").string(), "--out", (dir / "out").string(), "--jobs", "3"}, dir / "log");
    std::size_t most = 0;
    std::set<pid_t> seen;
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) == 0) {
        const auto c = children_of(pid);
        most = std::max(most, c.size());
        for (const auto& p : c) seen.insert(p.pid);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << read_text(dir / "log");
    EXPECT_EQ(most, 3u) << "the bound is 3 and 7 rows of ~0.8 s keep it full";
    EXPECT_GE(seen.size(), 6u);  // one process per row (a short start-up may escape the 5 ms polling)
    const YAML::Node s = YAML::LoadFile((dir / "out/summary.json").string());
    EXPECT_EQ(s["ok"].as<int>(), 7);
    for (int i = 0; i < 7; ++i)
        EXPECT_EQ(read_text(dir / "out" / ("r" + std::to_string(i)) / "final_length.txt").substr(0, 1), "2");
    EXPECT_NE(read_text(dir / "log").find("7/7 rows done (7 ok, 0 failed), 0 running"), std::string::npos) << read_text(dir / "log");
}

TEST(BatchLocal, AKilledRowIsReportedFailedWithItsLog) {
    const fs::path dir = cf::testing::temp_dir("batch-kill");
    std::ofstream(dir / "m.csv") << demo_rows({{"quick", 0}, {"doomed", 5}, {"quick2", 0}});
    const pid_t pid = start_batch({(dir / "m.csv").string(), "--out", (dir / "out").string(), "--jobs", "3"}, dir / "log");
    pid_t victim = 0;
    for (int i = 0; i < 1000 && !victim; ++i) {
        for (const auto& p : children_of(pid))
            if (p.cmdline.find("/doomed") != std::string::npos) victim = p.pid;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ASSERT_GT(victim, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(victim, SIGKILL);
    EXPECT_EQ(wait_exit(pid, 60), 1) << read_text(dir / "log");
    const YAML::Node r = summary_row(dir / "out", "doomed");
    EXPECT_EQ(r["status"].as<std::string>(), "failed");
    EXPECT_EQ(r["signal"].as<int>(), 9);
    EXPECT_TRUE(r["exit_code"].IsNull());
    const std::string log = read_text(r["log"].as<std::string>());
    EXPECT_NE(log.find("== killed by signal 9"), std::string::npos) << log;
    EXPECT_NE(log.find("crackflow run"), std::string::npos) << log;  // the child's own output is in it
    EXPECT_EQ(summary_row(dir / "out", "quick")["status"].as<std::string>(), "ok");
    EXPECT_EQ(summary_row(dir / "out", "quick2")["status"].as<std::string>(), "ok");
    EXPECT_NE(read_text(dir / "log").find("doomed: failed: the process was killed by signal 9"), std::string::npos)
        << read_text(dir / "log");
}

TEST(BatchLocal, CtrlCStopsEveryChildAndKeepsCompletedRows) {
    const fs::path dir = cf::testing::temp_dir("batch-sigint");
    std::ofstream(dir / "m.csv") << demo_rows({{"done1", 0}, {"done2", 0}, {"long1", 5}, {"long2", 5}, {"never", 0}});
    const fs::path out = dir / "out";
    const pid_t pid = start_batch({(dir / "m.csv").string(), "--out", out.string(), "--jobs", "2"}, dir / "log");
    // Wait until both short rows are complete and both long ones run.
    bool ready = false;
    for (int i = 0; i < 3000 && !ready; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        ready = fs::exists(out / "done1/report.json") && fs::exists(out / "done2/report.json") && children_of(pid).size() == 2;
    }
    ASSERT_TRUE(ready) << read_text(dir / "log");
    const std::string done1 = read_text(out / "done1/report.json");
    // Long enough for the children to install their handlers (a loaded machine); they run 40 s.
    std::this_thread::sleep_for(std::chrono::milliseconds(2000));
    kill(pid, SIGINT);
    const auto t0 = Clock::now();
    EXPECT_EQ(wait_exit(pid, 30), 130) << read_text(dir / "log");
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 12.0);
    EXPECT_TRUE(mentioning(out.string()).empty()) << "a child outlived the batch";
    EXPECT_EQ(read_text(out / "done1/report.json"), done1);  // completed rows stay complete
    EXPECT_EQ(summary_row(out, "done1")["status"].as<std::string>(), "ok");
    EXPECT_EQ(summary_row(out, "done2")["status"].as<std::string>(), "ok");
    EXPECT_EQ(summary_row(out, "long1")["status"].as<std::string>(), "cancelled");
    EXPECT_EQ(summary_row(out, "long1")["exit_code"].as<int>(), 130);
    EXPECT_EQ(summary_row(out, "long2")["status"].as<std::string>(), "cancelled");
    EXPECT_EQ(summary_row(out, "never")["status"].as<std::string>(), "missing");
    EXPECT_FALSE(fs::exists(out / "never"));
}

// A retry reruns only the rows that are not complete: the failing row reads a mesh that appears
// only after the first pass.
TEST(BatchLocal, ARetryRunsOnlyTheRowsThatAreNotComplete) {
    const fs::path dir = cf::testing::temp_dir("batch-retry");
    fs::copy_file(src("tests/runtime/data/batch/box.off"), dir / "box.off");
    const std::string pipe = src("tests/runtime/data/batch/tension.yaml");
    std::ofstream(dir / "m.csv") << "id,pipeline,box.path,operators.E\n"
                                 << "a," << pipe << ",box.off,3.1e9\n"
                                 << "flaky," << pipe << ",flaky.off,3.1e9\n"
                                 << "c," << pipe << ",box.off,1e9\n";
    const std::string args = (dir / "m.csv").string() + " --out " + (dir / "out").string() + " --workdir " + dir.string();
    Outcome first = run_batch(args + " --jobs 2");
    EXPECT_EQ(first.code, 2) << first.output;  // a row was invalid (docs/batch.md: exit codes)
    // The missing mesh is found when the row's pipeline is loaded: exit 2, an invalid row, whose
    // log names every path tried (the manifest check lets it pass: the file may appear later).
    EXPECT_EQ(summary_row(dir / "out", "flaky")["status"].as<std::string>(), "invalid");
    EXPECT_EQ(summary_row(dir / "out", "flaky")["exit_code"].as<int>(), 2);
    EXPECT_NE(read_text(dir / "out/flaky/batch_row.log").find((dir / "flaky.off").string()), std::string::npos);
    const std::string report_a = read_text(dir / "out/a/report.json");
    fs::copy_file(dir / "box.off", dir / "flaky.off");
    Outcome second = run_batch(args + " --jobs 2");
    EXPECT_EQ(second.code, 0) << second.output;
    EXPECT_NE(second.output.find("2 of 3 rows already complete"), std::string::npos) << second.output;
    EXPECT_NE(second.output.find("1/1 rows done (1 ok, 0 failed)"), std::string::npos) << second.output;
    EXPECT_EQ(read_text(dir / "out/a/report.json"), report_a);  // not rerun
    EXPECT_EQ(YAML::LoadFile((dir / "out/summary.json").string())["ok"].as<int>(), 3);
    // Identical rows give identical outputs (a and flaky read the same mesh with the same load).
    EXPECT_EQ(read_text(dir / "out/a/tension.vtp"), read_text(dir / "out/flaky/tension.vtp"));
    EXPECT_NE(read_text(dir / "out/a/tension.vtp"), read_text(dir / "out/c/tension.vtp"));
    // Nothing left to do.
    Outcome third = run_batch(args);
    EXPECT_EQ(third.code, 0) << third.output;
    EXPECT_NE(third.output.find("3 of 3 rows already complete"), std::string::npos) << third.output;
}

TEST(BatchLocal, AnInvalidManifestExits2AndRunsNothing) {
    const fs::path dir = cf::testing::temp_dir("batch-invalid");
    std::ofstream(dir / "m.csv") << "id,pipeline,settle.seconds,settle.secs\n"
                                 << "a," << src("pipelines/loop_demo.yaml") << ",-1,\n"
                                 << "a," << src("pipelines/nonexistent.yaml") << ",,\n";
    Outcome o = run_batch((dir / "m.csv").string() + " --out " + (dir / "out").string());
    EXPECT_EQ(o.code, 2) << o.output;
    const std::string f = (dir / "m.csv").string();
    EXPECT_NE(o.output.find(f + ":2:"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("row 'a', column 'settle.seconds': parameter 'seconds' of node 'settle' value -1"), std::string::npos)
        << o.output;
    EXPECT_NE(o.output.find(f + ":3:1: error: row 'a', column 'id': duplicate id"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("nothing was run"), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// --emit-commands: one self-contained command per row not yet complete, for any farm manager.
TEST(BatchLocal, EmittedCommandsRunTheRows) {
    const fs::path dir = cf::testing::temp_dir("batch-emit");
    std::ofstream(dir / "m.csv") << demo_rows({{"x", 0}, {"y", 0}});
    Outcome o = run_batch((dir / "m.csv").string() + " --out " + (dir / "out").string() + " --fast --emit-commands " +
                          (dir / "commands.txt").string());
    ASSERT_EQ(o.code, 0) << o.output;
    std::ifstream in(dir / "commands.txt");
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_NE(lines[0].find(" --row x "), std::string::npos) << lines[0];
    EXPECT_NE(lines[0].find(" --fast"), std::string::npos) << lines[0];
    for (const auto& l : lines) EXPECT_EQ(std::system(("cd / && " + l + " 2>/dev/null").c_str()), 0) << l;
    Outcome c = run_batch("--collect " + (dir / "out").string());
    EXPECT_EQ(c.code, 0) << c.output;
    EXPECT_NE(c.output.find("2 of 2 rows ok"), std::string::npos) << c.output;
    Outcome again = run_batch((dir / "m.csv").string() + " --out " + (dir / "out").string() + " --fast --emit-commands -");
    EXPECT_EQ(again.output.find("--row"), std::string::npos) << again.output;  // both complete
}

}  // namespace

namespace {

// The dataset example (pipelines/batch/dataset.csv): the whole manifest validates as --fast runs it,
// and one row of each of its three pipelines (two of the mesh one) runs to fragments through an emitted-command line
// (--row), from a working directory without the meshes: they are found in the build's data
// directory, where CMake extracted libcgal-demo's meshes (graph/input_paths.hpp).
TEST(BatchDataset, ManifestValidatesAndOneRowPerPipelineBreaks) {
    const std::string manifest = src("pipelines/batch/dataset.csv");
    Outcome check = run_batch(manifest + " --check --fast");
    ASSERT_EQ(check.code, 0) << check.output;
    EXPECT_NE(check.output.find("ok (51 rows)"), std::string::npos) << check.output;
    const fs::path work = cf::testing::temp_dir("batch-dataset-work");
    // setup.sh installs libcgal-demo and CMake extracts its meshes there: missing data is a failure.
    ASSERT_TRUE(fs::exists(fs::path(CRACKFLOW_BINARY_DIR) / "data/meshes/bunny00.off"))
        << "data/meshes/bunny00.off not extracted into the build folder: install libcgal-demo and re-run cmake";
    const fs::path out = cf::testing::temp_dir("batch-dataset");
    // knot1: its first crack grew through the coarse BEM surface of the knot's tube until the
    // dataset's pipelines gave propagation the BEM surface to keep new crack nodes inside.
    for (const std::string id : {"torus_u4e-3_s1", "cylinder_u4e-3_s1", "bunny00_u4e-3_s1", "knot1_u2e-3_s1"}) {
        Outcome o = run_batch(manifest + " --out " + out.string() + " --row " + id + " --workdir " + work.string() +
                              " --fast --threads 2");
        ASSERT_EQ(o.code, 0) << o.output << read_text(out / id / "batch_row.log");
        const YAML::Node report = YAML::LoadFile((out / id / "report.json").string());
        const long long fragments = report["summary"]["fracture"]["fragments"].as<long long>();
        int obj = 0;
        for (const auto& e : fs::directory_iterator(out / id))
            obj += e.path().extension() == ".obj" && e.path().filename().string().rfind("fragment_", 0) == 0;
        EXPECT_GE(fragments, 1) << id;
        EXPECT_EQ(obj, fragments) << id << ": one OBJ per fragment";
        // The pieces keep the object's own triangles (the surface mesher): fracture faces in the
        // material 'inside', no fragment fallen back to its level-set mesh.
        for (const auto& n : report["nodes"])
            if (n["type"].as<std::string>() == "export.fragments")
                EXPECT_EQ(n["counts"]["fallback_fragments"].as<int>(-1), 0) << id;
        EXPECT_NE(read_text(out / id / "fragment_000.obj").find("usemtl inside"), std::string::npos) << id;
        EXPECT_GE(report["summary"]["fracture"]["cracks_initiated"].as<int>(), 1) << id;
    }
    Outcome c = run_batch("--collect " + out.string());
    EXPECT_NE(c.output.find("4 of 51 rows ok, 47 failed"), std::string::npos) << c.output;  // the rest never ran
}

}  // namespace

namespace {

TEST(BatchLocal, CollectOfAFolderThatIsNoBatchIsAnInputError) {
    const fs::path dir = cf::testing::temp_dir("batch-collect");
    Outcome o = run_batch("--collect " + dir.string());
    EXPECT_EQ(o.code, 2) << o.output;
    EXPECT_NE(o.output.find("is not a batch output directory"), std::string::npos) << o.output;
}

}  // namespace

namespace {

// A manifest over thesis cases sets their sub-pipeline's parameters by the use node's name
// (fracture.method, a boundary-condition text with colons) and a node inside it by its path
// (fracture/propagate.substeps); a parameter the sub-pipeline does not declare is an error at its
// cell. --check --fast validates every row as run --fast would load it.
TEST(BatchLocal, ManifestColumnsSetSubPipelineParameters) {
    const fs::path dir = cf::testing::temp_dir("batch-subpipeline");
    {
        std::ofstream m(dir / "m.csv");
        m << "id,pipeline,fracture.method,fracture.boundary_conditions,fracture/propagate.substeps\n"
          << "a," << src("pipelines/edge_crack_mode1.yaml") << ",estimator,z_max: displacement 0 0 1e-4; *: traction 0 0 0,3\n"
          << "b," << src("pipelines/notched_bar.yaml") << ",hybrid,,\n";
    }
    Outcome ok = run_batch((dir / "m.csv").string() + " --check --fast");
    EXPECT_EQ(ok.code, 0) << ok.output;
    EXPECT_NE(ok.output.find("ok (2 rows)"), std::string::npos) << ok.output;
    {
        std::ofstream m(dir / "bad.csv");
        m << "id,pipeline,fracture.methd\n"
          << "a," << src("pipelines/edge_crack_mode1.yaml") << ",estimator\n";
    }
    Outcome bad = run_batch((dir / "bad.csv").string() + " --check");
    EXPECT_EQ(bad.code, 2) << bad.output;
    EXPECT_NE(bad.output.find("has no parameter 'methd'"), std::string::npos) << bad.output;
    EXPECT_NE(bad.output.find("did you mean 'method'?"), std::string::npos) << bad.output;
}

}  // namespace
