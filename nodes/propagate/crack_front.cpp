#include "nodes/propagate/crack_front.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace cf::propagate {

FrontFrame orthonormalised(const Vec3& n1_in, const Vec3& n3_in) {
    const double l1 = n1_in.norm();
    if (!(l1 > 0)) throw std::invalid_argument("crack-front frame: zero surface normal");
    FrontFrame f;
    f.n1 = n1_in / l1;
    const Vec3 t = n3_in - n3_in.dot(f.n1) * f.n1;
    const double l3 = t.norm();
    if (!(l3 > 1e-12 * n3_in.norm()) || !(l3 > 0))
        throw std::invalid_argument("crack-front frame: tangent vanishes or is parallel to the normal");
    f.n3 = t / l3;
    f.n2 = f.n3.cross(f.n1);
    return f;
}

std::vector<CrackFront> extract_fronts(const SurfaceMesh& cracks) {
    // Directed edges; a boundary edge a -> b has no twin b -> a.
    std::map<std::pair<int, int>, int> directed;  // edge -> triangle
    for (std::size_t t = 0; t < cracks.num_triangles(); ++t) {
        const Tri& tri = cracks.triangles[t];
        for (int k = 0; k < 3; ++k) directed[{tri[k], tri[(k + 1) % 3]}] = static_cast<int>(t);
    }
    std::map<int, int> next;   // boundary successor
    std::map<int, int> region; // region of the boundary edge starting at a vertex
    for (const auto& [e, t] : directed) {
        if (directed.count({e.second, e.first})) continue;
        if (next.count(e.first))
            throw std::invalid_argument("crack sheets: vertex " + std::to_string(e.first) +
                                        " starts two front edges (sheets touching at a vertex)");
        next[e.first] = e.second;
        region[e.first] = cracks.region_of(t);
    }
    std::vector<CrackFront> fronts;
    std::map<int, bool> used;
    for (const auto& [start, unused] : next) {
        if (used[start]) continue;
        CrackFront f;
        f.closed = true;
        f.region = region[start];
        int v = start;
        do {
            used[v] = true;
            f.nodes.push_back(v);
            const auto it = next.find(v);
            if (it == next.end()) throw std::invalid_argument("crack sheets: front stops at vertex " + std::to_string(v));
            v = it->second;
            if (v != start && used[v])
                throw std::invalid_argument("crack sheets: front revisits vertex " + std::to_string(v));
        } while (v != start);
        fronts.push_back(std::move(f));
    }
    std::stable_sort(fronts.begin(), fronts.end(), [](const CrackFront& a, const CrackFront& b) { return a.region < b.region; });
    return fronts;
}

void assign_node_sifs(CrackFront& front, const std::vector<EdgeSifs>& edges) {
    std::map<std::pair<int, int>, const EdgeSifs*> by_edge;
    for (const EdgeSifs& e : edges) by_edge[{e.v0, e.v1}] = &e;
    const std::size_t n = front.nodes.size(), ne = front.num_edges();
    std::vector<const EdgeSifs*> edge(ne);
    for (std::size_t i = 0; i < ne; ++i) {
        const int a = front.nodes[i], b = front.nodes[(i + 1) % n];
        auto it = by_edge.find({a, b});
        if (it == by_edge.end()) it = by_edge.find({b, a});
        if (it == by_edge.end())
            throw std::invalid_argument("no SIFs for crack-front edge " + std::to_string(a) + " -> " + std::to_string(b));
        edge[i] = it->second;
    }
    front.sifs.assign(n, Sifs{});
    front.frames.assign(n, FrontFrame{});
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<const EdgeSifs*> adj;
        if (front.closed || i > 0) adj.push_back(edge[(i + ne - 1) % ne]);
        if (front.closed || i + 1 < n) adj.push_back(edge[i % ne]);
        Sifs K;
        Vec3 n1 = Vec3::Zero(), n3 = Vec3::Zero();
        for (const EdgeSifs* e : adj) {
            const double w = 1.0 / adj.size();
            K.KI += w * e->K.KI;
            K.KII += w * e->K.KII;
            K.KIII += w * e->K.KIII;
            n1 += w * e->frame.n1;
            n3 += w * e->frame.n3;
        }
        front.sifs[i] = K;
        front.frames[i] = orthonormalised(n1, n3);
    }
}

}  // namespace cf::propagate
