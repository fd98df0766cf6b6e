// PLY with double-precision vertices and a per-face int "region" property (ignored by
// readers that do not know it).
#include "nodes/export/binary_out.hpp"
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

namespace cf {

void write_ply(std::ostream& os, const SurfaceMesh& m, bool binary) {
    check_writable(m);
    os << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
       << "comment crackflow surface mesh; region names:";
    for (int r = 0; r < m.num_regions(); ++r) os << ' ' << r << '=' << m.region_name(r);
    os << "\nelement vertex " << m.num_vertices() << "\nproperty double x\nproperty double y\nproperty double z\n"
       << "element face " << m.num_triangles() << "\nproperty list uchar int vertex_indices\nproperty int region\n"
       << "end_header\n";
    if (binary) {
        for (const Vec3& p : m.vertices) {
            put_f64(os, p.x());
            put_f64(os, p.y());
            put_f64(os, p.z());
        }
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            put_u8(os, 3);
            for (int v : m.triangles[t]) put_i32(os, v);
            put_i32(os, m.region_of(t));
        }
        return;
    }
    for (const Vec3& p : m.vertices) {
        write_real(os, p.x());
        os << ' ';
        write_real(os, p.y());
        os << ' ';
        write_real(os, p.z());
        os << '\n';
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Tri& f = m.triangles[t];
        os << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << ' ' << m.region_of(t) << '\n';
    }
}

}  // namespace cf
