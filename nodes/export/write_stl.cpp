// STL: unindexed facets with unit normals. Binary STL stores float32, so coordinates are
// rounded to single precision; ASCII STL keeps full double precision.
#include "nodes/export/binary_out.hpp"
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace cf {

void write_stl(std::ostream& os, const SurfaceMesh& m, bool binary) {
    check_writable(m);
    if (binary) {
        if (m.num_triangles() > UINT32_MAX)
            throw std::invalid_argument("cannot write binary STL: " + std::to_string(m.num_triangles()) +
                                        " triangles exceed the format's 32-bit count; use PLY");
        // The header must not start with "solid", or readers take the file for ASCII STL.
        std::string header = "crackflow binary STL";
        header.resize(80, ' ');
        os.write(header.data(), 80);
        put_u32(os, static_cast<std::uint32_t>(m.num_triangles()));
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const Vec3 n = triangle_normal(m, t);
            for (int k = 0; k < 3; ++k) put_f32(os, static_cast<float>(n[k]));
            for (int v : m.triangles[t])
                for (int k = 0; k < 3; ++k) put_f32(os, static_cast<float>(m.vertices[v][k]));
            put_u16(os, 0);
        }
        return;
    }
    auto point = [&](const Vec3& p) {
        write_real(os, p.x());
        os << ' ';
        write_real(os, p.y());
        os << ' ';
        write_real(os, p.z());
        os << '\n';
    };
    os << "solid crackflow\n";
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        os << "facet normal ";
        point(triangle_normal(m, t));
        os << "outer loop\n";
        for (int v : m.triangles[t]) {
            os << "vertex ";
            point(m.vertices[v]);
        }
        os << "endloop\nendfacet\n";
    }
    os << "endsolid crackflow\n";
}

}  // namespace cf
