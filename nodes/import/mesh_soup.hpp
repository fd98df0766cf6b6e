#pragma once
// The raw contents of a mesh file before any repair: vertex positions and polygons exactly as
// the file lists them, each polygon remembering where in the file it came from so that every
// later check can name the FILE and LINE (or byte offset, for binary files) it is about.
#include "nodes/domain/surface_mesh.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cf {

// Any problem with a mesh file; what() is a complete message "file:line: error: ...; fix".
struct MeshFileError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Where something is in a file: a 1-based line for text files, a byte offset for binary ones.
struct FileLocation {
    long long line = 0;         // > 0 for text formats
    long long byte_offset = -1;  // >= 0 for binary formats
};

struct SoupFace {
    std::size_t first = 0;  // into MeshSoup::indices
    std::size_t count = 0;
    FileLocation where;
    int region = -1;        // into MeshSoup::region_names; -1: none named (region 'default')
};

struct MeshSoup {
    std::string file;                 // the path as the user gave it, for messages
    std::vector<Vec3> vertices;       // file units
    std::vector<long long> indices;   // polygon corners as written in the file (see index_base)
    std::vector<SoupFace> faces;
    int index_base = 0;               // 1 for OBJ (indices printed as the file has them)
    bool weld_by_position = false;    // STL stores each facet's corners separately
    std::vector<std::string> region_names;  // named face groups (OBJ g/o/usemtl, PLY face property)
    // Optional texture coordinates and normals (OBJ vt/vn; PLY per-vertex u v / s t and nx ny nz).
    // corner_uv / corner_normal run parallel to `indices`: a 0-based index into uvs / normals, or
    // -1 where the corner has none. Both empty when the file has none.
    std::vector<Vec2> uvs;
    std::vector<Vec3> normals;
    std::vector<long long> corner_uv, corner_normal;
};

// The id of region `name` in soup.region_names, added if new. Throws MeshFileError at `where` for a
// name that boundary conditions could not address (empty, '*', or containing ':' or ';').
int soup_region(MeshSoup& soup, const std::string& name, const FileLocation& where);

// "file.obj:17" or "file.stl: byte 684".
std::string describe(const std::string& file, const FileLocation& where);
// Builds the standard message "file.obj:17: error: <what>; <fix>".
std::string file_error(const std::string& file, const FileLocation& where, const std::string& what,
                       const std::string& fix);
// Same without a location, for whole-file problems: "file.obj: error: <what>; <fix>".
std::string file_error(const std::string& file, const std::string& what, const std::string& fix);

// A token from the file in single quotes, safe to print: control and non-ASCII bytes as \xNN,
// cut to 40 characters.
std::string quote_token(std::string_view token);
// A point as "(x, y, z)", each coordinate as graph::format_number prints it (the shortest text
// that reads back as the same double), so it can be found in the file.
std::string format_point(const Vec3& p);

}  // namespace cf
