#include "runtime/step_table.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <vector>

namespace cf::runtime {

std::string loop_step_tables(const graph::Plan& plan, const graph::ExecutionResult& result) {
    std::string out;
    for (std::size_t l = 0; l < plan.nodes.size(); ++l) {
        if (!plan.nodes[l].is_loop()) continue;
        struct Column {
            std::size_t node;
            std::string key;  // "wall_seconds" or a node's own '*_seconds' count
            std::string title;
        };
        std::vector<Column> cols;
        std::size_t rows = 0;
        for (std::size_t i = 0; i < plan.nodes.size(); ++i) {
            if (plan.nodes[i].body_of != static_cast<int>(l)) continue;
            const auto& it = result.stats[i].iteration_counts;
            rows = std::max(rows, it.size());
            cols.push_back({i, "wall_seconds", plan.nodes[i].name});
            std::map<std::string, bool> keys;
            for (const auto& c : it)
                for (const auto& [k, v] : c)
                    if (k != "wall_seconds" && k.size() > 8 && k.compare(k.size() - 8, 8, "_seconds") == 0) keys[k] = true;
            for (const auto& [k, unused] : keys)
                cols.push_back({i, k, plan.nodes[i].name + ":" + k.substr(0, k.size() - 8)});
        }
        if (rows == 0) continue;
        char buf[64];
        out += "time per iteration of loop '" + plan.nodes[l].name + "' [s] (columns with ':' are parts of the node before)\n";
        out += "  step";
        for (const Column& c : cols) {
            std::snprintf(buf, sizeof buf, " %*s", static_cast<int>(std::max<std::size_t>(8, c.title.size())), c.title.c_str());
            out += buf;
        }
        out += "     total\n";
        // A long loop shows its first and last steps only (report.json has every recorded one).
        constexpr std::size_t shown = 50;
        for (std::size_t r = 0; r < rows; ++r) {
            if (rows > 2 * shown && r == shown) {
                out += "  ... " + std::to_string(rows - 2 * shown) + " steps not shown (report.json iteration_counts)\n";
                r = rows - shown;
            }
            std::snprintf(buf, sizeof buf, "  %4zu", r);
            out += buf;
            double total = 0;
            for (const Column& c : cols) {
                const auto& it = result.stats[c.node].iteration_counts;
                double v = 0;
                if (r < it.size()) {
                    const auto f = it[r].find(c.key);
                    if (f != it[r].end()) v = f->second;
                }
                if (c.key == "wall_seconds") total += v;
                std::snprintf(buf, sizeof buf, " %*.3f", static_cast<int>(std::max<std::size_t>(8, c.title.size())), v);
                out += buf;
            }
            std::snprintf(buf, sizeof buf, " %9.3f\n", total);
            out += buf;
        }
    }
    return out;
}

}  // namespace cf::runtime
