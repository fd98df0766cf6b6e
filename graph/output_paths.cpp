#include "graph/output_paths.hpp"

#include <filesystem>
#include <functional>
#include <vector>

namespace cf::graph {

namespace {

// A file name a run will write: given by a parameter, or fixed by a node type (FixedOutput).
// In `pattern`, kNumber stands for a number ({iteration} in a parameter, '*' in a fixed name).
struct Claim {
    std::string pattern;
    std::string shown;  // as the user wrote it, or the fixed name with its parameters filled in
    std::string owner;  // "w.path" for a parameter, the node's name for a fixed output
    const PlanNode* node = nullptr;
    bool fixed = false;
    std::string when;    // fixed: the Bool parameter that turns it on (or empty)
    std::vector<std::string> name_params;  // fixed: the parameters whose values are in the name
};

constexpr char kNumber = '\x01';  // in a pattern: any run of decimal digits (an iteration, an index)

// Whether some file name matches both patterns (kNumber: zero or more digits, the rest literal).
bool patterns_overlap(const std::string& a, const std::string& b) {
    std::vector<signed char> memo((a.size() + 1) * (b.size() + 1), -1);
    const auto digit_or_number = [](char c) { return c == kNumber || (c >= '0' && c <= '9'); };
    std::function<bool(std::size_t, std::size_t)> go = [&](std::size_t i, std::size_t j) -> bool {
        signed char& m = memo[i * (b.size() + 1) + j];
        if (m >= 0) return m;
        bool r;
        if (i == a.size() && j == b.size()) r = true;
        // A number in one pattern ends here, or takes the other's next digit (or all of its number).
        else if (i < a.size() && a[i] == kNumber) r = go(i + 1, j) || (j < b.size() && digit_or_number(b[j]) && go(i, j + 1));
        else if (j < b.size() && b[j] == kNumber) r = go(i, j + 1) || (i < a.size() && digit_or_number(a[i]) && go(i + 1, j));
        else r = i < a.size() && j < b.size() && a[i] == b[j] && go(i + 1, j + 1);
        m = r;
        return r;
    };
    return go(0, 0);
}

std::string replace_all(std::string s, const std::string& what, const std::string& with) {
    for (std::size_t k = s.find(what); k != std::string::npos; k = s.find(what, k + with.size())) s.replace(k, what.size(), with);
    return s;
}

std::string param_text(const PlanNode& n, const std::string& name) {
    const auto it = n.params.find(name);
    if (it == n.params.end()) return "";
    if (const auto* s = std::get_if<std::string>(&it->second)) return *s;
    return format_param_value(it->second);
}

bool param_true(const PlanNode& n, const std::string& name) {
    const auto it = n.params.find(name);
    const bool* b = it == n.params.end() ? nullptr : std::get_if<bool>(&it->second);
    return b && *b;
}

// The fixed names `n` will write with its parameters.
void add_fixed_claims(const PlanNode& n, std::vector<Claim>& claims) {
    for (const FixedOutput& f : n.type->fixed_outputs()) {
        if (!f.when.empty() && !param_true(n, f.when)) continue;
        std::string name = f.name;
        std::vector<std::string> name_params;
        for (std::size_t open = name.find('<'); open != std::string::npos; open = name.find('<')) {
            const std::size_t close = name.find('>', open);
            name_params.push_back(name.substr(open + 1, close - open - 1));
            name.replace(open, close - open + 1, param_text(n, name_params.back()));
        }
        claims.push_back({replace_all(name, "*", std::string(1, kNumber)), name, n.name, &n, true, f.when, name_params});
    }
}

std::string node_text(const Claim& c) { return "node '" + c.owner + "' (" + c.node->type->name() + ")"; }

// What to change so that fixed output `c` no longer takes that name.
std::string fixed_fix(const Claim& c) {
    std::string fix;
    for (const std::string& p : c.name_params)
        fix += std::string(fix.empty() ? "change '" : " or '") + c.owner + "." + p + "'";
    if (!c.when.empty()) fix += std::string(fix.empty() ? "" : ", or ") + "set '" + c.owner + "." + c.when + "' to false";
    return fix;
}

void report_collision(const Claim& earlier, const Claim& later, std::vector<Diagnostic>& diags) {
    if (!later.fixed && !earlier.fixed) {
        const bool same = later.pattern == earlier.pattern;
        diags.push_back({later.node->loc,
                         "parameter '" + later.owner + "' " + (same ? "names" : "can name") + " the same file as '" + earlier.owner +
                             "' ('" + (same ? later.shown : later.shown + "' and '" + earlier.shown) + "'); one would overwrite the other",
                         "give each output its own name"});
    } else if (!later.fixed || !earlier.fixed) {
        const Claim& user = later.fixed ? earlier : later;
        const Claim& fixed = later.fixed ? later : earlier;
        const std::string fix = fixed_fix(fixed);
        diags.push_back({later.node->loc,
                         "parameter '" + user.owner + "' ('" + user.shown + "') names a file that " + node_text(fixed) +
                             " writes under the fixed name '" + fixed.shown + "'; one would overwrite the other",
                         "give parameter '" + user.owner + "' another name" + (fix.empty() ? "" : ", or " + fix)});
    } else {
        const std::string fix = fixed_fix(later);
        diags.push_back({later.node->loc,
                         node_text(later) + " writes '" + later.shown + "', a file that " + node_text(earlier) +
                             " writes as '" + earlier.shown + "'; one would overwrite the other",
                         fix.empty() ? "keep only one of the two nodes" : "in node '" + later.owner + "', " + fix});
    }
}

}  // namespace

void check_output_paths(const Plan& plan, bool allow_absolute, std::vector<Diagnostic>& diags) {
    std::vector<Claim> claims;  // in plan order: a collision is reported at the later node
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
            claims.push_back({replace_all(rel.string(), "{iteration}", std::string(1, kNumber)), rel.string(), where, &n, false, "", {}});
        }
        add_fixed_claims(n, claims);
    }
    for (std::size_t k = 1; k < claims.size(); ++k)
        for (std::size_t e = 0; e < k; ++e) {
            // A node's own fixed names are distinct by construction.
            if (claims[e].fixed && claims[k].fixed && claims[e].node == claims[k].node) continue;
            if (!patterns_overlap(claims[e].pattern, claims[k].pattern)) continue;
            report_collision(claims[e], claims[k], diags);
            break;  // one message per output
        }
}

}  // namespace cf::graph
