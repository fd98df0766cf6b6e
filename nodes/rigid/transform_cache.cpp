#include "nodes/rigid/transform_cache.hpp"

#include "graph/atomic_write.hpp"
#include "nodes/export/number_text.hpp"
#include "nodes/export/xml_text.hpp"
#include "nodes/rigid/animation_checks.hpp"

#include <cstdio>
#include <locale>
#include <ostream>
#include <stdexcept>
#include <vector>

namespace cf::rigid {

namespace {

// Scalars are written kPerLine to a line, tuples one to a line (readable, diffable).
constexpr std::size_t kPerLine = 12;

void separator(std::ostream& os, std::size_t i, std::size_t n, std::size_t per_line = kPerLine) {
    os << ((i + 1) % per_line == 0 || i + 1 == n ? '\n' : ' ');
}

void float64_array(std::ostream& os, const char* name, int components, const std::vector<double>& values) {
    os << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"" << components
       << "\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < values.size(); ++i) {
        write_real(os, values[i]);
        separator(os, i, values.size(), components > 1 ? std::size_t(components) : kPerLine);
    }
    os << "        </DataArray>\n";
}

void int_array(std::ostream& os, const char* type, const char* name, const std::vector<long long>& values) {
    os << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" format=\"ascii\">\n";
    for (std::size_t i = 0; i < values.size(); ++i) {
        os << values[i];
        separator(os, i, values.size());
    }
    os << "        </DataArray>\n";
}

// VTK's ASCII string array: each string's bytes as unsigned decimals, then a 0.
void string_array(std::ostream& os, const char* name, const std::vector<std::string>& values) {
    os << "        <DataArray type=\"String\" Name=\"" << name << "\" NumberOfTuples=\"" << values.size()
       << "\" format=\"ascii\">\n";
    for (const std::string& s : values) {
        for (char c : s) os << static_cast<unsigned>(static_cast<unsigned char>(c)) << ' ';
        os << "0\n";
    }
    os << "        </DataArray>\n";
}

void append(std::vector<double>& out, const Vec3& v) { out.insert(out.end(), {v.x(), v.y(), v.z()}); }

void begin_file(std::ostream& os) {
    os.imbue(std::locale::classic());  // no digit grouping from a global locale
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
       << "  <PolyData>\n";
}

void end_file(std::ostream& os) { os << "    </Piece>\n  </PolyData>\n</VTKFile>\n"; }

void points(std::ostream& os, const std::vector<double>& xyz) {
    os << "      <Points>\n";
    float64_array(os, "Points", 3, xyz);
    os << "      </Points>\n";
}

// The cells of one kind: `n` cells of `size` consecutive points each.
void cells(std::ostream& os, const char* kind, const std::vector<long long>& connectivity, std::size_t n, std::size_t size) {
    std::vector<long long> offsets(n);
    for (std::size_t c = 0; c < n; ++c) offsets[c] = static_cast<long long>((c + 1) * size);
    os << "      <" << kind << ">\n";
    int_array(os, "Int64", "connectivity", connectivity);
    int_array(os, "Int64", "offsets", offsets);
    os << "      </" << kind << ">\n";
}

void write_rest(std::ostream& os, const Animation& a) {
    std::vector<double> xyz;
    std::vector<long long> connectivity, piece, inside;
    std::vector<double> uv;
    std::vector<std::string> names;
    bool any_uv = false;
    for (const AnimationPiece& p : a.pieces) any_uv = any_uv || p.rest_mesh->has_uv();
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
        const SurfaceMesh& m = *a.pieces[i].rest_mesh;
        const auto base = static_cast<long long>(xyz.size() / 3);
        int inside_id = -1;
        for (int r = 0; r < static_cast<int>(m.region_names.size()); ++r)
            if (m.region_names[static_cast<std::size_t>(r)] == "inside") inside_id = r;
        for (const Vec3& x : m.vertices) append(xyz, x);
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            for (int v : m.triangles[t]) connectivity.push_back(base + v);
            piece.push_back(static_cast<long long>(i));
            inside.push_back(inside_id >= 0 && m.region_of(t) == inside_id ? 1 : 0);
            if (any_uv)
                for (int k = 0; k < 3; ++k) {
                    const Vec2 w = m.has_uv() ? m.corner_uv[t][static_cast<std::size_t>(k)] : Vec2::Zero();
                    uv.insert(uv.end(), {w.x(), w.y()});
                }
        }
        names.push_back(a.pieces[i].name);
    }
    begin_file(os);
    os << "    <FieldData>\n";
    string_array(os, "piece_names", names);
    os << "    </FieldData>\n"
       << "    <Piece NumberOfPoints=\"" << xyz.size() / 3 << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
       << "NumberOfStrips=\"0\" NumberOfPolys=\"" << piece.size() << "\">\n"
       << "      <CellData Scalars=\"piece\">\n";
    int_array(os, "Int32", "piece", piece);
    int_array(os, "Int32", "inside", inside);
    if (any_uv) float64_array(os, "uv", 6, uv);
    os << "      </CellData>\n";
    points(os, xyz);
    cells(os, "Polys", connectivity, piece.size(), 3);
    end_file(os);
}

void write_frame(std::ostream& os, const Animation& a, const AnimationFrame& frame) {
    const std::size_t n = frame.poses.size();
    std::vector<double> xyz, orient, pivot(3 * n, 0.0), v, w;
    std::vector<long long> piece, connectivity;
    std::vector<std::string> names;
    for (const auto& [i, pose] : frame.poses) {
        append(xyz, pose.position);
        const Eigen::Quaterniond& q = pose.rotation;
        orient.insert(orient.end(), {q.x(), q.y(), q.z(), q.w()});
        append(v, pose.velocity);
        append(w, pose.angular_velocity);
        connectivity.push_back(static_cast<long long>(piece.size()));
        piece.push_back(i);
        names.push_back(a.pieces[static_cast<std::size_t>(i)].name);
    }
    begin_file(os);
    os << "    <FieldData>\n        <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">";
    write_real(os, frame.time);
    os << "</DataArray>\n    </FieldData>\n"
       << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"" << n << "\" NumberOfLines=\"0\" "
       << "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
       << "      <PointData>\n";
    string_array(os, "name", names);
    int_array(os, "Int32", "piece", piece);
    float64_array(os, "orient", 4, orient);
    float64_array(os, "pivot", 3, pivot);
    float64_array(os, "v", 3, v);
    float64_array(os, "w", 3, w);
    os << "      </PointData>\n";
    points(os, xyz);
    cells(os, "Verts", connectivity, n, 1);
    end_file(os);
}

void write_collection(std::ostream& os, const Animation& a, const std::string& stem) {
    os.imbue(std::locale::classic());
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <Collection>\n";
    for (std::size_t f = 0; f < a.frames.size(); ++f) {
        os << "    <DataSet timestep=\"";
        write_real(os, a.frames[f].time);
        os << "\" part=\"0\" file=\"" << xml_escape(transform_cache_frame_name(stem, static_cast<int>(f))) << "\"/>\n";
    }
    os << "  </Collection>\n</VTKFile>\n";
}

void check_stem(const std::string& stem) {
    if (stem.empty() || stem.find('/') != std::string::npos || stem == "." || stem == "..")
        throw std::invalid_argument("cannot write the transform cache: the stem \"" + stem +
                                    "\" must be a plain, non-empty file name without '/'");
}

}  // namespace

std::string transform_cache_frame_name(const std::string& stem, int frame) {
    char digits[16];
    std::snprintf(digits, sizeof digits, "%04d", frame);
    return stem + "_" + digits + ".vtp";
}

void write_transform_cache(const Animation& a, const std::filesystem::path& dir, const std::string& stem) {
    check_animation(a);
    check_stem(stem);
    graph::write_atomically(dir / (stem + "_rest.vtp"), [&](std::ostream& os) { write_rest(os, a); });
    for (std::size_t f = 0; f < a.frames.size(); ++f)
        graph::write_atomically(dir / transform_cache_frame_name(stem, static_cast<int>(f)),
                                [&](std::ostream& os) { write_frame(os, a, a.frames[f]); });
    graph::write_atomically(dir / (stem + ".pvd"), [&](std::ostream& os) { write_collection(os, a, stem); });
}

}  // namespace cf::rigid
