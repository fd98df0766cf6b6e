#include "nodes/propagate/front_growth.hpp"

#include <algorithm>
#include <cmath>
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
    // Case (c): merge the new nodes of short edges whose ends both move (greedy along the front,
    // a node merges at most once, a closed front keeps at least three nodes).
    std::vector<long> merged_with(N, -1);
    std::size_t remaining = N;
    for (std::size_t e = 0; e < E; ++e) {
        const std::size_t i = e, j = (e + 1) % N;
        if (!moves[i] || !moves[j] || merged_with[i] >= 0 || merged_with[j] >= 0) continue;
        if ((target[i] - target[j]).norm() > lo) continue;
        if (front.closed && remaining <= 3) continue;
        if (s.admissible && !s.admissible(0.5 * (target[i] + target[j]))) continue;
        merged_with[i] = static_cast<long>(j);
        merged_with[j] = static_cast<long>(i);
        const Vec3 mid = 0.5 * (target[i] + target[j]);
        target[i] = target[j] = mid;
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
        cracks.vertices.push_back(target[i]);
    }
    auto add = [&](int a, int b, int c) {
        cracks.triangles.push_back({a, b, c});
        cracks.region.push_back(front.region);
    };
    auto P = [&](int v) { return cracks.vertices[v]; };

    // Triangulate edge by edge; collect the new front in order.
    std::vector<int> nodes;
    auto push_node = [&](int v) {
        if (nodes.empty() || nodes.back() != v) nodes.push_back(v);
    };
    for (std::size_t e = 0; e < E; ++e) {
        const std::size_t i = e, j = (e + 1) % N;
        const int a = front.nodes[i], b = front.nodes[j];
        const int A = new_id[i], B = new_id[j];
        push_node(A);
        if (!moves[i] && !moves[j]) continue;  // edge stays on the front
        if (A == B) {                          // (c): one triangle onto the merged node
            add(b, a, A);
            ++g.contracted;
            continue;
        }
        const double len = (P(A) - P(B)).norm();
        const Vec3 split_point = range_mean(fm, i * n, (i + 1) * n);
        if (len >= hi && (!s.admissible || s.admissible(split_point))) {
            // (b): split at the mean of the edge's markers (twice the node sampling density)
            const int M = static_cast<int>(cracks.vertices.size());
            cracks.vertices.push_back(split_point);
            add(b, a, M);
            if (moves[i]) add(a, A, M);
            if (moves[j]) add(b, M, B);
            push_node(M);
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
    if (!front.closed) push_node(new_id[N - 1]);
    if (front.closed && nodes.size() > 1 && nodes.front() == nodes.back()) nodes.pop_back();

    g.front.nodes = nodes;
    g.front.closed = front.closed;
    g.front.region = front.region;
    g.added_vertices = cracks.vertices.size() - v0;
    g.added_triangles = cracks.triangles.size() - t0;

    // Markers: the high-resolution polyline is kept and re-sampled to n per new edge, starting
    // (closed fronts) at the polyline point nearest to the new first node; each new marker
    // inherits the state of the nearest old marker, its SIFs becoming history.
    const std::vector<Vec3> old = fm.positions();
    const std::size_t new_edges = g.front.num_edges();
    const std::size_t count = front.closed ? new_edges * n : new_edges * n + 1;
    double start = 0;
    if (front.closed && !nodes.empty()) {
        double best = 1e300, arc = 0;
        for (std::size_t k = 0; k < old.size(); ++k) {
            const Vec3& p = old[k];
            const Vec3& q = old[(k + 1) % old.size()];
            const Vec3 d = q - p;
            const double l2 = d.squaredNorm();
            const double t = l2 > 0 ? std::clamp((P(nodes[0]) - p).dot(d) / l2, 0.0, 1.0) : 0.0;
            const double dist = (P(nodes[0]) - (p + t * d)).norm();
            if (dist < best) {
                best = dist;
                start = arc + t * std::sqrt(l2);
            }
            arc += std::sqrt(l2);
        }
    }
    const std::vector<Vec3> pos = resample_polyline(old, front.closed, count, start);
    g.markers.closed = front.closed;
    g.markers.per_edge = fm.per_edge;
    for (const Vec3& p : pos) {
        std::size_t near = 0;
        for (std::size_t k = 1; k < old.size(); ++k)
            if ((old[k] - p).squaredNorm() < (old[near] - p).squaredNorm()) near = k;
        MarkerState m = fm.markers[near];
        m.position = p;
        m.K_old = m.K;
        m.has_old = true;
        g.markers.markers.push_back(m);
    }
    return g;
}

}  // namespace cf::propagate
