#include "runtime/run_notes.hpp"

#include "graph/diagnostics.hpp"

#include <variant>

namespace cf::runtime {
namespace {

// "FILE:LINE (in a sub-pipeline used at ...)" for a parameter given in a file or by --set; "" for a default.
std::string where_set(const graph::PlanNode& n, const std::string& param) {
    const auto it = n.param_locs.find(param);
    if (it == n.param_locs.end() || it->second.file.empty()) return "";
    std::string s = it->second.file;
    if (it->second.line > 0) s += ":" + std::to_string(it->second.line);
    if (!it->second.via.empty()) s += ", in a sub-pipeline used at " + it->second.via;
    return s;
}

double last_count(const graph::NodeStats& s, const std::string& key) {
    const auto& c = s.iteration_counts.empty() ? s.counts : s.iteration_counts.back();
    const auto it = c.find(key);
    return it == c.end() ? 0.0 : it->second;
}

}  // namespace

std::vector<std::string> run_notes(const graph::Plan& plan, const graph::ExecutionResult& result) {
    std::vector<std::string> notes;
    for (std::size_t i = 0; i < plan.nodes.size() && i < result.stats.size(); ++i) {
        const graph::PlanNode& n = plan.nodes[i];
        const graph::NodeStats& s = result.stats[i];
        if (n.is_loop() || s.runs == 0 || s.type != "initiate.cracks") continue;
        const auto p = n.params.find("max_cracks");
        if (p == n.params.end() || !std::holds_alternative<long long>(p->second)) continue;
        const long long max_cracks = std::get<long long>(p->second);
        const double held = last_count(s, "over_budget");
        if (max_cracks <= 0 || held <= 0) continue;  // 0: initiation switched off on purpose
        const std::string at = where_set(n, "max_cracks");
        notes.push_back("initiate.cracks '" + n.name + "': max_cracks = " + std::to_string(max_cracks) +
                        (at.empty() ? " (the default)" : " (set at " + at + ")") + " was reached; in the last BEM step " +
                        graph::format_number(held) +
                        " more surface elements exceeded the strength more than r_c from every crack front. Raise "
                        "max_cracks if more cracks should start");
    }
    return notes;
}

}  // namespace cf::runtime
