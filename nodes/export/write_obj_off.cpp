// OBJ and OFF: the two simple indexed text formats.
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace cf {

namespace {

void write_point(TextOut& out, const Vec3& p) { out << p.x() << ' ' << p.y() << ' ' << p.z(); }

// One OBJ index per distinct value (exact; -0 and +0 are one value), in order of first use. A hash
// of the bit patterns: a sorted map of vectors allocated per corner took 0.5 s for a 180 k-triangle
// fragment with UVs and normals.
template <class V>
std::vector<std::array<int, 3>> indexed_corners(const std::vector<std::array<V, 3>>& corner, std::vector<V>& values) {
    constexpr int N = int(V::RowsAtCompileTime);
    using Key = std::array<double, N>;
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 0x9E3779B97F4A7C15ull;
            for (double x : k) {
                std::uint64_t b;
                std::memcpy(&b, &x, sizeof b);
                h = (h ^ b) * 0x100000001B3ull;
                h ^= h >> 29;
            }
            return std::size_t(h);
        }
    };
    std::unordered_map<Key, int, KeyHash> index;
    index.reserve(corner.size());
    std::vector<std::array<int, 3>> out(corner.size());
    for (std::size_t t = 0; t < corner.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const V& v = corner[t][k];
            Key key;
            for (int c = 0; c < N; ++c) key[std::size_t(c)] = v[c] + 0.0;  // -0 -> +0
            auto [it, added] = index.try_emplace(key, int(values.size()));
            if (added) values.push_back(v);
            out[t][k] = it->second + 1;
        }
    return out;
}

// The lines of items [0, count), each written by `line`, formatted in pieces on parallel tasks
// (oneTBB) and passed to `out` in order: the bytes of one pass (a fragment's OBJ is tens of MB of
// numbers, its writing serial after the mesh was made).
template <class Line>
void in_pieces(TextOut& out, std::size_t count, Line&& line) {
    constexpr std::size_t kPiece = 16384;
    const std::size_t pieces = (count + kPiece - 1) / kPiece;
    std::vector<std::string> text(pieces);
    tbb::parallel_for(std::size_t(0), pieces, [&](std::size_t p) {
        TextOut o(text[p]);
        for (std::size_t i = p * kPiece; i < std::min(count, (p + 1) * kPiece); ++i) line(o, i);
    });
    for (const std::string& s : text) out.write_formatted(s);
}

}  // namespace

void write_obj(std::ostream& os, const SurfaceMesh& m) { write_obj(os, m, ""); }

void write_obj(std::ostream& os, const SurfaceMesh& m, const std::string& mtllib) {
    check_writable(m);
    TextOut out(os);
    out << "# crackflow surface mesh: " << m.num_vertices() << " vertices, " << m.num_triangles() << " triangles\n";
    if (!mtllib.empty()) out << "mtllib " << mtllib << '\n';
    in_pieces(out, m.vertices.size(), [&](TextOut& o, std::size_t v) {
        o << "v ";
        write_point(o, m.vertices[v]);
        o << '\n';
    });
    std::vector<Vec2> uvs;
    std::vector<Vec3> normals;
    const auto uv_index = m.has_uv() ? indexed_corners(m.corner_uv, uvs) : std::vector<std::array<int, 3>>{};
    const auto n_index = m.has_normals() ? indexed_corners(m.corner_normal, normals) : std::vector<std::array<int, 3>>{};
    for (const Vec2& t : uvs) out << "vt " << t.x() << ' ' << t.y() << '\n';
    for (const Vec3& n : normals) {
        out << "vn ";
        write_point(out, n);
        out << '\n';
    }
    // Regions become OBJ groups (and materials of the same name when there is a material library),
    // started whenever the region changes (face order is kept).
    in_pieces(out, m.triangles.size(), [&](TextOut& o, std::size_t t) {
        if (t == 0 || m.region_of(t) != m.region_of(t - 1)) {
            const int group = m.region_of(t);
            o << "g " << m.region_name(group) << '\n';
            if (!mtllib.empty()) o << "usemtl " << m.region_name(group) << '\n';
        }
        const Tri& f = m.triangles[t];
        o << 'f';
        for (int k = 0; k < 3; ++k) {
            o << ' ' << f[k] + 1;
            if (!uv_index.empty() || !n_index.empty()) o << '/';
            if (!uv_index.empty()) o << uv_index[t][k];
            if (!n_index.empty()) o << '/' << n_index[t][k];
        }
        o << '\n';
    });
}

void write_mtl(std::ostream& os, const std::vector<std::pair<std::string, Vec3>>& materials) {
    TextOut out(os);
    out << "# crackflow materials\n";
    for (const auto& [name, colour] : materials) {
        out << "newmtl " << name << "\nKd ";
        write_point(out, colour);
        out << "\nKa 0 0 0\nKs 0 0 0\nillum 1\n";
    }
}

void write_off(std::ostream& os, const SurfaceMesh& m) {
    check_writable(m);
    TextOut out(os);
    out << "OFF\n" << m.num_vertices() << ' ' << m.num_triangles() << " 0\n";
    for (const Vec3& p : m.vertices) {
        write_point(out, p);
        out << '\n';
    }
    for (const Tri& f : m.triangles) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

}  // namespace cf
