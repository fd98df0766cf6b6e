#include "nodes/domain/mesh_topology.hpp"

#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

namespace cf {
namespace {

struct DisjointSets {
    std::vector<std::size_t> parent;
    explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t{0}); }
    std::size_t find(std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
    void unite(std::size_t a, std::size_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

struct HalfEdge {
    int lo, hi;         // undirected key
    bool forward;       // traversed lo -> hi
    std::size_t tri;
};

bool valid_indices(const SurfaceMesh& m, const Tri& f) {
    const int n = static_cast<int>(m.vertices.size());
    for (int v : f)
        if (v < 0 || v >= n) return false;
    return f[0] != f[1] && f[1] != f[2] && f[2] != f[0];
}

// check_topology's steps, in the order it calls them.

// Triangles: valid ones (indices in range, three distinct corners) give their half-edges and
// mark their vertices used; invalid or (nearly) zero-area ones count as degenerate.
struct TriangleScan {
    std::vector<char> valid, used;  // per triangle, per vertex
    std::vector<HalfEdge> half;
};

TriangleScan scan_triangles(const SurfaceMesh& m, double degenerate_ratio, MeshTopologyReport& r) {
    TriangleScan s;
    s.valid.assign(m.triangles.size(), 0);
    s.half.reserve(3 * m.triangles.size());
    s.used.assign(m.vertices.size(), 0);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Tri& f = m.triangles[t];
        if (!valid_indices(m, f)) {
            ++r.degenerate_triangles;
            continue;
        }
        s.valid[t] = 1;
        double longest = 0;
        for (int k = 0; k < 3; ++k)
            longest = std::max(longest, (m.vertices[f[(k + 1) % 3]] - m.vertices[f[k]]).squaredNorm());
        if (triangle_normal_unnormalised(m, t).norm() <= degenerate_ratio * longest) ++r.degenerate_triangles;
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3];
            s.half.push_back({std::min(a, b), std::max(a, b), a < b, t});
            s.used[a] = 1;
        }
    }
    return s;
}

// Edges: half-edges grouped by their undirected key, counted by use; triangles sharing an edge
// are united into pieces.
void count_edges(std::vector<HalfEdge>& half, DisjointSets& pieces, MeshTopologyReport& r) {
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.tri < y.tri;
    });
    for (std::size_t i = 0; i < half.size();) {
        const HalfEdge& e = half[i];
        std::size_t uses = 1;
        bool same_direction = false;
        for (; i + uses < half.size() && half[i + uses].lo == e.lo && half[i + uses].hi == e.hi; ++uses) {
            pieces.unite(e.tri, half[i + uses].tri);
            same_direction = same_direction || half[i + uses].forward == e.forward;
        }
        ++r.edges;
        if (uses == 1) ++r.boundary_edges;
        else if (uses > 2) ++r.nonmanifold_edges;
        else if (same_direction) ++r.misoriented_edges;
        i += uses;
    }
}

// Vertices: the triangles around a manifold vertex form one fan (a disc or, on a boundary,
// a half-disc); two fans touching only at the vertex make it non-manifold ("bow tie").
void count_vertices(const SurfaceMesh& m, const TriangleScan& s, MeshTopologyReport& r) {
    std::vector<std::size_t> start(m.vertices.size() + 1, 0);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (s.valid[t])
            for (int v : m.triangles[t]) ++start[v + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::size_t> incident(start.back()), fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (s.valid[t])
            for (int v : m.triangles[t]) incident[fill[v]++] = t;
    std::vector<std::pair<int, std::size_t>> spokes;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        if (!s.used[v]) {
            ++r.unreferenced_vertices;
            continue;
        }
        ++r.vertices;
        const std::size_t n = start[v + 1] - start[v];
        DisjointSets fans(n);
        // (other vertex, local triangle): triangles listing the same other vertex share that edge.
        spokes.clear();
        for (std::size_t k = 0; k < n; ++k)
            for (int w : m.triangles[incident[start[v] + k]])
                if (w != static_cast<int>(v)) spokes.emplace_back(w, k);
        std::sort(spokes.begin(), spokes.end());
        for (std::size_t k = 1; k < spokes.size(); ++k)
            if (spokes[k].first == spokes[k - 1].first) fans.unite(spokes[k].second, spokes[k - 1].second);
        std::size_t roots = 0;
        for (std::size_t k = 0; k < n; ++k) roots += fans.find(k) == k;
        if (roots > 1) ++r.nonmanifold_vertices;
    }
}

}  // namespace

MeshTopologyReport check_topology(const SurfaceMesh& m, double degenerate_ratio) {
    MeshTopologyReport r;
    r.triangles = m.triangles.size();
    TriangleScan s = scan_triangles(m, degenerate_ratio, r);
    DisjointSets pieces(m.triangles.size());
    count_edges(s.half, pieces, r);
    count_vertices(m, s, r);
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        if (s.valid[t] && pieces.find(t) == t) ++r.components;
    const auto faces = static_cast<long long>(std::count(s.valid.begin(), s.valid.end(), 1));
    r.euler_characteristic = static_cast<long long>(r.vertices) - static_cast<long long>(r.edges) + faces;
    return r;
}

std::vector<int> triangle_components(const SurfaceMesh& m) {
    MeshTopologyReport r;
    TriangleScan s = scan_triangles(m, 0, r);
    DisjointSets pieces(m.triangles.size());
    count_edges(s.half, pieces, r);
    std::vector<int> label(m.triangles.size(), -1), of_root(m.triangles.size(), -1);
    int n = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        if (!s.valid[t]) continue;
        int& root_label = of_root[pieces.find(t)];
        if (root_label < 0) root_label = n++;
        label[t] = root_label;
    }
    return label;
}

std::string MeshTopologyReport::describe() const {
    std::string s;
    auto add = [&s](std::size_t n, const char* what) {
        if (n == 0) return;
        s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + what;
    };
    if (triangles == 0) return "no triangles";
    add(boundary_edges, "boundary edges (holes: the surface is not closed)");
    add(nonmanifold_edges, "edges shared by more than two triangles");
    add(nonmanifold_vertices, "non-manifold vertices (fans touching at a point)");
    add(misoriented_edges, "edges whose two triangles disagree in orientation (flipped triangles)");
    add(degenerate_triangles, "degenerate triangles (repeated or invalid vertices, or zero area)");
    if (s.empty()) return "closed 2-manifold, consistently oriented";
    return s;
}

}  // namespace cf
