// Stanford PLY: a text header declaring elements and their properties, then the data as ASCII,
// binary little-endian or binary big-endian. We read element "vertex" (properties x, y, z of
// any numeric type) and element "face" (list property vertex_indices or vertex_index of an
// integer type); every other element and property is parsed and skipped. Regions: an integer
// face property named region, material_index, material or group (the first of these present, in
// this order) gives each face the region '<property><value>', e.g. region3 or material0.
// Per-vertex texture coordinates (u v, s t or texture_u texture_v) and normals (nx ny nz) are kept
// and given to every corner of the vertex (carried to the fragment meshes).
#include "nodes/import/soup_readers.hpp"
#include "nodes/import/text_scanner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

namespace cf {

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parse_type(std::string_view s, PlyType& t) {
    if (s == "char" || s == "int8") t = PlyType::Int8;
    else if (s == "uchar" || s == "uint8") t = PlyType::UInt8;
    else if (s == "short" || s == "int16") t = PlyType::Int16;
    else if (s == "ushort" || s == "uint16") t = PlyType::UInt16;
    else if (s == "int" || s == "int32") t = PlyType::Int32;
    else if (s == "uint" || s == "uint32") t = PlyType::UInt32;
    else if (s == "float" || s == "float32") t = PlyType::Float32;
    else if (s == "double" || s == "float64") t = PlyType::Float64;
    else return false;
    return true;
}

std::size_t type_size(PlyType t) {
    switch (t) {
        case PlyType::Int8: case PlyType::UInt8: return 1;
        case PlyType::Int16: case PlyType::UInt16: return 2;
        case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 1;
}

bool is_integer_type(PlyType t) { return t != PlyType::Float32 && t != PlyType::Float64; }

struct Property {
    std::string name;
    PlyType type = PlyType::Float32;
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;
};

struct Element {
    std::string name;
    long long count = 0;
    std::vector<Property> props;
    long long header_line = 0;
};

enum class Encoding { Ascii, BinaryLittle, BinaryBig };

// A number read from the data section: integers exactly, floats as double.
struct Number {
    bool is_integer = true;
    long long i = 0;
    double d = 0;
    double real() const { return is_integer ? static_cast<double>(i) : d; }
};

class BinaryCursor {
public:
    BinaryCursor(const std::string& file, std::string_view bytes, std::size_t pos, bool big)
        : file_(file), bytes_(bytes), pos_(pos), big_(big) {}

    Number read(PlyType t, const char* what) {
        const std::size_t n = type_size(t);
        if (bytes_.size() - pos_ < n)
            throw MeshFileError(file_error(file_, FileLocation{0, static_cast<long long>(pos_)},
                                           std::string("file ends inside ") + what + " (truncated?)",
                                           "re-export the file or fix the element counts in the header"));
        unsigned char b[8];
        std::memcpy(b, bytes_.data() + pos_, n);
        pos_ += n;
        if (big_) std::reverse(b, b + n);  // to little-endian order
        std::uint64_t u = 0;
        for (std::size_t k = 0; k < n; ++k) u |= std::uint64_t(b[k]) << (8 * k);
        Number r;
        switch (t) {
            case PlyType::Int8: r.i = static_cast<std::int8_t>(u); break;
            case PlyType::UInt8: r.i = static_cast<std::uint8_t>(u); break;
            case PlyType::Int16: r.i = static_cast<std::int16_t>(u); break;
            case PlyType::UInt16: r.i = static_cast<std::uint16_t>(u); break;
            case PlyType::Int32: r.i = static_cast<std::int32_t>(u); break;
            case PlyType::UInt32: r.i = static_cast<std::uint32_t>(u); break;
            case PlyType::Float32: {
                float f;
                std::uint32_t u32 = static_cast<std::uint32_t>(u);
                std::memcpy(&f, &u32, 4);
                r.is_integer = false;
                r.d = f;
                break;
            }
            case PlyType::Float64: {
                r.is_integer = false;
                std::memcpy(&r.d, &u, 8);
                break;
            }
        }
        return r;
    }
    std::size_t position() const { return pos_; }
    std::size_t remaining() const { return bytes_.size() - pos_; }

private:
    const std::string& file_;
    std::string_view bytes_;
    std::size_t pos_;
    bool big_;
};

// Tokens of the ASCII data section, crossing lines freely but remembering each token's line.
class AsciiCursor {
public:
    AsciiCursor(const std::string& file, std::string_view bytes, std::size_t pos, long long first_line)
        : file_(file), scan_(bytes, pos), line_offset_(first_line) {}

    // The line the next token is on (the line after the data when none is left).
    long long peek_line() {
        return refill() ? line() : line() + 1;
    }

    Number read(PlyType t, const char* what) {
        if (!refill())
            throw MeshFileError(file_error(file_, FileLocation{line(), -1},
                                           std::string("file ends inside ") + what + " (truncated?)",
                                           "re-export the file or fix the element counts in the header"));
        std::string_view s = tok_[next_++];
        Number r;
        if (is_integer_type(t)) {
            if (!parse_integer(s, r.i))
                throw MeshFileError(file_error(file_, FileLocation{line(), -1},
                                               std::string(what) + " " + quote_token(s) + " is not an integer",
                                               "fix the value or the property type in the header"));
        } else {
            r.is_integer = false;
            if (!parse_real(s, r.d))
                throw MeshFileError(file_error(file_, FileLocation{line(), -1},
                                               std::string(what) + " " + quote_token(s) + " is not a finite number",
                                               "fix the value"));
        }
        return r;
    }
    long long line() const { return line_offset_ + scan_.line_number(); }

private:
    bool refill() {
        while (next_ >= tok_.size()) {
            std::string_view line;
            if (!scan_.next_line(line)) return false;
            split_tokens(line, tok_);
            next_ = 0;
        }
        return true;
    }

    const std::string& file_;
    TextScanner scan_;
    long long line_offset_;
    std::vector<std::string_view> tok_;
    std::size_t next_ = 0;
};

// The face property that names regions (see the file comment), or -1.
int face_region_property(const Element& face) {
    for (const char* name : {"region", "material_index", "material", "group"})
        for (int p = 0; p < static_cast<int>(face.props.size()); ++p)
            if (!face.props[p].is_list && face.props[p].name == name && is_integer_type(face.props[p].type)) return p;
    return -1;
}

template <class Cursor>
void read_elements(MeshSoup& soup, const std::vector<Element>& elements, Cursor& cur,
                   const std::function<FileLocation()>& here) {
    for (const Element& e : elements) {
        const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
        int ix = -1, iy = -1, iz = -1, iface = -1, iregion = -1, iu = -1, iv = -1, inx = -1, iny = -1, inz = -1;
        if (is_face) iregion = face_region_property(e);
        for (int p = 0; p < static_cast<int>(e.props.size()); ++p) {
            const std::string& n = e.props[p].name;
            if (is_vertex && !e.props[p].is_list) {
                if (n == "x") ix = p;
                if (n == "y") iy = p;
                if (n == "z") iz = p;
                if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") iu = p;
                if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") iv = p;
                if (n == "nx") inx = p;
                if (n == "ny") iny = p;
                if (n == "nz") inz = p;
            }
            if (is_face && e.props[p].is_list && (n == "vertex_indices" || n == "vertex_index")) iface = p;
        }
        const bool has_uv = iu >= 0 && iv >= 0, has_normal = inx >= 0 && iny >= 0 && inz >= 0;
        for (long long i = 0; i < e.count; ++i) {
            Vec3 v = Vec3::Zero(), normal = Vec3::Zero();
            Vec2 uv = Vec2::Zero();
            const FileLocation at = here();
            SoupFace face{soup.indices.size(), 0, at};
            for (int p = 0; p < static_cast<int>(e.props.size()); ++p) {
                const Property& pr = e.props[p];
                if (!pr.is_list) {
                    Number x = cur.read(pr.type, "property value");
                    if (p == ix) v.x() = x.real();
                    if (p == iy) v.y() = x.real();
                    if (p == iz) v.z() = x.real();
                    if (p == iu) uv.x() = x.real();
                    if (p == iv) uv.y() = x.real();
                    if (p == inx) normal.x() = x.real();
                    if (p == iny) normal.y() = x.real();
                    if (p == inz) normal.z() = x.real();
                    if (p == iregion) face.region = soup_region(soup, pr.name + std::to_string(x.i), at);
                    continue;
                }
                Number n = cur.read(pr.count_type, "list length");
                if (n.i < 0)
                    throw MeshFileError(file_error(soup.file, here(), "negative list length " + std::to_string(n.i),
                                                   "fix the file (it is probably corrupt)"));
                for (long long k = 0; k < n.i; ++k) {
                    Number x = cur.read(pr.type, "list entry");
                    if (p == iface) soup.indices.push_back(x.i);
                }
                if (p == iface) face.count = static_cast<std::size_t>(n.i);
            }
            if (is_vertex) {
                if (!std::isfinite(v.x()) || !std::isfinite(v.y()) || !std::isfinite(v.z()))
                    throw MeshFileError(file_error(soup.file, at,
                                                   "vertex " + std::to_string(i) + " has a NaN or infinite coordinate",
                                                   "replace NaN/Inf coordinates with finite values (re-export the mesh)"));
                soup.vertices.push_back(v);
                if (has_uv) soup.uvs.push_back(uv);
                if (has_normal) soup.normals.push_back(normal);
            }
            if (is_face) soup.faces.push_back(face);
        }
    }
}

// read_ply_soup's steps, in the order it calls them.

struct PlyHeader {
    Encoding enc = Encoding::Ascii;
    std::vector<Element> elements;
};

// The header, line by line up to end_header; errors name the current line.
class HeaderReader {
public:
    HeaderReader(const std::string& file, TextScanner& scan) : file_(file), scan_(scan) {}

    PlyHeader read() {
        std::string_view line;
        if (!scan_.next_line(line) || line != "ply") throw error("missing 'ply' magic line", "a PLY file starts with the line ply");
        PlyHeader h;
        bool have_format = false, ended = false;
        while (scan_.next_line(line)) {
            split_tokens(line, tok_);
            if (tok_.empty()) continue;
            if (tok_[0] == "comment" || tok_[0] == "obj_info") continue;
            if (tok_[0] == "end_header") {
                ended = true;
                break;
            }
            if (tok_[0] == "format") {
                h.enc = format();
                have_format = true;
            } else if (tok_[0] == "element") {
                h.elements.push_back(element());
            } else if (tok_[0] == "property") {
                if (h.elements.empty()) throw error("property before any element", "declare the element first");
                h.elements.back().props.push_back(property(h.elements.back()));
            } else {
                throw error("unknown header keyword " + quote_token(tok_[0]),
                            "the header may contain only format, element, property, comment and obj_info lines");
            }
        }
        if (!ended) throw error("header has no end_header line (truncated?)", "re-export the file");
        if (!have_format) throw error("header has no format line", "add e.g. 'format ascii 1.0'");
        return h;
    }

private:
    MeshFileError error(const std::string& what, const std::string& fix) const {
        return MeshFileError(file_error(file_, FileLocation{std::max(1LL, scan_.line_number()), -1}, what, fix));
    }

    Encoding format() const {
        if (tok_.size() < 2) throw error("incomplete format line", "write e.g. 'format ascii 1.0'");
        if (tok_[1] == "ascii") return Encoding::Ascii;
        if (tok_[1] == "binary_little_endian") return Encoding::BinaryLittle;
        if (tok_[1] == "binary_big_endian") return Encoding::BinaryBig;
        throw error("unknown format " + quote_token(tok_[1]), "use ascii, binary_little_endian or binary_big_endian");
    }

    Element element() const {
        Element e;
        if (tok_.size() != 3 || !parse_integer(tok_[2], e.count) || e.count < 0)
            throw error("malformed element line", "write 'element <name> <count>' with a count >= 0");
        e.name = std::string(tok_[1]);
        e.header_line = scan_.line_number();
        return e;
    }

    Property property(const Element& of) const {
        Property p;
        bool ok;
        if (tok_.size() >= 2 && tok_[1] == "list") {
            p.is_list = true;
            ok = tok_.size() == 5 && parse_type(tok_[2], p.count_type) && parse_type(tok_[3], p.type) &&
                 is_integer_type(p.count_type);
            if (ok) p.name = std::string(tok_[4]);
        } else {
            ok = tok_.size() == 3 && parse_type(tok_[1], p.type);
            if (ok) p.name = std::string(tok_[2]);
        }
        if (!ok)
            throw error("malformed property line",
                        "write 'property <type> <name>' or 'property list <count type> <type> <name>' with "
                        "types char, uchar, short, ushort, int, uint, float, double");
        if (of.name == "face" && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index") &&
            !is_integer_type(p.type))
            throw error("face vertex indices have a floating-point type", "use an integer type such as int");
        return p;
    }

    const std::string& file_;
    TextScanner& scan_;
    std::vector<std::string_view> tok_;
};

// The elements must describe a mesh: vertices with x, y, z and faces with vertex indices.
void check_mesh_elements(const std::string& file, const std::vector<Element>& elements) {
    bool has_xyz = false, has_faces = false;
    for (const Element& e : elements) {
        if (e.count > 0 && e.props.empty())
            throw MeshFileError(file_error(file, FileLocation{e.header_line, -1},
                                           "element '" + e.name + "' has no properties", "declare its properties"));
        if (e.name == "vertex") {
            int found = 0;
            for (const auto& p : e.props) found += !p.is_list && (p.name == "x" || p.name == "y" || p.name == "z");
            has_xyz = found == 3;
        }
        if (e.name == "face")
            for (const auto& p : e.props) has_faces |= p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index");
    }
    if (!has_xyz)
        throw MeshFileError(file_error(file, "no element 'vertex' with properties x, y and z", "this is not a mesh PLY file"));
    if (!has_faces)
        throw MeshFileError(file_error(file, "no element 'face' with a list property vertex_indices",
                                       "the file holds no polygons (a point cloud?); export the surface with faces"));
}

// The declared counts against the bytes present, before reserving anything.
void check_data_size(const std::string& file, const PlyHeader& h, std::size_t remaining_bytes) {
    const long double remaining = static_cast<long double>(remaining_bytes);
    long double needed = 0;
    for (const Element& e : h.elements) {
        long double per = 0;
        for (const auto& p : e.props)
            per += h.enc == Encoding::Ascii ? 2 : static_cast<long double>(type_size(p.is_list ? p.count_type : p.type));
        needed += per * static_cast<long double>(e.count);
    }
    if (needed > remaining + 1)
        throw MeshFileError(file_error(file, "header declares elements needing at least " +
                                                 std::to_string(static_cast<long long>(needed)) + " bytes but only " +
                                                 std::to_string(static_cast<long long>(remaining)) +
                                                 " bytes of data follow (truncated?)",
                                       "re-export the file or fix the element counts"));
}

}  // namespace

MeshSoup read_ply_soup(const std::string& file, std::string_view bytes) {
    MeshSoup soup;
    soup.file = file;
    TextScanner scan(bytes);
    const PlyHeader h = HeaderReader(file, scan).read();
    check_mesh_elements(file, h.elements);
    const std::size_t data_start = scan.position();
    check_data_size(file, h, bytes.size() - data_start);
    for (const Element& e : h.elements) {
        if (e.name == "vertex") soup.vertices.reserve(static_cast<std::size_t>(e.count));
        if (e.name == "face") soup.faces.reserve(static_cast<std::size_t>(e.count));
    }
    if (h.enc == Encoding::Ascii) {
        AsciiCursor cur(file, bytes, data_start, scan.line_number());
        read_elements(soup, h.elements, cur, [&] { return FileLocation{cur.peek_line(), -1}; });
    } else {
        BinaryCursor cur(file, bytes, data_start, h.enc == Encoding::BinaryBig);
        read_elements(soup, h.elements, cur, [&] { return FileLocation{0, static_cast<long long>(cur.position())}; });
    }
    // Per-vertex attributes: every corner uses its vertex's (the index is checked with the vertex's).
    if (!soup.uvs.empty() && soup.uvs.size() == soup.vertices.size()) soup.corner_uv = soup.indices;
    if (!soup.normals.empty() && soup.normals.size() == soup.vertices.size()) soup.corner_normal = soup.indices;
    return soup;
}

}  // namespace cf
