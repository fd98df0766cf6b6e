// PLY with double-precision vertices and a per-face int "region" property (ignored by
// readers that do not know it). A mesh with corner attributes gets one vertex per distinct
// (position, uv, normal) with float properties nx ny nz and u v, and, when it has a region named
// "inside" (the fracture faces of a fragment), a per-face uchar property "inside" (1 on those faces).
#include "nodes/export/binary_out.hpp"
#include "nodes/export/corner_vertices.hpp"
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

namespace cf {

namespace {

// The id of the region named "inside", or -1.
int inside_region(const SurfaceMesh& m) {
    for (int r = 0; r < int(m.region_names.size()); ++r)
        if (m.region_names[std::size_t(r)] == "inside") return r;
    return -1;
}

}  // namespace

void write_ply(std::ostream& os, const SurfaceMesh& m, bool binary) {
    check_writable(m);
    const bool split = m.has_uv() || m.has_normals();
    const CornerVertices cv = split ? split_corner_vertices(m) : CornerVertices{};
    const std::size_t nv = split ? cv.vertex.size() : m.num_vertices();
    const int inside = inside_region(m);
    os << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
       << "comment crackflow surface mesh; region names:";
    for (int r = 0; r < m.num_regions(); ++r) os << ' ' << r << '=' << m.region_name(r);
    os << "\nelement vertex " << nv << "\nproperty double x\nproperty double y\nproperty double z\n";
    if (!cv.normal.empty()) os << "property float nx\nproperty float ny\nproperty float nz\n";
    if (!cv.uv.empty()) os << "property float u\nproperty float v\n";
    os << "element face " << m.num_triangles() << "\nproperty list uchar int vertex_indices\nproperty int region\n";
    if (inside >= 0) os << "property uchar inside\n";
    os << "end_header\n";
    const std::vector<Tri>& tris = split ? cv.triangles : m.triangles;
    for (std::size_t i = 0; i < nv; ++i) {
        const Vec3& p = m.vertices[split ? std::size_t(cv.vertex[i]) : i];
        if (binary) {
            put_f64(os, p.x());
            put_f64(os, p.y());
            put_f64(os, p.z());
            if (!cv.normal.empty())
                for (int k = 0; k < 3; ++k) put_f32(os, float(cv.normal[i][k]));
            if (!cv.uv.empty())
                for (int k = 0; k < 2; ++k) put_f32(os, float(cv.uv[i][k]));
            continue;
        }
        write_real(os, p.x());
        os << ' ';
        write_real(os, p.y());
        os << ' ';
        write_real(os, p.z());
        if (!cv.normal.empty())
            for (int k = 0; k < 3; ++k) os << ' ' << float(cv.normal[i][k]);
        if (!cv.uv.empty())
            for (int k = 0; k < 2; ++k) os << ' ' << float(cv.uv[i][k]);
        os << '\n';
    }
    for (std::size_t t = 0; t < tris.size(); ++t) {
        const Tri& f = tris[t];
        if (binary) {
            put_u8(os, 3);
            for (int v : f) put_i32(os, v);
            put_i32(os, m.region_of(t));
            if (inside >= 0) put_u8(os, m.region_of(t) == inside ? 1 : 0);
            continue;
        }
        os << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << ' ' << m.region_of(t);
        if (inside >= 0) os << ' ' << (m.region_of(t) == inside ? 1 : 0);
        os << '\n';
    }
}

}  // namespace cf
