#include "nodes/propagate/front_growth.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace cf::propagate {

namespace {

// Mean of the n markers centred on marker index `centre` (wrapping on closed fronts). The end
// nodes of an open front follow their own end marker: a clipped window would pull them inwards.
Vec3 window_mean(const FrontMarkers& fm, long centre) {
    const long M = static_cast<long>(fm.markers.size()), n = fm.per_edge;
    if (!fm.closed && (centre == 0 || centre == M - 1)) return fm.markers[centre].position;
    const long first = centre - n / 2;
    Vec3 sum = Vec3::Zero();
    int count = 0;
    for (long m = first; m < first + n; ++m) {
        long idx = m;
        if (fm.closed) idx = ((m % M) + M) % M;
        else if (m < 0 || m >= M) continue;
        sum += fm.markers[idx].position;
        ++count;
    }
    return sum / count;
}

// Mean of the markers first..last (inclusive, wrapping on closed fronts).
Vec3 range_mean(const FrontMarkers& fm, std::size_t first, std::size_t last) {
    Vec3 sum = Vec3::Zero();
    for (std::size_t m = first; m <= last; ++m) sum += fm.markers[m % fm.markers.size()].position;
    return sum / static_cast<double>(last - first + 1);
}

}  // namespace

FrontGrowth grow_front(SurfaceMesh& cracks, const CrackFront& front, const FrontMarkers& fm, const GrowthSettings& s) {
    if (!(s.r_c > 0)) throw std::invalid_argument("grow_front: r_c must be > 0 [m]");
    const std::size_t N = front.nodes.size(), n = fm.per_edge, E = front.num_edges();
    const std::size_t expected = front.closed ? N * n : (N == 0 ? 0 : (N - 1) * n + 1);
    if (fm.markers.size() != expected || fm.closed != front.closed)
        throw std::invalid_argument("grow_front: " + std::to_string(fm.markers.size()) + " markers do not belong to a front of " +
                                    std::to_string(N) + " nodes (expected " + std::to_string(expected) + ")");
    if (N == 0) {  // an empty front grows nothing (the open-front end node below needs N > 0)
        FrontGrowth none;
        none.front = front;
        none.markers.closed = fm.closed;
        none.markers.per_edge = fm.per_edge;
        return none;
    }
    const double lo = s.min_factor * s.r_c, hi = s.max_factor * s.r_c;
    if (cracks.region.size() != cracks.triangles.size()) cracks.region.assign(cracks.triangles.size(), 0);
    const std::size_t v0 = cracks.vertices.size(), t0 = cracks.triangles.size();
    FrontGrowth g;

    // New node positions and which nodes propagate.
    std::vector<Vec3> target(N);
    std::vector<char> moves(N);
    for (std::size_t i = 0; i < N; ++i) {
        target[i] = window_mean(fm, static_cast<long>(i * n));
        moves[i] = (target[i] - cracks.vertices[front.nodes[i]]).norm() >= lo && (!s.admissible || s.admissible(target[i]));
    }
    // Old front triangle of each front edge: its normal is the reference orientation.
    std::vector<Vec3> edge_normal(E, Vec3::Zero());
    {
        std::map<std::pair<int, int>, Vec3> by_edge;
        for (std::size_t t = 0; t < t0; ++t) {
            const Tri& tri = cracks.triangles[t];
            const Vec3 nrm = triangle_normal(cracks, t);
            for (int k = 0; k < 3; ++k) by_edge[{tri[k], tri[(k + 1) % 3]}] = nrm;
        }
        for (std::size_t e = 0; e < E; ++e) {
            const int a = front.nodes[e], b = front.nodes[(e + 1) % N];
            auto it = by_edge.find({a, b});
            if (it == by_edge.end()) it = by_edge.find({b, a});
            if (it != by_edge.end()) edge_normal[e] = it->second;
        }
    }
    std::vector<char> no_split(E, 0);
    const SurfaceMesh original = cracks;
    std::vector<int> nodes;
    std::vector<double> sources;  // per new front node: the old marker index it grew from
    for (std::size_t attempt = 0;; ++attempt) {
        cracks = original;
        g = FrontGrowth{};
        nodes.clear();
        sources.clear();
        // Which front node (or split edge) made each new vertex, to undo a bad move.
        std::vector<long> made_by_node, made_by_edge;
        std::vector<std::size_t> triangle_edge;  // front edge of each new triangle
        std::vector<Vec3> tgt = target;          // merging moves targets; every attempt starts afresh
        // Case (c): merge the new nodes of short edges whose ends both move (greedy along the front,
        // a node merges at most once, a closed front keeps at least three nodes).
        std::vector<long> merged_with(N, -1);
        std::size_t remaining = N;
        for (std::size_t e = 0; e < E; ++e) {
            const std::size_t i = e, j = (e + 1) % N;
            if (!moves[i] || !moves[j] || merged_with[i] >= 0 || merged_with[j] >= 0) continue;
            if ((tgt[i] - tgt[j]).norm() > lo) continue;
            if (front.closed && remaining <= 3) continue;
            if (s.admissible && !s.admissible(0.5 * (tgt[i] + tgt[j]))) continue;
            merged_with[i] = static_cast<long>(j);
            merged_with[j] = static_cast<long>(i);
            const Vec3 mid = 0.5 * (tgt[i] + tgt[j]);
            tgt[i] = tgt[j] = mid;
            --remaining;
        }
        // Vertex ids of the new nodes (a merged pair shares one).
        std::vector<int> new_id(N, -1);
        for (std::size_t i = 0; i < N; ++i) {
            if (!moves[i]) {
                new_id[i] = front.nodes[i];
                continue;
            }
            if (merged_with[i] >= 0 && new_id[merged_with[i]] >= 0 && merged_with[i] < static_cast<long>(i)) {
                new_id[i] = new_id[merged_with[i]];
                continue;
            }
            new_id[i] = static_cast<int>(cracks.vertices.size());
            cracks.vertices.push_back(tgt[i]);
            made_by_node.push_back(static_cast<long>(i));
            made_by_edge.push_back(-1);
        }
        std::size_t current_edge = 0;
        auto add = [&](int a, int b, int c) {
            cracks.triangles.push_back({a, b, c});
            cracks.region.push_back(front.region);
            triangle_edge.push_back(current_edge);
        };
        auto P = [&](int v) { return cracks.vertices[v]; };

        // Triangulate edge by edge; collect the new front in order.
        auto push_node = [&](int v, double source) {
            if (nodes.empty() || nodes.back() != v) {
                nodes.push_back(v);
                sources.push_back(source);
            }
        };
        for (std::size_t e = 0; e < E; ++e) {
            const std::size_t i = e, j = (e + 1) % N;
            const int a = front.nodes[i], b = front.nodes[j];
            const int A = new_id[i], B = new_id[j];
            current_edge = e;
            push_node(A, static_cast<double>(i * n));
            if (!moves[i] && !moves[j]) continue;  // edge stays on the front
            if (A == B) {                          // (c): one triangle onto the merged node
                add(b, a, A);
                ++g.contracted;
                continue;
            }
            const double len = (P(A) - P(B)).norm();
            const Vec3 split_point = range_mean(fm, i * n, (i + 1) * n);
            if (len >= hi && !no_split[e] && (!s.admissible || s.admissible(split_point))) {
                // (b): split at the mean of the edge's markers (twice the node sampling density)
                const int M = static_cast<int>(cracks.vertices.size());
                cracks.vertices.push_back(split_point);
                made_by_node.push_back(-1);
                made_by_edge.push_back(static_cast<long>(e));
                add(b, a, M);
                if (moves[i]) add(a, A, M);
                if (moves[j]) add(b, M, B);
                push_node(M, i * n + 0.5 * n);
                ++g.split;
                continue;
            }
            // (a): two triangles with the shorter diagonal, or one if a single node moved.
            if (moves[i] && moves[j]) {
                if ((P(a) - P(B)).norm() <= (P(b) - P(A)).norm()) {
                    add(b, a, B);
                    add(a, A, B);
                } else {
                    add(b, a, A);
                    add(b, A, B);
                }
            } else if (moves[i]) {
                add(b, a, A);
            } else {
                add(b, a, B);
            }
            ++g.kept;
        }
        if (!front.closed) push_node(new_id[N - 1], static_cast<double>((N - 1) * n));
        if (front.closed && nodes.size() > 1 && nodes.front() == nodes.back()) {
            nodes.pop_back();
            sources.pop_back();
        }
        // Validity of the new triangles (each new triangle belongs to one front edge).
        bool changed = false;
        for (std::size_t t = t0; t < cracks.triangles.size(); ++t) {
            const Tri& tri = cracks.triangles[t];
            const Vec3 a = cracks.vertices[tri[0]], b = cracks.vertices[tri[1]], c = cracks.vertices[tri[2]];
            const Vec3 nrm = (b - a).cross(c - a);
            const double sum = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
            const double quality = sum > 0 ? 2 * std::sqrt(3.0) * nrm.norm() / sum : 0;
            const Vec3& ref = edge_normal[triangle_edge[t - t0]];
            const bool oriented = ref.squaredNorm() == 0 || nrm.normalized().dot(ref) >= s.min_normal_dot;
            bool crosses = false;  // a lattice point outside the object
            if (s.inside)
                for (int i = 0; i <= 4 && !crosses; ++i)
                    for (int j = 0; i + j <= 4 && !crosses; ++j) {
                        const int k = 4 - i - j;
                        if (i == 4 || j == 4 || k == 4) continue;  // the corners: nodes are checked on their own
                        crosses = !s.inside((i * a + j * b + k * c) / 4.0);
                    }
            if (quality >= s.min_quality && oriented && !crosses) continue;
            for (int v : tri) {
                if (v < static_cast<int>(v0)) continue;
                const std::size_t k = static_cast<std::size_t>(v) - v0;
                if (made_by_node[k] >= 0 && moves[made_by_node[k]]) {
                    moves[made_by_node[k]] = 0;
                    changed = true;
                }
                if (made_by_edge[k] >= 0 && !no_split[made_by_edge[k]]) {
                    no_split[made_by_edge[k]] = 1;
                    changed = true;
                }
            }
        }
        if (!changed || attempt > N) break;
    }
    g.front.nodes = nodes;
    g.front.closed = front.closed;
    g.front.region = front.region;
    g.added_vertices = cracks.vertices.size() - v0;
    g.added_triangles = cracks.triangles.size() - t0;

    // Markers: the fine front is kept where it is and re-divided locally: the markers between the
    // old marker indices two consecutive new nodes grew from (a node's own marker, or the middle
    // of a split edge) become the n markers of the new edge, equally spaced in index along the old
    // polyline. Markers never migrate to another part of the front, so marker i n stays at the
    // fine-front point of node i even where parts of the front stopped at a surface. Each new
    // marker inherits the state of the nearest old marker, its SIFs becoming history.
    const std::size_t M = fm.markers.size();
    g.markers.closed = front.closed;
    g.markers.per_edge = fm.per_edge;
    auto emit = [&](double u) {
        if (front.closed) u = std::fmod(std::fmod(u, double(M)) + M, double(M));
        else u = std::clamp(u, 0.0, double(M - 1));
        const std::size_t lo_i = static_cast<std::size_t>(std::floor(u));
        const std::size_t hi_i = front.closed ? (lo_i + 1) % M : std::min(lo_i + 1, M - 1);
        const double w = u - std::floor(u);
        MarkerState m = fm.markers[w < 0.5 ? lo_i : hi_i];
        m.position = (1 - w) * fm.markers[lo_i].position + w * fm.markers[hi_i].position;
        m.K_old = m.K;
        m.has_old = true;
        g.markers.markers.push_back(m);
    };
    const std::size_t NN = nodes.size();
    for (std::size_t k = 0; k < g.front.num_edges(); ++k) {
        const double a = sources[k];
        double b = sources[(k + 1) % NN];
        if (front.closed && b <= a) b += M;
        for (std::size_t m = 0; m < n; ++m) emit(a + (b - a) * m / n);
    }
    if (!front.closed && NN > 0) emit(sources.back());
    return g;
}

}  // namespace cf::propagate
