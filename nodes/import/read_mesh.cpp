#include "nodes/import/read_mesh.hpp"

#include "graph/machine_memory.hpp"
#include "nodes/import/soup_readers.hpp"

#include <cctype>
#include <fstream>
#include <sstream>
#include <system_error>

namespace cf {

namespace {

// Peak memory of an import per byte of the file, rounded up from measurements (peak resident size
// less that of an empty run, over the file size) on a 940800-triangle box written by export.mesh:
// binary STL 47.0 MB -> 7.55, binary PLY 27.3 MB -> 8.55, OBJ 42.0 MB -> 5.95 (2026-12-02). It
// covers the bytes themselves, the polygon soup, the mesh and its topology and orientation checks.
// Binary PLY is the densest file per triangle, so the worst per byte; ASCII PLY is counted as it.
constexpr double kImportBytesPerByteStl = 8;
constexpr double kImportBytesPerBytePly = 9;
constexpr double kImportBytesPerByteText = 6;  // OBJ, OFF

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

double import_bytes_per_file_byte(const std::string& ext) {
    return ext == ".stl" ? kImportBytesPerByteStl : ext == ".ply" ? kImportBytesPerBytePly : kImportBytesPerByteText;
}

// Refuses a file whose import would not fit in the memory this process may use, before reading it
// (it was read whole and then failed with a bare std::bad_alloc).
void check_import_memory(const std::string& file, std::uintmax_t size, const std::string& ext) {
    const double need = double(size) * import_bytes_per_file_byte(ext), have = available_memory_bytes();
    if (have > 0 && need > 0.8 * have) {
        std::ostringstream what;
        what.precision(3);
        what << "importing this " << double(size) / 1e9 << " GB file needs about " << need / 1e9 << " GB of memory, more than the "
             << have / 1e9 << " GB this process may use (physical memory, or a ulimit)";
        throw MeshFileError(file_error(file, what.str(), "simplify the mesh before importing it, or run where more memory is available"));
    }
}

std::string read_bytes(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw MeshFileError(file_error(file, std::filesystem::exists(path, ec) ? "not a regular file" : "file not found",
                                       "check the path (relative paths are relative to the working directory)"));
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw MeshFileError(file_error(file, "cannot get the file size: " + ec.message(), "check permissions"));
    if (size == 0) throw MeshFileError(file_error(file, "file is empty (0 bytes)", "re-export the mesh"));
    check_import_memory(file, size, lower(path.extension().string()));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw MeshFileError(file_error(file, "cannot open the file for reading", "check permissions"));
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) != size)
        throw MeshFileError(file_error(file, "read error (file changed while reading?)", "try again"));
    return bytes;
}

}  // namespace

MeshSoup read_mesh_soup(const std::string& file, const std::string& extension, std::string_view bytes) {
    const std::string ext = lower(extension);
    if (bytes.empty()) throw MeshFileError(file_error(file, "file is empty (0 bytes)", "re-export the mesh"));
    if (ext == ".obj") return read_obj_soup(file, bytes);
    if (ext == ".off") return read_off_soup(file, bytes);
    if (ext == ".ply") return read_ply_soup(file, bytes);
    if (ext == ".stl") return read_stl_soup(file, bytes);
    throw MeshFileError(file_error(file, "unknown mesh file extension " + quote_token(extension),
                                   "use a .obj, .off, .ply or .stl file"));
}

ImportedMesh read_mesh_file(const std::filesystem::path& path, const ImportOptions& options) {
    const std::string ext = path.extension().string();
    const std::string l = lower(ext);
    if (l != ".obj" && l != ".off" && l != ".ply" && l != ".stl")  // before reading a large file
        throw MeshFileError(file_error(path.string(), "unknown mesh file extension '" + ext + "'",
                                       "use a .obj, .off, .ply or .stl file"));
    const std::string bytes = read_bytes(path);
    return build_surface_mesh(read_mesh_soup(path.string(), ext, bytes), options);
}

SurfaceMesh read_mesh(const std::filesystem::path& path, const ImportOptions& options) {
    return read_mesh_file(path, options).mesh;
}

}  // namespace cf
