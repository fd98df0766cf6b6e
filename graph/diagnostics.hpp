#pragma once
// Source locations and error lists for pipeline files: every problem is reported at once as
// `FILE:LINE:COL: error: message` followed by an optional hint line.
#include <string>
#include <string_view>
#include <vector>

namespace cf::graph {

struct SourceLoc {
    std::string file;
    int line = 0;    // 1-based; 0 = unknown
    int column = 0;  // 1-based
    // Inside a sub-pipeline: where it is used, "FILE:LINE:COL (node 'NAME')" (outermost last,
    // separated by ", used at "); empty in the top file.
    std::string via = {};
};

struct Diagnostic {
    SourceLoc loc;
    std::string message;
    std::string hint;  // e.g. "did you mean 'shape.box'?"
};

std::string format(const Diagnostic& d);

// The closest candidate by edit distance, or "" when nothing is close enough to suggest.
std::string closest_match(const std::string& word, const std::vector<std::string>& candidates);
// "did you mean 'x'?" or a short list of the valid names when nothing is close.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

// A number for a message: the shortest text that reads back as the same double (2.9499e-4 ->
// "0.00029499", 1e-7 -> "1e-07", 0.1 -> "0.1"), so two different values never print alike.
// Messages use this, not std::to_string (%f: 2.9499e-4 and 2.95e-4 both "0.000295", 1e-7
// "0.000000"). Non-finite values print as "nan", "inf", "-inf".
std::string format_number(double v);
// A quantity with its SI unit: format_quantity(2.9499e-4, "m") == "0.00029499 m"; no unit, no space.
std::string format_quantity(double v, std::string_view unit);

}  // namespace cf::graph
