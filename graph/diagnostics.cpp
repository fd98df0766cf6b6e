#include "graph/diagnostics.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace cf::graph {

std::string format(const Diagnostic& d) {
    std::string s = d.loc.file.empty() ? std::string("<pipeline>") : d.loc.file;
    if (d.loc.line > 0) s += ":" + std::to_string(d.loc.line) + ":" + std::to_string(d.loc.column);
    s += ": error: " + d.message;
    if (!d.loc.via.empty()) s += "\n  in a sub-pipeline used at " + d.loc.via;
    if (!d.hint.empty()) s += "\n  hint: " + d.hint;
    return s;
}

std::string format_number(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    std::array<char, 32> buf;  // the longest shortest form of a double is 24 characters
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), r.ptr);
}

std::string format_quantity(double v, std::string_view unit) {
    std::string s = format_number(v);
    if (!unit.empty()) s += " " + std::string(unit);
    return s;
}

static std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j)
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

std::string closest_match(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best;
    std::size_t best_d = std::string::npos;
    for (const auto& c : candidates) {
        std::size_t d = edit_distance(word, c);
        if (d < best_d) best_d = d, best = c;
    }
    // Close enough: at most a third of the word's letters differ (and at least one typo allowed).
    if (best_d <= std::max<std::size_t>(2, word.size() / 3)) return best;
    return "";
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
    std::string best = closest_match(word, candidates);
    if (!best.empty()) return "did you mean '" + best + "'?";
    if (candidates.empty()) return "";
    std::string list;
    std::size_t shown = std::min<std::size_t>(candidates.size(), 12);
    for (std::size_t i = 0; i < shown; ++i) list += (i ? ", " : "") + candidates[i];
    if (shown < candidates.size()) list += ", ...";
    return "valid names: " + list;
}

}  // namespace cf::graph
