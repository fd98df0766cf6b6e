#pragma once
// Reading a triangle surface from OBJ, OFF, PLY (ascii / binary little or big endian) or STL
// (ascii / binary) into a cf::SurfaceMesh, with every problem reported as
// "file.obj:17: error: <what>; <how to fix>" (a MeshFileError).
#include "nodes/import/mesh_soup.hpp"

#include <filesystem>

namespace cf {

struct ImportOptions {
    bool reorient = false;        // re-orient inconsistent or inside-out shells instead of failing
    double scale = 1.0;           // metres per file unit; > 0
    double weld_tolerance = 0.0;  // metres; > 0 merges vertices closer than this (any format).
                                  // STL is always welded by exact position.
};

struct ImportReport {
    std::size_t file_vertices = 0, file_faces = 0;  // as listed in the file
    std::size_t welded_vertices = 0;                // merged into an earlier vertex
    std::size_t unreferenced_vertices = 0;          // used by no face, dropped
    std::size_t flipped_triangles = 0;              // re-oriented (reorient only)
    std::size_t components = 0;                     // closed shells
};

struct ImportedMesh {
    SurfaceMesh mesh;
    ImportReport report;
};

// Polygons with more than 3 corners are fan-triangulated (corner 0 with each consecutive
// pair). Vertices are kept in file order, minus welded and unreferenced ones; every triangle
// gets region 0, named "default". The result is checked with check_closed_surface.
ImportedMesh build_surface_mesh(const MeshSoup& soup, const ImportOptions& options);

// Picks the reader by extension (.obj, .off, .ply, .stl; any case).
ImportedMesh read_mesh_file(const std::filesystem::path& path, const ImportOptions& options = {});
SurfaceMesh read_mesh(const std::filesystem::path& path, const ImportOptions& options = {});

// The parser alone, for callers that have the bytes already (tests, archives).
MeshSoup read_mesh_soup(const std::string& file, const std::string& extension, std::string_view bytes);

}  // namespace cf
