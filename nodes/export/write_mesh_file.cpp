#include "graph/atomic_write.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/vtp_writer.hpp"

#include <cctype>
#include <stdexcept>

namespace cf {

MeshFormat mesh_format_from_name(const std::string& name) {
    if (name == "obj") return MeshFormat::Obj;
    if (name == "off") return MeshFormat::Off;
    if (name == "ply") return MeshFormat::Ply;
    if (name == "stl") return MeshFormat::Stl;
    if (name == "vtp") return MeshFormat::Vtp;
    if (name == "glb") return MeshFormat::Glb;
    throw std::invalid_argument("unknown mesh format '" + name + "'; use obj, off, ply, stl, vtp or glb");
}

MeshFormat mesh_format_from_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext.size() > 1) {
        try {
            return mesh_format_from_name(ext.substr(1));
        } catch (const std::invalid_argument&) {
        }
    }
    throw std::invalid_argument("cannot tell the mesh format of '" + path.string() +
                                "' from its extension; name it .obj, .off, .ply, .stl, .vtp or .glb, or set format");
}

const char* to_string(MeshFormat f) {
    switch (f) {
        case MeshFormat::Obj: return "obj";
        case MeshFormat::Off: return "off";
        case MeshFormat::Ply: return "ply";
        case MeshFormat::Stl: return "stl";
        case MeshFormat::Vtp: return "vtp";
        case MeshFormat::Glb: return "glb";
    }
    return "?";
}

std::uintmax_t write_mesh_file(const std::filesystem::path& path, const SurfaceMesh& m, MeshFormat format,
                               bool binary) {
    graph::write_atomically(path, [&](std::ostream& os) {
        switch (format) {
            case MeshFormat::Obj: write_obj(os, m); break;
            case MeshFormat::Off: write_off(os, m); break;
            case MeshFormat::Ply: write_ply(os, m, binary); break;
            case MeshFormat::Stl: write_stl(os, m, binary); break;
            case MeshFormat::Vtp: write_vtp(os, m); break;
            case MeshFormat::Glb: write_glb(os, m, path.stem().string(), {}); break;
        }
    });
    return std::filesystem::file_size(path);
}

}  // namespace cf
