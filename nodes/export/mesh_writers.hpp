#pragma once
// Writers of cf::SurfaceMesh to common mesh formats, as plain functions on a stream (so other
// stages can write into archives or strings) plus one atomic file-writing entry point.
// ASCII output carries full double precision (shortest round-trip text); binary PLY stores
// doubles; binary STL stores float32 as the format demands.
#include "nodes/domain/surface_mesh.hpp"

#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace cf {

enum class MeshFormat { Obj, Off, Ply, Stl, Vtp, Glb };

void write_obj(std::ostream& os, const SurfaceMesh& m);
// With texture coordinates and normals when the mesh has them (vt/vn per distinct value), and,
// when `mtllib` is not empty, "mtllib <mtllib>" and "usemtl <region name>" beside each group.
void write_obj(std::ostream& os, const SurfaceMesh& m, const std::string& mtllib);
// A Wavefront material library: one diffuse colour (RGB in [0, 1]) per material name.
void write_mtl(std::ostream& os, const std::vector<std::pair<std::string, Vec3>>& materials);
// glTF 2.0 binary: one mesh, one primitive per region with a material of the region's name
// (colours from `colours`, by region name; grey when absent), POSITION, NORMAL (the corner normals,
// or flat) and TEXCOORD_0 when the mesh has UVs (v flipped: glTF's origin is the top left).
void write_glb(std::ostream& os, const SurfaceMesh& m, const std::string& name,
               const std::vector<std::pair<std::string, Vec3>>& colours);
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
