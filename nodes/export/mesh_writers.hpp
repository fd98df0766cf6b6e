#pragma once
// Writers of cf::SurfaceMesh to common mesh formats, as plain functions on a stream (so other
// stages can write into archives or strings) plus one atomic file-writing entry point.
// ASCII output carries full double precision (shortest round-trip text); binary PLY stores
// doubles; binary STL stores float32 as the format demands.
#include "nodes/domain/surface_mesh.hpp"

#include <filesystem>
#include <ostream>
#include <string>

namespace cf {

enum class MeshFormat { Obj, Off, Ply, Stl, Vtp };

void write_obj(std::ostream& os, const SurfaceMesh& m);
void write_off(std::ostream& os, const SurfaceMesh& m);
void write_ply(std::ostream& os, const SurfaceMesh& m, bool binary);  // binary = little endian
void write_stl(std::ostream& os, const SurfaceMesh& m, bool binary);

// The format for a file extension (".obj", ".OFF", ...); throws std::invalid_argument naming
// the path and the accepted extensions.
MeshFormat mesh_format_from_extension(const std::filesystem::path& path);
// "obj", "off", "ply", "stl", "vtp" -> format; throws std::invalid_argument otherwise.
MeshFormat mesh_format_from_name(const std::string& name);
const char* to_string(MeshFormat f);

// Writes atomically (cf::graph::write_atomically); returns the bytes written. `binary`
// applies to PLY and STL only. VTP gets the "region" cell data and no other fields.
std::uintmax_t write_mesh_file(const std::filesystem::path& path, const SurfaceMesh& m, MeshFormat format,
                               bool binary);

}  // namespace cf
