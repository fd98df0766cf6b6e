#pragma once
// One reader per file format. Each turns the file's bytes into a MeshSoup, rejecting anything
// it cannot parse with a MeshFileError naming the file and line (or byte offset). They check
// declared sizes against the bytes actually present before allocating anything, so a header
// claiming 4e9 faces costs nothing. Topology is checked later, by build_surface_mesh.
#include "nodes/import/mesh_soup.hpp"

#include <string>
#include <string_view>

namespace cf {

// `file` is used only in messages; `bytes` is the whole file.
MeshSoup read_obj_soup(const std::string& file, std::string_view bytes);
MeshSoup read_off_soup(const std::string& file, std::string_view bytes);
MeshSoup read_ply_soup(const std::string& file, std::string_view bytes);   // ascii, binary LE/BE
MeshSoup read_stl_soup(const std::string& file, std::string_view bytes);   // ascii or binary

// Parses one vertex coordinate token, rejecting non-numbers and NaN/Inf with a message.
double parse_coordinate(const std::string& file, long long line, std::string_view token);

}  // namespace cf
