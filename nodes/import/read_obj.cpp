// Wavefront OBJ: "v x y z" vertices and "f a b c ..." polygons with 1-based indices, optionally
// "a/t/n"; negative indices count back from the latest vertex (OBJ's relative indices).
// Regions: each face belongs to the name of the latest "g", "o" or "usemtl" line before it (its
// first name; a bare "g" returns to region 'default'), so face groups and materials assigned in a
// modelling tool become boundary regions. Everything else (normals, texture coordinates, lines) is
// skipped.
#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

namespace cf {

MeshSoup read_obj_soup(const std::string& file, std::string_view bytes) {
    MeshSoup soup;
    soup.file = file;
    soup.index_base = 1;
    TextScanner scan(bytes);
    std::string_view line;
    std::vector<std::string_view> tok;
    int region = -1;  // the current group/object/material; -1: none yet
    while (scan.next_line(line)) {
        split_tokens(strip_comment(line, '#'), tok);
        if (tok.empty()) continue;
        const long long ln = scan.line_number();
        const FileLocation at{ln, -1};
        if (tok[0] == "v") {
            if (tok.size() < 4)
                throw MeshFileError(file_error(file, at, "vertex has " + std::to_string(tok.size() - 1) + " coordinates",
                                               "write vertices as 'v x y z'"));
            soup.vertices.emplace_back(parse_coordinate(file, ln, tok[1]), parse_coordinate(file, ln, tok[2]),
                                       parse_coordinate(file, ln, tok[3]));
        } else if (tok[0] == "g" || tok[0] == "o" || tok[0] == "usemtl") {
            region = tok.size() >= 2 ? soup_region(soup, std::string(tok[1]), at) : -1;
        } else if (tok[0] == "f") {
            SoupFace face{soup.indices.size(), 0, at, region};
            for (std::size_t k = 1; k < tok.size(); ++k) {
                std::string_view v = tok[k].substr(0, tok[k].find('/'));
                long long idx = 0;
                if (!parse_integer(v, idx))
                    throw MeshFileError(file_error(file, at, "face corner " + quote_token(tok[k]) + " is not a vertex index",
                                                   "write faces as 'f 1 2 3' or 'f 1/1/1 2/2/2 3/3/3'"));
                if (idx == 0)
                    throw MeshFileError(file_error(file, at, "face index 0 is invalid (OBJ indices start at 1)",
                                                   "fix the index"));
                if (idx < 0) {
                    const long long nv = static_cast<long long>(soup.vertices.size());
                    if (-idx > nv)
                        throw MeshFileError(file_error(
                            file, at,
                            "relative face index " + std::to_string(idx) + " points before the first vertex (only " +
                                std::to_string(nv) + " vertices defined so far)",
                            "fix the index"));
                    idx = nv + idx + 1;
                }
                soup.indices.push_back(idx);
            }
            face.count = soup.indices.size() - face.first;
            soup.faces.push_back(face);
        }
    }
    return soup;
}

}  // namespace cf
