#include "graph/output_paths.hpp"

#include <filesystem>
#include <map>

namespace cf::graph {

void check_output_paths(const Plan& plan, bool allow_absolute, std::vector<Diagnostic>& diags) {
    std::map<std::string, std::string> owner;  // normalised path -> "node.param"
    for (const PlanNode& n : plan.nodes) {
        if (n.is_loop()) continue;
        for (const ParamDecl& d : n.type->params()) {
            if (!d.output_file) continue;
            const auto it = n.params.find(d.name);
            if (it == n.params.end() || !std::holds_alternative<std::string>(it->second)) continue;
            const std::string& value = std::get<std::string>(it->second);
            if (value.empty() || value == "none") continue;  // "not written" / derived from another parameter
            const std::string where = n.name + "." + d.name;
            const std::filesystem::path p(value);
            if (p.is_absolute()) {
                if (!allow_absolute)
                    diags.push_back({n.loc, "parameter '" + where + "' is the absolute path '" + value + "'",
                                     "outputs go inside the output directory (--out): use a relative name, or run with "
                                     "--allow-absolute-paths"});
                continue;
            }
            const std::filesystem::path rel = p.lexically_normal();
            if (rel.empty() || *rel.begin() == "..") {
                diags.push_back({n.loc, "parameter '" + where + "' ('" + value + "') leaves the output directory",
                                 "use a name inside it"});
                continue;
            }
            if (rel == "report.json") {
                diags.push_back({n.loc, "parameter '" + where + "' names report.json, which the run writes last",
                                 "choose another file name"});
                continue;
            }
            const auto [other, fresh] = owner.emplace(rel.string(), where);
            if (!fresh)
                diags.push_back({n.loc, "parameter '" + where + "' names the same file as '" + other->second + "' ('" +
                                            rel.string() + "'); one would overwrite the other",
                                 "give each output its own name"});
        }
    }
}

}  // namespace cf::graph
