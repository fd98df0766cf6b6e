#include "nodes/import/check_closed_surface.hpp"

#include "graph/diagnostics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace cf {

namespace {

struct HalfEdge {
    int a, b;      // a < b
    int tri;
    bool forward;  // the triangle traverses a -> b
};

class Locator {
public:
    Locator(const std::string& file, const std::vector<FileLocation>& where) : file_(file), where_(where) {}
    std::string operator()(std::size_t t) const {
        if (t < where_.size()) return describe(file_, where_[t]);
        return file_ + ": triangle " + std::to_string(t);
    }
    // Within a message that already names the file: "line 17", "byte 684" or "triangle 5".
    std::string ref(std::size_t t) const {
        if (t < where_.size() && where_[t].line > 0) return "line " + std::to_string(where_[t].line);
        if (t < where_.size() && where_[t].byte_offset >= 0) return "byte " + std::to_string(where_[t].byte_offset);
        return "triangle " + std::to_string(t);
    }
    std::string error(std::size_t t, const std::string& what, const std::string& fix) const {
        return (*this)(t) + ": error: " + what + "; " + fix;
    }

private:
    const std::string& file_;
    const std::vector<FileLocation>& where_;
};

// Union-find over triangle corners, for fans around vertices.
struct DisjointSets {
    std::vector<int> parent;
    explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(int x, int y) {
        x = find(x), y = find(y);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
    }
};

int corner_of(const Tri& t, int v) { return t[0] == v ? 0 : t[1] == v ? 1 : 2; }

// Solid angle of triangle (a, b, c) seen from the origin, signed by orientation
// (Van Oosterom & Strackee 1983).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    return 2.0 * std::atan2(num, den);
}

// The checks of check_closed_surface, in order; each throws MeshFileError naming the file line of
// a triangle.
class ClosedSurfaceCheck {
public:
    ClosedSurfaceCheck(const std::vector<Vec3>& V, std::vector<Tri>& T, const std::string& file,
                       const std::vector<FileLocation>& where)
        : V(V), T(T), loc(file, where), nt(static_cast<int>(T.size())) {}

    // Half-edges sorted by (a, b, triangle); packed into integer pairs because sorting those is fast.
    void sort_half_edges() {
        std::vector<std::pair<std::uint64_t, std::uint64_t>> packed;
        packed.reserve(3 * T.size());
        for (int t = 0; t < nt; ++t)
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t u = static_cast<std::uint32_t>(T[t][k]), v = static_cast<std::uint32_t>(T[t][(k + 1) % 3]);
                packed.emplace_back(std::min(u, v) << 32 | std::max(u, v), std::uint64_t(t) << 1 | (u < v));
            }
        std::sort(packed.begin(), packed.end());
        edges.resize(packed.size());
        for (std::size_t i = 0; i < packed.size(); ++i)
            edges[i] = {static_cast<int>(packed[i].first >> 32), static_cast<int>(packed[i].first & 0xffffffffu),
                        static_cast<int>(packed[i].second >> 1), (packed[i].second & 1) != 0};
    }

    // Group equal edges: exactly two triangles each on a closed manifold surface.
    void pair_edges() {
        pairs.reserve(edges.size() / 2);
        std::size_t boundary = 0, first_boundary = 0;
        for (std::size_t i = 0; i < edges.size();) {
            std::size_t j = i;
            while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
            const std::size_t n = j - i;
            if (n > 2) {
                std::string places;
                for (std::size_t k = i; k < j && k < i + 4; ++k) places += (k > i ? ", " : "") + loc.ref(edges[k].tri);
                if (n > 4) places += ", ...";
                throw MeshFileError(loc.error(edges[i].tri,
                                              "non-manifold edge: " + edge_text(edges[i]) + " is shared by " +
                                                  std::to_string(n) + " triangles (" + places + ")",
                                              "each edge of a closed surface must belong to exactly 2 triangles; separate "
                                              "the parts that meet there or repair the mesh"));
            }
            if (n == 1) {
                if (boundary == 0) first_boundary = i;
                ++boundary;
            } else {
                pairs.push_back({edges[i].tri, edges[i + 1].tri, edges[i].forward == edges[i + 1].forward, i});
            }
            i = j;
        }
        if (boundary > 0)
            throw MeshFileError(loc.error(
                edges[first_boundary].tri,
                "the surface is open: " + std::to_string(boundary) + " edge" + (boundary > 1 ? "s are" : " is") +
                    " used by only one triangle, e.g. " + edge_text(edges[first_boundary]) + " of this triangle",
                "the object must be closed (watertight): fill the holes; if the mesh is split along seams (duplicate "
                "vertices at the same position) set weld_tolerance to a small length such as 1e-9 m"));
    }

    // Non-manifold vertices: the triangles around each vertex must form one fan.
    void check_vertex_fans() const {
        DisjointSets corners(3 * T.size());
        for (const Pair& p : pairs) {
            const HalfEdge& e = edges[p.first];
            for (int v : {e.a, e.b}) corners.unite(3 * p.t1 + corner_of(T[p.t1], v), 3 * p.t2 + corner_of(T[p.t2], v));
        }
        std::vector<int> fan_of_vertex(V.size(), -1);
        for (int t = 0; t < nt; ++t)
            for (int k = 0; k < 3; ++k) {
                const int v = T[t][k], fan = corners.find(3 * t + k);
                if (fan_of_vertex[v] < 0) fan_of_vertex[v] = fan;
                else if (fan_of_vertex[v] != fan)
                    throw MeshFileError(loc.error(
                        t,
                        "non-manifold vertex at " + format_point(V[v]) +
                            ": separate sheets of the surface touch only at this point (" + loc.ref(fan_of_vertex[v] / 3) +
                            " and this triangle)",
                        "separate the parts (move them apart) or merge them into one closed surface"));
            }
    }

    // Orientation: neighbours across an edge must traverse it in opposite directions.
    void check_consistent_orientation() const {
        for (const Pair& p : pairs)
            if (p.same_direction)
                throw MeshFileError(loc.error(
                    std::max(p.t1, p.t2),
                    "inconsistent orientation: the triangles at " + loc.ref(p.t1) + " and " + loc.ref(p.t2) +
                        " traverse " + edge_text(edges[p.first]) + " in the same direction, so one of them is flipped",
                    "fix the vertex order of the flipped faces, or set reorient: true to re-orient them automatically"));
    }

    // Adjacency (CSR) and breadth-first search per connected shell: each triangle's shell and
    // whether it must flip to agree with the shell's first triangle; flips them.
    void orient_shells(SurfaceCheckResult& result) {
        std::vector<int> start(nt + 1, 0);
        for (const Pair& p : pairs) ++start[p.t1 + 1], ++start[p.t2 + 1];
        for (int t = 0; t < nt; ++t) start[t + 1] += start[t];
        std::vector<std::pair<int, bool>> adj(start[nt]);
        {
            std::vector<int> fill(start.begin(), start.end() - 1);
            for (const Pair& p : pairs) {
                adj[fill[p.t1]++] = {p.t2, p.same_direction};
                adj[fill[p.t2]++] = {p.t1, p.same_direction};
            }
        }
        component.assign(nt, -1);
        flip.assign(nt, 0);
        std::vector<int> queue;
        queue.reserve(nt);
        for (int s = 0; s < nt; ++s) {
            if (component[s] >= 0) continue;
            const int c = static_cast<int>(first_of_component.size());
            first_of_component.push_back(s);
            component[s] = c;
            queue.clear();
            queue.push_back(s);
            for (std::size_t q = 0; q < queue.size(); ++q) {
                const int t = queue[q];
                for (int k = start[t]; k < start[t + 1]; ++k) {
                    const auto [u, same] = adj[k];
                    const char want = flip[t] ^ static_cast<char>(same);
                    if (component[u] < 0) {
                        component[u] = c;
                        flip[u] = want;
                        queue.push_back(u);
                    } else if (flip[u] != want) {
                        throw MeshFileError(loc.error(
                            u, "the surface containing this triangle is non-orientable (like a Moebius strip or Klein bottle)",
                            "a solid's boundary must have an inside and an outside; repair or remesh the object"));
                    }
                }
            }
        }
        for (int t = 0; t < nt; ++t)
            if (flip[t]) {
                std::swap(T[t][1], T[t][2]);
                ++result.flipped_triangles;
            }
        nc = static_cast<int>(first_of_component.size());
        result.components = nc;
    }

    // Signed volume and bounding box of each shell.
    void measure_shells() {
        volume.assign(nc, 0.0);
        lo.assign(nc, Vec3::Constant(INFINITY));
        hi.assign(nc, Vec3::Constant(-INFINITY));
        for (int t = 0; t < nt; ++t) {
            const int c = component[t];
            const Vec3& o = V[T[first_of_component[c]][0]];  // shell-local origin, for accuracy
            const Vec3 a = V[T[t][0]] - o, b = V[T[t][1]] - o, d = V[T[t][2]] - o;
            volume[c] += a.dot(b.cross(d)) / 6.0;
            for (int k = 0; k < 3; ++k) {
                lo[c] = lo[c].cwiseMin(V[T[t][k]]);
                hi[c] = hi[c].cwiseMax(V[T[t][k]]);
            }
        }
    }

    // Nesting depth of each shell: how many other shells contain one of its vertices
    // (|generalised winding number| ~ 1 inside a closed shell, ~ 0 outside).
    void nest_shells() {
        depth.assign(nc, 0);
        if (nc <= 1) return;
        std::vector<std::vector<int>> tris_of(nc);
        for (int t = 0; t < nt; ++t) tris_of[component[t]].push_back(t);
        for (int i = 0; i < nc; ++i) {
            const Vec3& p = V[T[first_of_component[i]][0]];
            for (int j = 0; j < nc; ++j) {
                if (j == i || (p.array() < lo[j].array()).any() || (p.array() > hi[j].array()).any()) continue;
                double w = 0;
                for (int t : tris_of[j]) w += solid_angle(V[T[t][0]] - p, V[T[t][1]] - p, V[T[t][2]] - p);
                if (std::abs(w) > 2.0 * M_PI) ++depth[i];  // |w / 4 pi| > 1/2
            }
        }
    }

    // Every shell encloses volume, outer shells point outwards and cavities inwards; with
    // `reorient` a shell the wrong way round is flipped instead of reported.
    void check_shell_orientation(bool reorient, SurfaceCheckResult& result) {
        for (int c = 0; c < nc; ++c) {
            const double size = (hi[c] - lo[c]).norm();
            const int t0 = first_of_component[c];
            if (!(std::abs(volume[c]) > 1e-12 * size * size * size))
                throw MeshFileError(loc.error(t0,
                                              "the closed shell containing this triangle encloses no volume (signed volume " +
                                                  graph::format_number(volume[c]) + " cubic file units; a doubled flat sheet?)",
                                              "remove the shell or give it thickness"));
            const bool cavity = depth[c] % 2 == 1;
            if ((volume[c] > 0) == !cavity) continue;
            if (reorient) {
                for (int t = 0; t < nt; ++t)
                    if (component[t] == c) {
                        std::swap(T[t][1], T[t][2]);
                        // A triangle flipped twice is back as the file had it.
                        if (flip[t]) --result.flipped_triangles;
                        else ++result.flipped_triangles;
                    }
                continue;
            }
            std::string what =
                nc == 1 ? "the surface is inside-out: its normals point inwards (signed volume " + graph::format_number(volume[c]) +
                              " cubic file units, should be positive)"
                : cavity ? "the closed shell containing this triangle lies inside " + std::to_string(depth[c]) +
                               " other shell(s), so it bounds a cavity and its normals should point into the cavity, but they "
                               "point outwards"
                         : "the closed shell containing this triangle is inside-out: its normals point inwards (signed "
                           "volume " + graph::format_number(volume[c]) + " cubic file units, should be positive)";
            throw MeshFileError(loc.error(t0, what, "set reorient: true to flip it, or flip its normals in your modelling tool"));
        }
    }

private:
    struct Pair {
        int t1, t2;
        bool same_direction;
        std::size_t first;
    };
    std::string edge_text(const HalfEdge& e) const {
        return "the edge from " + format_point(V[e.a]) + " to " + format_point(V[e.b]);
    }

    const std::vector<Vec3>& V;
    std::vector<Tri>& T;
    const Locator loc;
    const int nt;
    std::vector<HalfEdge> edges;
    std::vector<Pair> pairs;
    std::vector<int> component;  // each triangle's shell
    std::vector<char> flip;
    std::vector<int> first_of_component;
    int nc = 0;  // shells
    std::vector<double> volume;
    std::vector<Vec3> lo, hi;
    std::vector<int> depth;
};

}  // namespace

SurfaceCheckResult check_closed_surface(const std::vector<Vec3>& V, std::vector<Tri>& T, const std::string& file,
                                        const std::vector<FileLocation>& where, bool reorient) {
    SurfaceCheckResult result;
    ClosedSurfaceCheck check(V, T, file, where);
    check.sort_half_edges();
    check.pair_edges();
    check.check_vertex_fans();
    if (!reorient) check.check_consistent_orientation();
    check.orient_shells(result);
    check.measure_shells();
    check.nest_shells();
    check.check_shell_orientation(reorient, result);
    return result;
}

}  // namespace cf
