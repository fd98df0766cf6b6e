// Object File Format: "OFF" (or COFF/NOFF/CNOFF/STOFF variants, whose extra per-vertex values
// are ignored), then "nV nF nE", nV vertex lines "x y z ...", nF face lines "n i0 ... i(n-1)"
// with 0-based indices. Comments start with '#'. Binary OFF is not supported.
#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

namespace cf {

namespace {

bool next_data_line(TextScanner& scan, std::vector<std::string_view>& tok) {
    std::string_view line;
    while (scan.next_line(line)) {
        split_tokens(strip_comment(line, '#'), tok);
        if (!tok.empty()) return true;
    }
    return false;
}

bool is_off_keyword(std::string_view t) {
    return t == "OFF" || t == "COFF" || t == "NOFF" || t == "CNOFF" || t == "STOFF" || t == "STCOFF" ||
           t == "STNOFF" || t == "STCNOFF";
}

}  // namespace

MeshSoup read_off_soup(const std::string& file, std::string_view bytes) {
    MeshSoup soup;
    soup.file = file;
    TextScanner scan(bytes);
    std::vector<std::string_view> tok;
    if (!next_data_line(scan, tok) || !is_off_keyword(tok[0]))
        throw MeshFileError(file_error(file, FileLocation{std::max(1LL, scan.line_number()), -1},
                                       "missing 'OFF' header line",
                                       "an OFF file starts with the line OFF (binary and 4D OFF are not supported)"));
    // The counts may share the header line ("OFF 8 12 0") or follow on the next line.
    tok.erase(tok.begin());
    if (tok.empty() && !next_data_line(scan, tok))
        throw MeshFileError(file_error(file, "file ends after the OFF header (truncated?)",
                                       "add the line 'nVertices nFaces nEdges' and the data"));
    if (tok.size() == 1 && tok[0] == "BINARY")
        throw MeshFileError(file_error(file, FileLocation{scan.line_number(), -1}, "binary OFF is not supported",
                                       "convert the file to ASCII OFF, OBJ, PLY or STL"));
    long long nv = 0, nf = 0;
    const FileLocation counts_at{scan.line_number(), -1};
    if (tok.size() < 2 || !parse_integer(tok[0], nv) || !parse_integer(tok[1], nf) || nv < 0 || nf < 0)
        throw MeshFileError(file_error(file, counts_at, "expected vertex and face counts 'nV nF nE'",
                                       "write the counts as non-negative integers after the OFF line"));
    // Each vertex needs at least 6 bytes ("0 0 0\n"), each face at least 8 ("3 0 1 2\n").
    const long long remaining = static_cast<long long>(bytes.size() - scan.position());
    if (nv > remaining / 6 + 1 || nf > remaining / 8 + 1)
        throw MeshFileError(file_error(file, counts_at,
                                       "header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                           " faces but only " + std::to_string(remaining) + " bytes follow (truncated?)",
                                       "re-export the file or fix the counts"));
    soup.vertices.reserve(static_cast<std::size_t>(nv));
    soup.faces.reserve(static_cast<std::size_t>(nf));
    for (long long i = 0; i < nv; ++i) {
        if (!next_data_line(scan, tok))
            throw MeshFileError(file_error(file, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
                                                     " vertices (truncated?)",
                                           "re-export the file or fix the vertex count in the header"));
        const long long ln = scan.line_number();
        if (tok.size() < 3)
            throw MeshFileError(file_error(file, FileLocation{ln, -1}, "vertex line has " + std::to_string(tok.size()) +
                                                                           " values, expected 3",
                                           "write vertices as 'x y z'"));
        soup.vertices.emplace_back(parse_coordinate(file, ln, tok[0]), parse_coordinate(file, ln, tok[1]),
                                   parse_coordinate(file, ln, tok[2]));
    }
    for (long long i = 0; i < nf; ++i) {
        if (!next_data_line(scan, tok))
            throw MeshFileError(file_error(file, "file ends after " + std::to_string(i) + " of " + std::to_string(nf) +
                                                     " faces (truncated?)",
                                           "re-export the file or fix the face count in the header"));
        const FileLocation at{scan.line_number(), -1};
        long long n = 0;
        if (!parse_integer(tok[0], n) || n < 0)
            throw MeshFileError(file_error(file, at, "face line must start with its vertex count, got " +
                                                         quote_token(tok[0]),
                                           "write faces as 'n i0 i1 ... i(n-1)'"));
        if (static_cast<long long>(tok.size()) - 1 < n)
            throw MeshFileError(file_error(file, at, "face declares " + std::to_string(n) + " vertices but lists " +
                                                         std::to_string(tok.size() - 1),
                                           "fix the face line"));
        SoupFace face{soup.indices.size(), static_cast<std::size_t>(n), at};
        for (long long k = 1; k <= n; ++k) {
            long long idx = 0;
            if (!parse_integer(tok[k], idx))
                throw MeshFileError(file_error(file, at, "face index " + quote_token(tok[k]) + " is not an integer",
                                               "fix the index"));
            soup.indices.push_back(idx);
        }
        soup.faces.push_back(face);
    }
    return soup;
}

}  // namespace cf
