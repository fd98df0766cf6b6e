// OBJ and OFF: the two simple indexed text formats.
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

#include <map>
#include <vector>

namespace cf {

namespace {

void write_point(std::ostream& os, const Vec3& p) {
    write_real(os, p.x());
    os << ' ';
    write_real(os, p.y());
    os << ' ';
    write_real(os, p.z());
}

// One OBJ index per distinct value (exact), in order of first use.
template <class V>
std::vector<std::array<int, 3>> indexed_corners(const std::vector<std::array<V, 3>>& corner, std::vector<V>& values) {
    std::map<std::vector<double>, int> index;
    std::vector<std::array<int, 3>> out(corner.size());
    for (std::size_t t = 0; t < corner.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const V& v = corner[t][k];
            auto [it, added] = index.try_emplace(std::vector<double>(v.data(), v.data() + v.size()), int(values.size()));
            if (added) values.push_back(v);
            out[t][k] = it->second + 1;
        }
    return out;
}

}  // namespace

void write_obj(std::ostream& os, const SurfaceMesh& m) { write_obj(os, m, ""); }

void write_obj(std::ostream& os, const SurfaceMesh& m, const std::string& mtllib) {
    check_writable(m);
    os << "# crackflow surface mesh: " << m.num_vertices() << " vertices, " << m.num_triangles() << " triangles\n";
    if (!mtllib.empty()) os << "mtllib " << mtllib << '\n';
    for (const Vec3& p : m.vertices) {
        os << "v ";
        write_point(os, p);
        os << '\n';
    }
    std::vector<Vec2> uvs;
    std::vector<Vec3> normals;
    const auto uv_index = m.has_uv() ? indexed_corners(m.corner_uv, uvs) : std::vector<std::array<int, 3>>{};
    const auto n_index = m.has_normals() ? indexed_corners(m.corner_normal, normals) : std::vector<std::array<int, 3>>{};
    for (const Vec2& t : uvs) {
        os << "vt ";
        write_real(os, t.x());
        os << ' ';
        write_real(os, t.y());
        os << '\n';
    }
    for (const Vec3& n : normals) {
        os << "vn ";
        write_point(os, n);
        os << '\n';
    }
    // Regions become OBJ groups (and materials of the same name when there is a material library),
    // started whenever the region changes (face order is kept).
    int group = -1;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        if (m.region_of(t) != group) {
            group = m.region_of(t);
            os << "g " << m.region_name(group) << '\n';
            if (!mtllib.empty()) os << "usemtl " << m.region_name(group) << '\n';
        }
        const Tri& f = m.triangles[t];
        os << 'f';
        for (int k = 0; k < 3; ++k) {
            os << ' ' << f[k] + 1;
            if (!uv_index.empty() || !n_index.empty()) os << '/';
            if (!uv_index.empty()) os << uv_index[t][k];
            if (!n_index.empty()) os << '/' << n_index[t][k];
        }
        os << '\n';
    }
}

void write_mtl(std::ostream& os, const std::vector<std::pair<std::string, Vec3>>& materials) {
    os << "# crackflow materials\n";
    for (const auto& [name, colour] : materials) {
        os << "newmtl " << name << "\nKd ";
        write_point(os, colour);
        os << "\nKa 0 0 0\nKs 0 0 0\nillum 1\n";
    }
}

void write_off(std::ostream& os, const SurfaceMesh& m) {
    check_writable(m);
    os << "OFF\n" << m.num_vertices() << ' ' << m.num_triangles() << " 0\n";
    for (const Vec3& p : m.vertices) {
        write_point(os, p);
        os << '\n';
    }
    for (const Tri& f : m.triangles) os << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

}  // namespace cf
