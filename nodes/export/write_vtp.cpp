#include "nodes/export/mesh_checks.hpp"
#include "nodes/export/number_text.hpp"
#include "nodes/export/vtp_writer.hpp"
#include "nodes/export/xml_text.hpp"

#include <set>
#include <stdexcept>

namespace cf {

namespace {

void check_arrays(const std::vector<VtpArray>& arrays, std::size_t tuples, const char* kind,
                  std::set<std::string>& names) {
    for (const VtpArray& a : arrays) {
        const std::string id = std::string(kind) + " array '" + a.name + "'";
        if (a.name.empty()) throw std::invalid_argument(std::string("cannot write .vtp: a ") + kind + " array has no name");
        if (!names.insert(a.name).second)
            throw std::invalid_argument("cannot write .vtp: two arrays are named '" + a.name + "'");
        if (a.components != 1 && a.components != 3)
            throw std::invalid_argument("cannot write .vtp: " + id + " has " + std::to_string(a.components) +
                                        " components; use 1 (scalar) or 3 (vector)");
        if (a.values.size() != tuples * static_cast<std::size_t>(a.components))
            throw std::invalid_argument("cannot write .vtp: " + id + " has " + std::to_string(a.values.size()) +
                                        " values, expected " + std::to_string(a.components) + " x " +
                                        std::to_string(tuples));
    }
}

void write_array(std::ostream& os, const VtpArray& a) {
    os << "        <DataArray type=\"Float64\" Name=\"" << xml_escape(a.name) << "\" NumberOfComponents=\""
       << a.components << "\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < a.values.size(); ++i) {
        write_real(os, a.values[i]);
        os << ((i + 1) % a.components == 0 ? '\n' : ' ');
    }
    os << "        </DataArray>\n";
}

void write_points(std::ostream& os, const std::vector<Vec3>& points) {
    for (const Vec3& p : points) {
        write_real(os, p.x());
        os << ' ';
        write_real(os, p.y());
        os << ' ';
        write_real(os, p.z());
        os << '\n';
    }
}

}  // namespace

void write_vtp(std::ostream& os, const SurfaceMesh& m, const VtpFields& fields) {
    check_writable(m);
    std::set<std::string> names{"region"};
    check_arrays(fields.point_data, m.num_vertices(), "point", names);
    for (const VtpArray& a : fields.cell_data)
        if (a.name == "region")
            throw std::invalid_argument("cannot write .vtp: cell array name 'region' is reserved for the region ids");
    check_arrays(fields.cell_data, m.num_triangles(), "cell", names);

    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << "  <PolyData>\n"
       << "    <Piece NumberOfPoints=\"" << m.num_vertices() << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
       << "NumberOfStrips=\"0\" NumberOfPolys=\"" << m.num_triangles() << "\">\n";
    os << "      <PointData>\n";
    for (const VtpArray& a : fields.point_data) write_array(os, a);
    os << "      </PointData>\n      <CellData Scalars=\"region\">\n"
       << "        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < m.triangles.size(); ++t) os << m.region_of(t) << '\n';
    os << "        </DataArray>\n";
    for (const VtpArray& a : fields.cell_data) write_array(os, a);
    os << "      </CellData>\n      <Points>\n"
       << "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    write_points(os, m.vertices);
    os << "        </DataArray>\n      </Points>\n      <Polys>\n"
       << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const Tri& f : m.triangles) os << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
    os << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t t = 1; t <= m.triangles.size(); ++t) os << 3 * t << (t % 16 == 0 ? '\n' : ' ');
    os << "\n        </DataArray>\n      </Polys>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
}

void write_vtp_lines(std::ostream& os, const std::vector<Vec3>& points, const std::vector<std::vector<int>>& lines,
                     const std::vector<VtpArray>& point_data) {
    for (const Vec3& p : points)
        if (!p.allFinite()) throw std::invalid_argument("cannot write .vtp: a polyline point is not finite");
    for (const auto& l : lines) {
        if (l.size() < 2) throw std::invalid_argument("cannot write .vtp: a polyline has fewer than 2 points");
        for (int i : l)
            if (i < 0 || std::size_t(i) >= points.size())
                throw std::invalid_argument("cannot write .vtp: polyline point " + std::to_string(i) + " does not exist");
    }
    std::set<std::string> names;
    check_arrays(point_data, points.size(), "point", names);
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << "  <PolyData>\n"
       << "    <Piece NumberOfPoints=\"" << points.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << lines.size()
       << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n      <PointData>\n";
    for (const VtpArray& a : point_data) write_array(os, a);
    os << "      </PointData>\n      <Points>\n"
       << "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    write_points(os, points);
    os << "        </DataArray>\n      </Points>\n      <Lines>\n"
       << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const auto& l : lines) {
        for (std::size_t k = 0; k < l.size(); ++k) os << l[k] << (k + 1 < l.size() ? ' ' : '\n');
    }
    os << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    std::size_t off = 0;
    for (const auto& l : lines) os << (off += l.size()) << '\n';
    os << "        </DataArray>\n      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
}

}  // namespace cf
