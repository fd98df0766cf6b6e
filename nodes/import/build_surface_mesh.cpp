// From a raw soup to a checked SurfaceMesh: index checks, fan triangulation, welding, removal
// of unreferenced vertices, degenerate-triangle checks, then check_closed_surface.
#include "graph/diagnostics.hpp"
#include "nodes/import/check_closed_surface.hpp"
#include "nodes/import/read_mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace cf {

namespace {

// rep[v] = the earliest vertex with exactly the same position (-0 and +0 are the same).
std::vector<int> weld_exact(const std::vector<Vec3>& V) {
    struct Key {
        std::uint64_t bits[3];
        bool operator==(const Key& o) const { return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2]; }
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            std::uint64_t h = 1469598103934665603ULL;
            for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ULL ^ (b >> 29);
            return static_cast<std::size_t>(h);
        }
    };
    std::unordered_map<Key, int, KeyHash> first;
    first.reserve(V.size());
    std::vector<int> rep(V.size());
    for (std::size_t v = 0; v < V.size(); ++v) {
        Key k;
        for (int c = 0; c < 3; ++c) {
            const double x = V[v][c] == 0.0 ? 0.0 : V[v][c];
            std::memcpy(&k.bits[c], &x, 8);
        }
        rep[v] = first.emplace(k, static_cast<int>(v)).first->second;
    }
    return rep;
}

// rep[v] = the earliest kept vertex within `tol` of v (vertices visited in file order; a
// vertex is kept when no earlier kept vertex is that close). Grid of cell size tol.
std::vector<int> weld_within(const std::vector<Vec3>& V, double tol, const std::string& file) {
    struct Key {
        long long x, y, z;
        bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            // Unsigned arithmetic: wrap-around is intended here.
            return static_cast<std::size_t>(static_cast<std::uint64_t>(k.x) * 73856093u ^
                                            static_cast<std::uint64_t>(k.y) * 19349663u ^
                                            static_cast<std::uint64_t>(k.z) * 83492791u);
        }
    };
    std::unordered_map<Key, std::vector<int>, KeyHash> grid;
    std::vector<int> rep(V.size());
    for (std::size_t v = 0; v < V.size(); ++v) {
        const Vec3 c = V[v] / tol;
        if (!(c.cwiseAbs().maxCoeff() < 1e15))
            throw MeshFileError(file_error(file, "weld_tolerance " + graph::format_number(tol) +
                                                     " is too small for coordinates as large as " + format_point(V[v]),
                                           "use a larger weld_tolerance (or 0 to disable welding)"));
        const Key k{static_cast<long long>(std::floor(c.x())), static_cast<long long>(std::floor(c.y())),
                    static_cast<long long>(std::floor(c.z()))};
        int best = -1;
        for (long long dx = -1; dx <= 1; ++dx)
            for (long long dy = -1; dy <= 1; ++dy)
                for (long long dz = -1; dz <= 1; ++dz) {
                    auto it = grid.find(Key{k.x + dx, k.y + dy, k.z + dz});
                    if (it == grid.end()) continue;
                    for (int u : it->second)
                        if ((V[u] - V[v]).norm() <= tol && (best < 0 || u < best)) best = u;
                }
        if (best >= 0) {
            rep[v] = best;
        } else {
            rep[v] = static_cast<int>(v);
            grid[k].push_back(static_cast<int>(v));
        }
    }
    return rep;
}

// build_surface_mesh's steps, in the order it calls them.

void check_options_and_counts(const MeshSoup& soup, const ImportOptions& options) {
    const std::string& file = soup.file;
    if (!(options.scale > 0) || !std::isfinite(options.scale))
        throw MeshFileError(file_error(file, "scale " + graph::format_number(options.scale) + " is not a positive number",
                                       "set scale to the length of one file unit in metres, e.g. 0.001 for millimetres"));
    if (!(options.weld_tolerance >= 0) || !std::isfinite(options.weld_tolerance))
        throw MeshFileError(file_error(file, "weld_tolerance must be >= 0", "use 0 to disable welding"));
    const long long nv = static_cast<long long>(soup.vertices.size());
    if (nv > INT_MAX)
        throw MeshFileError(file_error(file, "too many vertices (" + std::to_string(nv) + ")",
                                       "split the mesh; at most 2^31-1 vertices are supported"));
    if (soup.faces.empty())
        throw MeshFileError(file_error(file, "no faces found (" + std::to_string(nv) + " vertices)",
                                       "the file must contain a closed triangle surface, not only points or lines"));
}

// Triangles with the file location of the face each came from.
struct LocatedTriangles {
    std::vector<Tri> tris;
    std::vector<FileLocation> where;
    std::vector<int> region;  // per triangle, into MeshSoup::region_names (-1: default)
    std::vector<std::array<std::size_t, 3>> corner;  // per triangle, its corners' positions in MeshSoup::indices
};

// Index checks and fan triangulation.
LocatedTriangles fan_triangulate(const MeshSoup& soup) {
    const std::string& file = soup.file;
    const long long nv = static_cast<long long>(soup.vertices.size());
    LocatedTriangles out;
    out.tris.reserve(soup.faces.size());
    out.where.reserve(soup.faces.size());
    const long long base = soup.index_base;
    for (const SoupFace& f : soup.faces) {
        if (f.count < 3)
            throw MeshFileError(file_error(file, f.where, "face has " + std::to_string(f.count) + " vertices",
                                           "a face needs at least 3 vertices; remove it"));
        for (std::size_t k = 0; k < f.count; ++k) {
            const long long idx = soup.indices[f.first + k];
            if (idx - base < 0 || idx - base >= nv) {
                const std::string range = nv == 0 ? "the file has no vertices"
                                                  : "file has " + std::to_string(nv) + " vertices, valid indices are " +
                                                        std::to_string(base) + ".." + std::to_string(base + nv - 1);
                throw MeshFileError(file_error(file, f.where,
                                               std::string(idx < 0 ? "negative face index " : "face index ") +
                                                   std::to_string(idx) + " out of range (" + range + ")",
                                               "fix the index"));
            }
        }
        auto corner = [&](std::size_t k) { return static_cast<int>(soup.indices[f.first + k] - base); };
        for (std::size_t k = 1; k + 1 < f.count; ++k) {
            out.tris.push_back({corner(0), corner(k), corner(k + 1)});
            out.where.push_back(f.where);
            out.region.push_back(f.region);
            out.corner.push_back({f.first, f.first + k, f.first + k + 1});
        }
    }
    return out;
}

// Welding (in file units) and compaction to the referenced vertices, keeping file order: the
// kept vertices go into out.mesh, tris are renumbered to them, the report counts the rest.
void weld_and_compact(const MeshSoup& soup, const ImportOptions& options, std::vector<Tri>& tris, ImportedMesh& out) {
    std::vector<int> weld;
    if (options.weld_tolerance > 0) weld = weld_within(soup.vertices, options.weld_tolerance / options.scale, soup.file);
    else if (soup.weld_by_position) weld = weld_exact(soup.vertices);
    else {
        weld.resize(soup.vertices.size());
        std::iota(weld.begin(), weld.end(), 0);
    }
    std::vector<char> used(soup.vertices.size(), 0);
    for (Tri& t : tris)
        for (int& v : t) used[v = weld[v]] = 1;
    std::vector<int> new_index(soup.vertices.size(), -1);
    SurfaceMesh& m = out.mesh;
    for (std::size_t v = 0; v < soup.vertices.size(); ++v) {
        if (weld[v] != static_cast<int>(v)) ++out.report.welded_vertices;
        else if (!used[v]) ++out.report.unreferenced_vertices;
        else {
            new_index[v] = static_cast<int>(m.vertices.size());
            m.vertices.push_back(soup.vertices[v]);
        }
    }
    for (Tri& t : tris)
        for (int& v : t) v = new_index[v];
}

// Degenerate triangles: a repeated corner, or corners (numerically) on one line: the sine of the
// angle at corner 0 below 1e-14.
void check_degenerate(const std::vector<Vec3>& V, const LocatedTriangles& lt, const std::string& file, bool welding) {
    for (std::size_t t = 0; t < lt.tris.size(); ++t) {
        const Tri& f = lt.tris[t];
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
            const int v = f[0] == f[1] || f[0] == f[2] ? f[0] : f[1];
            throw MeshFileError(file_error(
                file, lt.where[t], "degenerate triangle: two of its corners are the same vertex at " + format_point(V[v]),
                welding ? "remove the face (it may have collapsed when vertices were welded; a smaller weld_tolerance "
                          "may help)"
                        : "remove the face"));
        }
        const Vec3 e1 = V[f[1]] - V[f[0]], e2 = V[f[2]] - V[f[0]];
        if (!(e1.cross(e2).norm() > 1e-14 * e1.norm() * e2.norm()))
            throw MeshFileError(file_error(file, lt.where[t],
                                           "degenerate triangle with zero area: corners " + format_point(V[f[0]]) + ", " +
                                               format_point(V[f[1]]) + ", " + format_point(V[f[2]]) + " lie on one line",
                                           "remove the face or move its vertices apart"));
    }
}

// File units to metres.
void apply_scale(double scale, const std::string& file, SurfaceMesh& m) {
    if (scale == 1.0) return;
    for (Vec3& p : m.vertices) {
        const Vec3 q = p * scale;
        if (!q.allFinite())
            throw MeshFileError(file_error(file, "scale " + graph::format_number(scale) + " makes vertex " +
                                                     format_point(p) + " overflow",
                                           "use a smaller scale"));
        p = q;
    }
}

// Regions in order of first use; a name no face uses gets no region (an OBJ "o" line followed by
// "usemtl" names only the material's faces), so no region of an imported mesh is empty.
void assign_soup_regions(const MeshSoup& soup, const std::vector<int>& soup_region, SurfaceMesh& m) {
    std::vector<int> id_of(soup.region_names.size() + 1, -1);  // soup region + 1 -> mesh region
    m.region.resize(m.triangles.size());
    m.region_names.clear();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        int& id = id_of[std::size_t(soup_region[t] + 1)];
        if (id < 0) {
            id = static_cast<int>(m.region_names.size());
            m.region_names.push_back(soup_region[t] < 0 ? "default" : soup.region_names[std::size_t(soup_region[t])]);
        }
        m.region[t] = id;
    }
}

// Per-corner texture coordinates and normals where every corner has them (a file that gives them to
// only some faces gets none: a fragment mesh cannot interpolate what is missing). `before` are the
// triangles as triangulated, m.triangles the same after re-orientation: a flipped triangle's
// corners are matched by vertex.
void assign_corner_attributes(const MeshSoup& soup, const LocatedTriangles& lt, const std::vector<Tri>& before,
                              SurfaceMesh& m) {
    auto complete = [&](const std::vector<long long>& c, std::size_t n) {
        if (c.size() != soup.indices.size() || n == 0) return false;
        for (long long i : c)
            if (i < 0 || i >= static_cast<long long>(n)) return false;
        return true;
    };
    const bool uv = complete(soup.corner_uv, soup.uvs.size()), normal = complete(soup.corner_normal, soup.normals.size());
    if (uv) m.corner_uv.resize(m.triangles.size());
    if (normal) m.corner_normal.resize(m.triangles.size());
    for (std::size_t t = 0; t < m.triangles.size() && (uv || normal); ++t)
        for (int k = 0; k < 3; ++k) {
            int j = 0;
            while (j < 2 && before[t][j] != m.triangles[t][k]) ++j;
            const std::size_t c = lt.corner[t][std::size_t(j)];
            if (uv) m.corner_uv[t][k] = soup.uvs[std::size_t(soup.corner_uv[c])];
            if (normal) {
                const Vec3 n = soup.normals[std::size_t(soup.corner_normal[c])];
                m.corner_normal[t][k] = n.norm() > 0 ? Vec3(n.normalized()) : n;
            }
        }
}

}  // namespace

ImportedMesh build_surface_mesh(const MeshSoup& soup, const ImportOptions& options) {
    const std::string& file = soup.file;
    check_options_and_counts(soup, options);
    ImportedMesh out;
    ImportReport& rep = out.report;
    rep.file_vertices = soup.vertices.size();
    rep.file_faces = soup.faces.size();

    LocatedTriangles lt = fan_triangulate(soup);
    weld_and_compact(soup, options, lt.tris, out);
    SurfaceMesh& m = out.mesh;
    check_degenerate(m.vertices, lt, file, options.weld_tolerance > 0 || soup.weld_by_position);
    const std::vector<Tri> triangulated = lt.tris;
    const SurfaceCheckResult check = check_closed_surface(m.vertices, lt.tris, file, lt.where, options.reorient);
    rep.flipped_triangles = check.flipped_triangles;
    rep.components = check.components;

    apply_scale(options.scale, file, m);
    m.triangles = std::move(lt.tris);
    assign_soup_regions(soup, lt.region, m);
    assign_corner_attributes(soup, lt, triangulated, m);
    return out;
}

}  // namespace cf
