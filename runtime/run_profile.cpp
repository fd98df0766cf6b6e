#include "runtime/run_profile.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

namespace cf::runtime {
namespace {

// The ordinary nodes whose runs node i waits for: its inputs' nodes, a loop replaced by the
// sources of its initial, next and while values (recursively, for nested loops).
std::vector<int> upstream_nodes(const graph::Plan& plan, int i) {
    std::set<int> out, seen;
    std::vector<int> todo;
    for (const graph::PlanInput& in : plan.nodes[i].inputs) todo.push_back(in.source);
    while (!todo.empty()) {
        const int j = todo.back();
        todo.pop_back();
        if (j < 0 || j == i || !seen.insert(j).second) continue;
        if (!plan.nodes[j].is_loop()) {
            out.insert(j);
            continue;
        }
        // A loop's values come from its initial values and its body's `next` (and `while`) nodes.
        for (const graph::PlanInput& in : plan.nodes[j].loop_init) todo.push_back(in.source);
        for (const graph::PlanInput& in : plan.nodes[j].loop_next) todo.push_back(in.source);
        if (plan.nodes[j].loop_while) todo.push_back(plan.nodes[j].loop_while->source);
    }
    return {out.begin(), out.end()};
}

struct Run {
    int node = -1;
    double start = 0, end = 0;
};

}  // namespace

RunProfile run_profile(const graph::Plan& plan, const graph::ExecutionResult& result) {
    RunProfile p;
    p.wall_seconds = result.wall_seconds;
    std::map<std::string, double> by_type;
    std::vector<std::vector<Run>> runs(plan.nodes.size());
    const Run* last = nullptr;
    for (std::size_t i = 0; i < plan.nodes.size() && i < result.stats.size(); ++i) {
        if (plan.nodes[i].is_loop()) continue;
        const graph::NodeStats& s = result.stats[i];
        by_type[s.type] += s.wall_seconds;
        p.node_seconds += s.wall_seconds;
        for (const auto& [a, b] : s.intervals)
            if (b >= a) runs[i].push_back(Run{int(i), a, b});
    }
    for (const auto& r : runs)
        for (const Run& x : r)
            if (!last || x.end > last->end) last = &x;
    p.stage_seconds.assign(by_type.begin(), by_type.end());
    std::stable_sort(p.stage_seconds.begin(), p.stage_seconds.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    std::vector<std::vector<int>> up(plan.nodes.size());
    for (std::size_t i = 0; i < plan.nodes.size(); ++i) up[i] = upstream_nodes(plan, int(i));
    std::vector<const Run*> path;
    constexpr double kSlack = 1e-3;  // [s] a consumer starts just after its producer's end is stamped
    for (const Run* r = last; r;) {
        path.push_back(r);
        const Run* before = nullptr;
        for (int j : up[r->node])
            for (const Run& x : runs[j])
                // Started strictly earlier, so the walk ends (loop bodies are upstream of each other).
                if (x.end <= r->start + kSlack && x.start < r->start && (!before || x.end > before->end)) before = &x;
        r = before;
    }
    std::reverse(path.begin(), path.end());
    std::map<int, std::size_t> slot;  // node -> its entry in critical_path
    for (const Run* r : path) {
        auto [it, fresh] = slot.emplace(r->node, p.critical_path.size());
        if (fresh) p.critical_path.push_back(CriticalNode{plan.nodes[r->node].name, result.stats[r->node].type, 0, 0});
        CriticalNode& c = p.critical_path[it->second];
        ++c.runs;
        c.seconds += r->end - r->start;
        p.critical_seconds += r->end - r->start;
    }
    return p;
}

std::string profile_text(const RunProfile& p) {
    std::string out;
    char line[256];
    std::snprintf(line, sizeof line, "profile: wall %.2f s; node runs %.2f s in all (%.2fx overlap)\n", p.wall_seconds,
                  p.node_seconds, p.wall_seconds > 0 ? p.node_seconds / p.wall_seconds : 0.0);
    out += line;
    out += "  seconds per node type (share of the node runs):\n";
    for (const auto& [type, s] : p.stage_seconds) {
        if (s < 0.0005) continue;
        std::snprintf(line, sizeof line, "    %-28s %8.3f  %5.1f %%\n", type.c_str(), s,
                      p.node_seconds > 0 ? 100 * s / p.node_seconds : 0.0);
        out += line;
    }
    std::snprintf(line, sizeof line, "  critical path (%.2f s of nodes, %.2f s waiting or scheduling):\n",
                  p.critical_seconds, std::max(0.0, p.wall_seconds - p.critical_seconds));
    out += line;
    for (const CriticalNode& c : p.critical_path) {
        if (c.seconds < 0.0005) continue;
        std::snprintf(line, sizeof line, "    %-22s %-24s %4d run%s %8.3f s\n", c.node.c_str(), c.type.c_str(), c.runs,
                      c.runs == 1 ? " " : "s", c.seconds);
        out += line;
    }
    return out;
}

}  // namespace cf::runtime
