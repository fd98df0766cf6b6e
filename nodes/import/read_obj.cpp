// Wavefront OBJ: "v x y z" vertices and "f a b c ..." polygons with 1-based indices, optionally
// "a/t/n"; negative indices count back from the latest vertex (OBJ's relative indices).
// Regions: each face belongs to the name of the latest "g", "o" or "usemtl" line before it (its
// first name; a bare "g" returns to region 'default'), so face groups and materials assigned in a
// modelling tool become boundary regions. Texture coordinates ("vt u v") and normals ("vn x y z")
// referenced by "a/t/n" corners are kept per corner (carried to the fragment meshes); everything
// else (lines, parameter-space vertices) is skipped.
#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

namespace cf {

namespace {

// The 0-based index of an OBJ attribute reference ("t" or "n" of "v/t/n"; negative counts back
// from the latest one), or -1 for an empty, malformed or dangling reference: such a corner has no
// attribute, and a mesh with a corner without one carries none (the geometry is read as before;
// files with stray "v/1/1" references and no vt lines exist in the wild).
long long attribute_index(std::string_view text, std::size_t count) {
    long long idx = 0;
    if (text.empty() || !parse_integer(text, idx) || idx == 0) return -1;
    const long long n = static_cast<long long>(count);
    if (idx < 0) idx = n + idx + 1;
    return idx >= 1 && idx <= n ? idx - 1 : -1;
}

// Texture and normal references of one face corner "v/t/n", "v//n" or "v/t".
void read_corner_attributes(MeshSoup& soup, std::string_view corner) {
    const std::size_t s1 = corner.find('/');
    std::string_view t, n;
    if (s1 != std::string_view::npos) {
        const std::size_t s2 = corner.find('/', s1 + 1);
        t = corner.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
        if (s2 != std::string_view::npos) n = corner.substr(s2 + 1);
    }
    soup.corner_uv.push_back(attribute_index(t, soup.uvs.size()));
    soup.corner_normal.push_back(attribute_index(n, soup.normals.size()));
}

}  // namespace

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
        } else if (tok[0] == "vt") {
            if (tok.size() < 2)
                throw MeshFileError(file_error(file, at, "texture coordinate has no values", "write 'vt u v'"));
            soup.uvs.emplace_back(parse_coordinate(file, ln, tok[1]), tok.size() >= 3 ? parse_coordinate(file, ln, tok[2]) : 0.0);
        } else if (tok[0] == "vn") {
            if (tok.size() < 4)
                throw MeshFileError(file_error(file, at, "normal has " + std::to_string(tok.size() - 1) + " components",
                                               "write normals as 'vn x y z'"));
            soup.normals.emplace_back(parse_coordinate(file, ln, tok[1]), parse_coordinate(file, ln, tok[2]),
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
                read_corner_attributes(soup, tok[k]);
            }
            face.count = soup.indices.size() - face.first;
            soup.faces.push_back(face);
        }
    }
    // No corner references any attribute: the soup has none (keeps plain files cheap).
    auto unused = [](const std::vector<long long>& c) {
        for (long long i : c)
            if (i >= 0) return false;
        return true;
    };
    if (unused(soup.corner_uv)) soup.corner_uv.clear();
    if (unused(soup.corner_normal)) soup.corner_normal.clear();
    return soup;
}

}  // namespace cf
