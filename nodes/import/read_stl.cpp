// STL, ASCII ("solid ... facet normal ... outer loop / vertex x y z ... endloop endfacet ...
// endsolid") or binary (80-byte header, uint32 triangle count, 50 bytes per triangle, little
// endian). Each facet lists its own corners, so the soup asks for welding by exact position.
// A file is binary when its size is exactly 84 + 50 * count; otherwise it must start with
// "solid" (binary headers sometimes start with "solid" too, hence the size test first).
#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace cf {

namespace {

std::uint32_t load_u32(const char* p) {
    std::uint32_t u = 0;
    for (int k = 0; k < 4; ++k) u |= std::uint32_t(static_cast<unsigned char>(p[k])) << (8 * k);
    return u;
}

float load_f32(const char* p) {
    std::uint32_t u = load_u32(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

MeshSoup read_binary(const std::string& file, std::string_view bytes) {
    MeshSoup soup;
    soup.file = file;
    soup.weld_by_position = true;
    const std::uint64_t n = load_u32(bytes.data() + 80);
    for (std::uint64_t t = 0; t < n; ++t) {
        const std::size_t at = 84 + 50 * static_cast<std::size_t>(t);
        SoupFace face{soup.indices.size(), 3, FileLocation{0, static_cast<long long>(at)}};
        for (int c = 0; c < 3; ++c) {
            const char* p = bytes.data() + at + 12 + 12 * c;
            Vec3 v(load_f32(p), load_f32(p + 4), load_f32(p + 8));
            if (!v.allFinite())
                throw MeshFileError(file_error(file, face.where,
                                               "triangle " + std::to_string(t) + " has a NaN or infinite coordinate",
                                               "replace NaN/Inf coordinates with finite values (re-export the mesh)"));
            soup.indices.push_back(static_cast<long long>(soup.vertices.size()));
            soup.vertices.push_back(v);
        }
        soup.faces.push_back(face);
    }
    return soup;
}

MeshSoup read_ascii(const std::string& file, std::string_view bytes) {
    MeshSoup soup;
    soup.file = file;
    soup.weld_by_position = true;
    TextScanner scan(bytes);
    std::string_view line;
    std::vector<std::string_view> tok;
    enum class State { Outside, InSolid, InFacet, InLoop, AfterLoop } state = State::Outside;
    SoupFace face;
    auto expect = [&](const std::string& what) {
        return MeshFileError(file_error(file, FileLocation{scan.line_number(), -1}, "expected " + what,
                                        "fix the ASCII STL structure (solid / facet normal / outer loop / vertex x3 / "
                                        "endloop / endfacet / endsolid)"));
    };
    while (scan.next_line(line)) {
        split_tokens(line, tok);
        if (tok.empty()) continue;
        const FileLocation at{scan.line_number(), -1};
        switch (state) {
            case State::Outside:
                if (tok[0] != "solid") throw expect("'solid'");
                state = State::InSolid;
                break;
            case State::InSolid:
                if (tok[0] == "endsolid") state = State::Outside;
                else if (tok[0] == "facet") {
                    face = SoupFace{soup.indices.size(), 0, at};
                    state = State::InFacet;
                } else
                    throw expect("'facet normal' or 'endsolid'");
                break;
            case State::InFacet:
                if (tok.size() < 2 || tok[0] != "outer" || tok[1] != "loop") throw expect("'outer loop'");
                state = State::InLoop;
                break;
            case State::InLoop:
                if (tok[0] == "vertex") {
                    if (tok.size() != 4) throw expect("'vertex x y z'");
                    soup.indices.push_back(static_cast<long long>(soup.vertices.size()));
                    soup.vertices.emplace_back(parse_coordinate(file, at.line, tok[1]), parse_coordinate(file, at.line, tok[2]),
                                               parse_coordinate(file, at.line, tok[3]));
                } else if (tok[0] == "endloop") {
                    face.count = soup.indices.size() - face.first;
                    soup.faces.push_back(face);
                    state = State::AfterLoop;
                } else
                    throw expect("'vertex x y z' or 'endloop'");
                break;
            case State::AfterLoop:
                if (tok[0] != "endfacet") throw expect("'endfacet'");
                state = State::InSolid;
                break;
        }
    }
    if (state != State::Outside)
        throw MeshFileError(file_error(file, "file ends inside a solid (no 'endsolid'; truncated?)",
                                       "re-export the file"));
    return soup;
}

bool starts_with_solid(std::string_view bytes) {
    std::size_t i = 0;
    while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n')) ++i;
    return bytes.substr(i, 5) == "solid";
}

}  // namespace

MeshSoup read_stl_soup(const std::string& file, std::string_view bytes) {
    if (bytes.size() >= 84) {
        // Compare the claimed count with the size before touching any triangle, so a header
        // claiming 4e9 triangles allocates nothing.
        const std::uint64_t n = load_u32(bytes.data() + 80);
        const std::uint64_t expected = 84 + 50 * n;
        if (expected == bytes.size()) return read_binary(file, bytes);
        if (!starts_with_solid(bytes))
            throw MeshFileError(file_error(file,
                                           "binary STL header declares " + std::to_string(n) + " triangles, which need " +
                                               std::to_string(expected) + " bytes, but the file has " +
                                               std::to_string(bytes.size()) +
                                               (expected > bytes.size() ? " bytes (truncated?)" : " bytes (extra data at the end)"),
                                           "re-export the file; it is damaged or not an STL file"));
    } else if (!starts_with_solid(bytes)) {
        throw MeshFileError(file_error(file,
                                       "file has " + std::to_string(bytes.size()) +
                                           " bytes: too short for binary STL (84-byte header) and not ASCII STL (no 'solid')",
                                       "re-export the file; it is truncated or not an STL file"));
    }
    return read_ascii(file, bytes);
}

}  // namespace cf
