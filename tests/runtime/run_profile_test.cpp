// The run profile (issue 17): seconds per node type and the critical path, on hand-made timelines.
#include "runtime/run_profile.hpp"

#include <gtest/gtest.h>

namespace cf::runtime {
namespace {

const graph::NodeType kWork("test.work", "a node that takes time");

graph::PlanNode node(const std::string& name, std::vector<int> inputs) {
    graph::PlanNode n;
    n.name = name;
    n.type = &kWork;
    for (int i : inputs) n.inputs.push_back(graph::PlanInput{"in", i, "out"});
    return n;
}

graph::NodeStats stats(const std::string& name, std::vector<std::pair<double, double>> runs) {
    graph::NodeStats s;
    s.name = name;
    s.type = "test.work";
    for (const auto& [a, b] : runs) s.wall_seconds += b - a;
    s.runs = int(runs.size());
    s.intervals = std::move(runs);
    return s;
}

// a -> b -> d and a -> c -> d, c longer than b: the path is a, c, d; b ran beside c.
TEST(RunProfile, CriticalPathFollowsTheLongerBranch) {
    graph::Plan plan;
    plan.nodes = {node("a", {}), node("b", {0}), node("c", {0}), node("d", {1, 2})};
    graph::ExecutionResult r;
    r.wall_seconds = 4.1;
    r.stats = {stats("a", {{0, 1}}), stats("b", {{1, 1.5}}), stats("c", {{1, 3}}), stats("d", {{3, 4}})};
    const RunProfile p = run_profile(plan, r);
    ASSERT_EQ(p.critical_path.size(), 3u);
    EXPECT_EQ(p.critical_path[0].node, "a");
    EXPECT_EQ(p.critical_path[1].node, "c");
    EXPECT_EQ(p.critical_path[2].node, "d");
    EXPECT_DOUBLE_EQ(p.critical_seconds, 4.0);  // 1 + 2 + 1
    EXPECT_DOUBLE_EQ(p.node_seconds, 4.5);      // b's 0.5 s overlapped
    ASSERT_EQ(p.stage_seconds.size(), 1u);
    EXPECT_DOUBLE_EQ(p.stage_seconds[0].second, 4.5);
    EXPECT_NE(profile_text(p).find("critical path (4.00 s of nodes, 0.10 s waiting"), std::string::npos);
}

// A loop of two iterations: body x (from the loop variable) then y (the loop's next value); an
// output node z streamed beside it per iteration is not on the path; w after the loop is.
TEST(RunProfile, CriticalPathRunsThroughLoopIterations) {
    graph::Plan plan;
    plan.nodes.resize(6);
    plan.nodes[0] = node("init", {});
    plan.nodes[1].name = "loop";  // type null: a loop
    plan.nodes[1].loop_init = {graph::PlanInput{"", 0, "out"}};
    plan.nodes[1].loop_next = {graph::PlanInput{"", 3, "out"}};
    plan.nodes[2] = node("x", {1});
    plan.nodes[2].body_of = 1;
    plan.nodes[3] = node("y", {2});
    plan.nodes[3].body_of = 1;
    plan.nodes[4] = node("z", {3});
    plan.nodes[4].body_of = 1;
    plan.nodes[5] = node("w", {1});
    graph::ExecutionResult r;
    r.wall_seconds = 8;
    r.stats = {stats("init", {{0, 1}}), graph::NodeStats{},
               stats("x", {{1, 2}, {3, 4}}), stats("y", {{2, 3}, {4, 5}}),
               stats("z", {{3, 3.9}, {5, 7.5}}), stats("w", {{5, 8}})};
    r.stats[1].type = "loop";
    const RunProfile p = run_profile(plan, r);
    ASSERT_EQ(p.critical_path.size(), 4u);
    EXPECT_EQ(p.critical_path[0].node, "init");
    EXPECT_EQ(p.critical_path[1].node, "x");
    EXPECT_EQ(p.critical_path[1].runs, 2);
    EXPECT_EQ(p.critical_path[2].node, "y");
    EXPECT_EQ(p.critical_path[2].runs, 2);
    EXPECT_EQ(p.critical_path[3].node, "w");
    EXPECT_DOUBLE_EQ(p.critical_seconds, 8.0);
}

}  // namespace
}  // namespace cf::runtime
