#include "nodes/import/mesh_soup.hpp"

#include "graph/diagnostics.hpp"

namespace cf {

std::string describe(const std::string& file, const FileLocation& where) {
    if (where.line > 0) return file + ":" + std::to_string(where.line);
    if (where.byte_offset >= 0) return file + ": byte " + std::to_string(where.byte_offset);
    return file;
}

std::string file_error(const std::string& file, const FileLocation& where, const std::string& what,
                       const std::string& fix) {
    return describe(file, where) + ": error: " + what + "; " + fix;
}

std::string file_error(const std::string& file, const std::string& what, const std::string& fix) {
    return file + ": error: " + what + "; " + fix;
}

std::string quote_token(std::string_view token) {
    static const char* hex = "0123456789abcdef";
    std::string r = "'";
    for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        if (c >= 32 && c < 127) r += static_cast<char>(c);
        else r += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    }
    if (token.size() > 40) r += "...";
    return r + "'";
}

std::string format_point(const Vec3& p) {
    return "(" + graph::format_number(p.x()) + ", " + graph::format_number(p.y()) + ", " + graph::format_number(p.z()) + ")";
}

int soup_region(MeshSoup& soup, const std::string& name, const FileLocation& where) {
    if (name.empty() || name == "*" || name.find_first_of(":;") != std::string::npos)
        throw MeshFileError(file_error(soup.file, where, "region name " + quote_token(name) + " cannot be used in boundary conditions",
                                       "rename the group or material: no ':' or ';', not '*'"));
    if (name == "default") return -1;  // the region of faces without a name
    for (std::size_t k = 0; k < soup.region_names.size(); ++k)
        if (soup.region_names[k] == name) return static_cast<int>(k);
    soup.region_names.push_back(name);
    return static_cast<int>(soup.region_names.size() - 1);
}

}  // namespace cf
