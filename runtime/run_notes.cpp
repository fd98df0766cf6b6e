#include "runtime/run_notes.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>
#include <variant>

namespace cf::runtime {
namespace {

// "set at FILE:LINE (in a sub-pipeline used at ...)" or "given by --set" for a parameter given in a
// file or by an override; "" for a default.
std::string where_set(const graph::PlanNode& n, const std::string& param) {
    const auto it = n.param_locs.find(param);
    if (it == n.param_locs.end() || it->second.file.empty()) return "";
    if (it->second.file.rfind("--set", 0) == 0) return "given by --set";
    std::string s = "set at " + it->second.file;
    if (it->second.line > 0) s += ":" + std::to_string(it->second.line);
    if (!it->second.via.empty()) s += ", in a sub-pipeline used at " + it->second.via;
    return s;
}

// A count of a node's last run (NodeStats::counts holds the last run's; 0 when not reported).
double last_count(const graph::NodeStats& s, const std::string& key) {
    const auto it = s.counts.find(key);
    return it == s.counts.end() ? 0.0 : it->second;
}

// Loop i stopped by max_iterations while its `while` still said go on.
void note_cut_short_loop(const graph::Plan& plan, const graph::ExecutionResult& result, std::size_t i,
                         std::vector<std::string>& notes) {
    const graph::PlanNode& n = plan.nodes[i];
    const graph::NodeStats& s = result.stats[i];
    if (!n.loop_while || !s.counts.count("stopped_by_while") || last_count(s, "stopped_by_while") != 0 ||
        s.runs < n.max_iterations)
        return;
    std::string growth;
    for (std::size_t j = 0; j < plan.nodes.size() && j < result.stats.size(); ++j) {
        if (plan.nodes[j].body_of != int(i) || result.stats[j].type != "propagate.fronts" || result.stats[j].runs == 0) continue;
        growth = " (in its last step '" + plan.nodes[j].name + "' added " +
                 graph::format_number(last_count(result.stats[j], "elements_added")) + " crack elements and " +
                 graph::format_number(last_count(result.stats[j], "active_markers")) + " front markers were still moving)";
        break;
    }
    const std::string at = where_set(n, "max_iterations");
    notes.push_back("loop '" + n.name + "' stopped after max_iterations = " + std::to_string(n.max_iterations) +
                    (at.empty() ? " (the default)" : " (" + at + ")") + " with its while condition still true" +
                    growth + ". Raise max_iterations to let it run on");
}

// initiate.cracks node i reached max_cracks with candidates left over in its last run.
void note_crack_limit(const graph::Plan& plan, const graph::ExecutionResult& result, std::size_t i,
                      std::vector<std::string>& notes) {
    const graph::PlanNode& n = plan.nodes[i];
    const auto p = n.params.find("max_cracks");
    if (p == n.params.end() || !std::holds_alternative<long long>(p->second)) return;
    const long long max_cracks = std::get<long long>(p->second);
    const double held = last_count(result.stats[i], "over_budget");
    if (max_cracks <= 0 || held <= 0) return;  // 0: initiation switched off on purpose
    const std::string at = where_set(n, "max_cracks");
    notes.push_back("initiate.cracks '" + n.name + "': max_cracks = " + std::to_string(max_cracks) +
                    (at.empty() ? " (the default)" : " (" + at + ")") + " was reached; in the last BEM step " +
                    graph::format_number(held) +
                    " more surface elements exceeded the strength more than r_c from every crack front. Raise "
                    "max_cracks if more cracks should start");
}

// simplify.remesh node i ended more than 5 % away from its target count: it keeps the closest of
// its edge-length corrections rather than failing, so the user hears of it here.
void note_remesh_count(const graph::Plan& plan, const graph::ExecutionResult& result, std::size_t i,
                       std::vector<std::string>& notes) {
    const graph::PlanNode& n = plan.nodes[i];
    const auto p = n.params.find("target_triangles");
    if (p == n.params.end() || !std::holds_alternative<long long>(p->second)) return;
    const double target = double(std::get<long long>(p->second)), got = last_count(result.stats[i], "triangles");
    if (!(target > 0) || !(got > 0)) return;
    const double off = std::abs(got / target - 1);
    if (off <= 0.05) return;
    const std::string at = where_set(n, "target_triangles");
    notes.push_back("simplify.remesh '" + n.name + "': " + graph::format_number(got) + " triangles for target_triangles = " +
                    graph::format_number(target) + (at.empty() ? " (the default)" : " (" + at + ")") + ", " +
                    graph::format_number(std::round(1000 * off) / 10) +
                    " % off: the closest count its edge-length corrections reached while meeting the element-shape "
                    "bounds. Change target_triangles if the BEM mesh should be finer or coarser");
}

}  // namespace

std::vector<std::string> run_notes(const graph::Plan& plan, const graph::ExecutionResult& result) {
    std::vector<std::string> notes;
    for (std::size_t i = 0; i < plan.nodes.size() && i < result.stats.size(); ++i) {
        if (result.stats[i].runs == 0) continue;
        if (plan.nodes[i].is_loop()) note_cut_short_loop(plan, result, i, notes);
        else if (result.stats[i].type == "initiate.cracks") note_crack_limit(plan, result, i, notes);
        else if (result.stats[i].type == "simplify.remesh") note_remesh_count(plan, result, i, notes);
    }
    return notes;
}

}  // namespace cf::runtime
