#pragma once
// Source locations and error lists for pipeline files: every problem is reported at once as
// `FILE:LINE:COL: error: message` followed by an optional hint line.
#include <string>
#include <vector>

namespace cf::graph {

struct SourceLoc {
    std::string file;
    int line = 0;    // 1-based; 0 = unknown
    int column = 0;  // 1-based
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

}  // namespace cf::graph
