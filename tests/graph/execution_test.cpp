// Executing plans on the oneTBB flow graph: values, loops, streaming, concurrency, failures.
#include "graph/executor.hpp"
#include "test_registry.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <thread>

using namespace cf::graph;

namespace {

Plan must_load(const std::string& text) {
    std::vector<Diagnostic> diags;
    Plan p = load_text(text, diags);
    std::string s;
    for (const auto& d : diags) s += format(d) + "\n";
    EXPECT_TRUE(diags.empty()) << s;
    return p;
}

const NodeStats& stats(const ExecutionResult& r, const std::string& name) {
    for (const auto& s : r.stats)
        if (s.name == name) return s;
    throw std::logic_error("no stats for " + name);
}

bool overlap(std::pair<double, double> a, std::pair<double, double> b) { return a.first < b.second && b.first < a.second; }

std::filesystem::path fresh_dir(const std::string& name) {
    auto d = std::filesystem::temp_directory_path() / "crackflow-tests" / ("graph-" + name);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

}  // namespace

TEST(Execution, ComputesValuesThroughTheGraph) {
    Plan plan = must_load(R"(nodes:
  a: {type: core.real, params: {value: 2}}
  b: {type: core.real, params: {value: 3.5}}
  s: {type: core.add, inputs: {a: a.value, b: b.value}}
  t: {type: core.add, inputs: {a: s.sum, b: s.sum}}
)");
    ExecutionResult r = execute(plan, RunOptions{});
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_DOUBLE_EQ(r.outputs.at("t").at("sum").get<double>(), 11.0);
    for (const auto& s : r.stats) EXPECT_EQ(s.runs, 1) << s.name;
}

TEST(Execution, LoopIteratesWhileConditionHoldsAndStreamsEveryIteration) {
    auto dir = fresh_dir("loop");
    Plan plan = must_load(R"(nodes:
  zero: {type: core.real, params: {value: 0}}
  one: {type: core.real, params: {value: 1}}
  limit: {type: core.real, params: {value: 5}}
  count:
    type: loop
    params: {max_iterations: 100}
    inputs: {n: zero.value}
    body:
      inc: {type: core.add, inputs: {a: count.n, b: one.value}}
      more: {type: core.less, inputs: {a: inc.sum, b: limit.value}}
    next: {n: inc.sum}
    while: more.result
  write_each: {type: core.write_real, params: {path: "n_{iteration}.txt"}, inputs: {value: count.each.n}}
  doubled: {type: core.add, inputs: {a: count.final.n, b: count.final.n}}
)");
    RunOptions opt;
    opt.output_dir = dir;
    ExecutionResult r = execute(plan, opt);
    ASSERT_TRUE(r.ok) << r.error;
    // n goes 0 -> 1 -> ... -> 5; the condition 5 < 5 fails after the fifth iteration.
    EXPECT_EQ(stats(r, "inc").runs, 5);
    EXPECT_EQ(stats(r, "write_each").runs, 5);
    EXPECT_EQ(stats(r, "doubled").runs, 1);
    EXPECT_DOUBLE_EQ(r.outputs.at("doubled").at("sum").get<double>(), 10.0);
    EXPECT_EQ(stats(r, "count").counts.at("iterations"), 5);
    EXPECT_EQ(stats(r, "count").counts.at("stopped_by_while"), 1);
    for (int k = 0; k < 5; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "n_%04d.txt", k);
        std::ifstream f(dir / name);
        double v = -1;
        f >> v;
        EXPECT_DOUBLE_EQ(v, k + 1.0) << name;
    }
}

TEST(Execution, LoopStopsAtMaxIterations) {
    Plan plan = must_load(R"(nodes:
  zero: {type: core.real}
  one: {type: core.real, params: {value: 1}}
  count:
    type: loop
    params: {max_iterations: 3}
    inputs: {n: zero.value}
    body:
      inc: {type: core.add, inputs: {a: count.n, b: one.value}}
    next: {n: inc.sum}
  result: {type: core.add, inputs: {a: count.final.n, b: zero.value}}
)");
    ExecutionResult r = execute(plan, RunOptions{});
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_DOUBLE_EQ(r.outputs.at("result").at("sum").get<double>(), 3.0);
    EXPECT_EQ(stats(r, "count").counts.at("stopped_by_while"), 0);
}

TEST(Execution, IndependentBranchesOverlapInTime) {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    Plan plan = must_load(R"(nodes:
  src: {type: core.real, params: {value: 1}}
  left: {type: core.wait, params: {seconds: 0.3}, inputs: {value: src.value}}
  right: {type: core.wait, params: {seconds: 0.3}, inputs: {value: src.value}}
  join: {type: core.add, inputs: {a: left.value, b: right.value}}
)");
    ExecutionResult r = execute(plan, RunOptions{});
    ASSERT_TRUE(r.ok) << r.error;
    const auto& l = stats(r, "left").intervals.at(0);
    const auto& rt = stats(r, "right").intervals.at(0);
    EXPECT_TRUE(overlap(l, rt)) << "left [" << l.first << ", " << l.second << "] right [" << rt.first << ", " << rt.second << "]";
    // The join starts only after both branches have finished.
    EXPECT_GE(stats(r, "join").intervals.at(0).first, std::max(l.second, rt.second));
}

TEST(Execution, StreamedOutputOverlapsTheNextIteration) {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    Plan plan = must_load(R"(nodes:
  zero: {type: core.real}
  one: {type: core.real, params: {value: 1}}
  steps:
    type: loop
    params: {max_iterations: 3}
    inputs: {n: zero.value}
    body:
      step: {type: core.add, inputs: {a: steps.n, b: one.value}}
      compute: {type: core.wait, params: {seconds: 0.2}, inputs: {value: step.sum}}
    next: {n: compute.value}
  export: {type: core.wait, params: {seconds: 0.2}, inputs: {value: steps.each.n}}
)");
    ExecutionResult r = execute(plan, RunOptions{});
    ASSERT_TRUE(r.ok) << r.error;
    const auto& ex = stats(r, "export").intervals;
    const auto& co = stats(r, "compute").intervals;
    ASSERT_EQ(ex.size(), 3u);
    ASSERT_EQ(co.size(), 3u);
    // Export of iteration 0 runs while iteration 1 computes.
    EXPECT_TRUE(overlap(ex[0], co[1])) << ex[0].first << " " << ex[0].second << " vs " << co[1].first << " " << co[1].second;
}

TEST(Execution, FailureCancelsTheRunAndIsReportedOnceWithTheNodeName) {
    Plan plan = must_load(R"(nodes:
  src: {type: core.real, params: {value: 1}}
  bad: {type: test.fail, inputs: {value: src.value}}
  slow: {type: core.wait, params: {seconds: 30}, inputs: {value: src.value}}
  after: {type: core.add, inputs: {a: bad.value, b: slow.value}}
)");
    auto t0 = std::chrono::steady_clock::now();
    ExecutionResult r = execute(plan, RunOptions{});
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_FALSE(r.ok);
    EXPECT_FALSE(r.cancelled);
    EXPECT_EQ(r.failed_node, "bad");
    EXPECT_EQ(r.error, "node 'bad' (test.fail): deliberate failure for the test");
    EXPECT_EQ(stats(r, "after").runs, 0);
    // The 30 s wait noticed the cancellation instead of running to the end.
    EXPECT_LT(seconds, 20.0);
}

TEST(Execution, CancelFlagStopsTheRun) {
    Plan plan = must_load(R"(nodes:
  src: {type: core.real, params: {value: 1}}
  slow: {type: core.wait, params: {seconds: 30}, inputs: {value: src.value}}
  after: {type: core.add, inputs: {a: slow.value, b: slow.value}}
)");
    std::atomic<bool> flag{false};
    RunOptions opt;
    opt.cancel_flag = &flag;
    std::thread ctrl_c([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        flag.store(true);  // what the SIGINT handler does
    });
    ExecutionResult r = execute(plan, opt);
    ctrl_c.join();
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(r.cancelled);
    EXPECT_TRUE(r.error.empty());
    EXPECT_EQ(stats(r, "after").runs, 0);
}

TEST(Execution, ResultsDoNotDependOnThreadCount) {
    const std::string text = R"(nodes:
  zero: {type: core.real}
  third: {type: core.real, params: {value: 0.333333333333}}
  acc:
    type: loop
    params: {max_iterations: 50}
    inputs: {x: zero.value}
    body:
      add: {type: core.add, inputs: {a: acc.x, b: third.value}}
    next: {x: add.sum}
  out: {type: core.add, inputs: {a: acc.final.x, b: zero.value}}
)";
    double v1, v2;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        v1 = execute(must_load(text), RunOptions{}).outputs.at("out").at("sum").get<double>();
    }
    {
        tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        v2 = execute(must_load(text), RunOptions{}).outputs.at("out").at("sum").get<double>();
    }
    EXPECT_EQ(v1, v2);
    EXPECT_NEAR(v1, 50 * 0.333333333333, 1e-9);
}
