#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

#include <cmath>

namespace cf {

double parse_coordinate(const std::string& file, long long line, std::string_view token) {
    double v = 0;
    FileLocation at{line, -1};
    if (!parse_real(token, v))
        throw MeshFileError(file_error(file, at, quote_token(token) + " is not a finite number",
                                       "vertex coordinates must be decimal numbers such as 0.25 or -1e-3"));
    if (!std::isfinite(v))
        throw MeshFileError(file_error(file, at, "vertex coordinate is " + std::string(token.substr(0, 40)),
                                       "replace NaN/Inf coordinates with finite values (re-export the mesh)"));
    return v;
}

}  // namespace cf
