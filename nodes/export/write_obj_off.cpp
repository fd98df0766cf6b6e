// OBJ and OFF: the two simple indexed text formats.
#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/mesh_writers.hpp"
#include "nodes/export/number_text.hpp"

namespace cf {

namespace {

void write_point(std::ostream& os, const Vec3& p) {
    write_real(os, p.x());
    os << ' ';
    write_real(os, p.y());
    os << ' ';
    write_real(os, p.z());
}

}  // namespace

void write_obj(std::ostream& os, const SurfaceMesh& m) {
    check_writable(m);
    os << "# crackflow surface mesh: " << m.num_vertices() << " vertices, " << m.num_triangles() << " triangles\n";
    for (const Vec3& p : m.vertices) {
        os << "v ";
        write_point(os, p);
        os << '\n';
    }
    // Regions become OBJ groups, started whenever the region changes (face order is kept).
    int group = -1;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        if (m.region_of(t) != group) {
            group = m.region_of(t);
            os << "g " << m.region_name(group) << '\n';
        }
        const Tri& f = m.triangles[t];
        os << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
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
