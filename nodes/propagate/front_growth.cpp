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

// One growth step (fig. 16). Each member below is one pass; grow_front calls them in order and
// repeats the passes from merge_short_edges on while undo_bad_triangles keeps nodes back.
class FrontGrower {
public:
    FrontGrower(SurfaceMesh& cracks, const CrackFront& front, const FrontMarkers& fm, const GrowthSettings& s)
        : cracks_(cracks), front_(front), fm_(fm), s_(s), N_(front.nodes.size()), n_(fm.per_edge), E_(front.num_edges()),
          lo_(s.min_factor * s.r_c), hi_(s.max_factor * s.r_c), v0_(cracks.vertices.size()), t0_(cracks.triangles.size()),
          no_split_(E_, 0) {}

    // New node positions (the window mean of each node's markers) and which nodes propagate.
    void choose_targets() {
        target_.resize(N_);
        moves_.resize(N_);
        for (std::size_t i = 0; i < N_; ++i) {
            target_[i] = window_mean(fm_, static_cast<long>(i * n_));
            moves_[i] = (target_[i] - cracks_.vertices[front_.nodes[i]]).norm() >= lo_ && (!s_.admissible || s_.admissible(target_[i]));
        }
    }

    // Old front triangle of each front edge: its normal is the reference orientation.
    void find_edge_normals() {
        edge_normal_.assign(E_, Vec3::Zero());
        std::map<std::pair<int, int>, Vec3> by_edge;
        for (std::size_t t = 0; t < t0_; ++t) {
            const Tri& tri = cracks_.triangles[t];
            const Vec3 nrm = triangle_normal(cracks_, t);
            for (int k = 0; k < 3; ++k) by_edge[{tri[k], tri[(k + 1) % 3]}] = nrm;
        }
        for (std::size_t e = 0; e < E_; ++e) {
            const int a = front_.nodes[e], b = front_.nodes[(e + 1) % N_];
            auto it = by_edge.find({a, b});
            if (it == by_edge.end()) it = by_edge.find({b, a});
            if (it != by_edge.end()) edge_normal_[e] = it->second;
        }
    }

    // Every attempt starts afresh from the targets (merging moves them).
    void start_attempt() {
        g_ = FrontGrowth{};
        nodes_.clear();
        sources_.clear();
        made_by_node_.clear();
        made_by_edge_.clear();
        triangle_edge_.clear();
        tgt_ = target_;
    }

    // Case (c): merge the new nodes of short edges whose ends both move (greedy along the front,
    // a node merges at most once, a closed front keeps at least three nodes).
    void merge_short_edges() {
        merged_with_.assign(N_, -1);
        std::size_t remaining = N_;
        for (std::size_t e = 0; e < E_; ++e) {
            const std::size_t i = e, j = (e + 1) % N_;
            if (!moves_[i] || !moves_[j] || merged_with_[i] >= 0 || merged_with_[j] >= 0) continue;
            if ((tgt_[i] - tgt_[j]).norm() > lo_) continue;
            if (front_.closed && remaining <= 3) continue;
            if (s_.admissible && !s_.admissible(0.5 * (tgt_[i] + tgt_[j]))) continue;
            merged_with_[i] = static_cast<long>(j);
            merged_with_[j] = static_cast<long>(i);
            const Vec3 mid = 0.5 * (tgt_[i] + tgt_[j]);
            tgt_[i] = tgt_[j] = mid;
            --remaining;
        }
    }

    // Vertex ids of the new nodes (a merged pair shares one).
    void add_new_nodes() {
        new_id_.assign(N_, -1);
        for (std::size_t i = 0; i < N_; ++i) {
            if (!moves_[i]) {
                new_id_[i] = front_.nodes[i];
                continue;
            }
            if (merged_with_[i] >= 0 && new_id_[merged_with_[i]] >= 0 && merged_with_[i] < static_cast<long>(i)) {
                new_id_[i] = new_id_[merged_with_[i]];
                continue;
            }
            new_id_[i] = static_cast<int>(cracks_.vertices.size());
            cracks_.vertices.push_back(tgt_[i]);
            made_by_node_.push_back(static_cast<long>(i));
            made_by_edge_.push_back(-1);
        }
    }

    // Triangulate edge by edge by case (a), (b) or (c); collect the new front in order.
    void triangulate_edges() {
        for (std::size_t e = 0; e < E_; ++e) triangulate_edge(e);
        if (!front_.closed) push_node(new_id_[N_ - 1], static_cast<double>((N_ - 1) * n_));
        if (front_.closed && nodes_.size() > 1 && nodes_.front() == nodes_.back()) {
            nodes_.pop_back();
            sources_.pop_back();
        }
    }

    // Validity of the new triangles (each new triangle belongs to one front edge): a node whose
    // triangle folds, is a sliver or crosses the surface stays this step, an edge whose split
    // made one is not split. Returns whether anything was held back (then the step is redone).
    bool undo_bad_triangles() {
        bool changed = false;
        for (std::size_t t = t0_; t < cracks_.triangles.size(); ++t) {
            const Tri& tri = cracks_.triangles[t];
            if (acceptable(tri, edge_normal_[triangle_edge_[t - t0_]])) continue;
            for (int v : tri) {
                if (v < static_cast<int>(v0_)) continue;
                const std::size_t k = static_cast<std::size_t>(v) - v0_;
                if (made_by_node_[k] >= 0 && moves_[made_by_node_[k]]) {
                    moves_[made_by_node_[k]] = 0;
                    changed = true;
                }
                if (made_by_edge_[k] >= 0 && !no_split_[made_by_edge_[k]]) {
                    no_split_[made_by_edge_[k]] = 1;
                    changed = true;
                }
            }
        }
        return changed;
    }

    FrontGrowth finish() {
        g_.front.nodes = nodes_;
        g_.front.closed = front_.closed;
        g_.front.region = front_.region;
        g_.added_vertices = cracks_.vertices.size() - v0_;
        g_.added_triangles = cracks_.triangles.size() - t0_;
        resample_markers();
        return g_;
    }

private:
    void add(int a, int b, int c, std::size_t edge) {
        cracks_.triangles.push_back({a, b, c});
        cracks_.region.push_back(front_.region);
        triangle_edge_.push_back(edge);
    }
    Vec3 P(int v) const { return cracks_.vertices[v]; }
    void push_node(int v, double source) {
        if (nodes_.empty() || nodes_.back() != v) {
            nodes_.push_back(v);
            sources_.push_back(source);
        }
    }

    void triangulate_edge(std::size_t e) {
        const std::size_t i = e, j = (e + 1) % N_;
        const int a = front_.nodes[i], b = front_.nodes[j];
        const int A = new_id_[i], B = new_id_[j];
        push_node(A, static_cast<double>(i * n_));
        if (!moves_[i] && !moves_[j]) return;  // edge stays on the front
        if (A == B) {                           // (c): one triangle onto the merged node
            add(b, a, A, e);
            ++g_.contracted;
            return;
        }
        const double len = (P(A) - P(B)).norm();
        const Vec3 split_point = range_mean(fm_, i * n_, (i + 1) * n_);
        if (len >= hi_ && !no_split_[e] && (!s_.admissible || s_.admissible(split_point))) {
            // (b): split at the mean of the edge's markers (twice the node sampling density)
            const int M = static_cast<int>(cracks_.vertices.size());
            cracks_.vertices.push_back(split_point);
            made_by_node_.push_back(-1);
            made_by_edge_.push_back(static_cast<long>(e));
            add(b, a, M, e);
            if (moves_[i]) add(a, A, M, e);
            if (moves_[j]) add(b, M, B, e);
            push_node(M, i * n_ + 0.5 * n_);
            ++g_.split;
            return;
        }
        // (a): two triangles with the shorter diagonal, or one if a single node moved.
        if (moves_[i] && moves_[j]) {
            if ((P(a) - P(B)).norm() <= (P(b) - P(A)).norm()) {
                add(b, a, B, e);
                add(a, A, B, e);
            } else {
                add(b, a, A, e);
                add(b, A, B, e);
            }
        } else if (moves_[i]) {
            add(b, a, A, e);
        } else {
            add(b, a, B, e);
        }
        ++g_.kept;
    }

    // Quality 4 sqrt(3) area / sum(edge^2), orientation against the old front triangle, and a
    // barycentric lattice (spacing 1/4, corners left to the node tests) inside the object.
    bool acceptable(const Tri& tri, const Vec3& ref) const {
        const Vec3 a = cracks_.vertices[tri[0]], b = cracks_.vertices[tri[1]], c = cracks_.vertices[tri[2]];
        const Vec3 nrm = (b - a).cross(c - a);
        const double sum = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
        const double quality = sum > 0 ? 2 * std::sqrt(3.0) * nrm.norm() / sum : 0;
        const bool oriented = ref.squaredNorm() == 0 || nrm.normalized().dot(ref) >= s_.min_normal_dot;
        bool crosses = false;  // a lattice point outside the object
        if (s_.inside)
            for (int i = 0; i <= 4 && !crosses; ++i)
                for (int j = 0; i + j <= 4 && !crosses; ++j) {
                    const int k = 4 - i - j;
                    if (i == 4 || j == 4 || k == 4) continue;  // the corners: nodes are checked on their own
                    crosses = !s_.inside((i * a + j * b + k * c) / 4.0);
                }
        if (!(quality >= s_.min_quality && oriented && !crosses)) return false;
        return !(s_.crosses_surface && s_.crosses_surface(a, b, c));
    }

    // Markers: the fine front is kept where it is and re-divided locally: the markers between the
    // old marker indices two consecutive new nodes grew from (a node's own marker, or the middle
    // of a split edge) become the n markers of the new edge, equally spaced in index along the old
    // polyline. Markers never migrate to another part of the front, so marker i n stays at the
    // fine-front point of node i even where parts of the front stopped at a surface. Each new
    // marker inherits the state of the nearest old marker, its SIFs becoming history.
    void resample_markers() {
        const std::size_t M = fm_.markers.size();
        g_.markers.closed = front_.closed;
        g_.markers.per_edge = fm_.per_edge;
        const std::size_t NN = nodes_.size();
        for (std::size_t k = 0; k < g_.front.num_edges(); ++k) {
            const double a = sources_[k];
            double b = sources_[(k + 1) % NN];
            if (front_.closed && b <= a) b += M;
            for (std::size_t m = 0; m < n_; ++m) emit_marker(a + (b - a) * m / n_);
        }
        if (!front_.closed && NN > 0) emit_marker(sources_.back());
    }
    void emit_marker(double u) {
        const std::size_t M = fm_.markers.size();
        if (front_.closed) u = std::fmod(std::fmod(u, double(M)) + M, double(M));
        else u = std::clamp(u, 0.0, double(M - 1));
        const std::size_t lo_i = static_cast<std::size_t>(std::floor(u));
        const std::size_t hi_i = front_.closed ? (lo_i + 1) % M : std::min(lo_i + 1, M - 1);
        const double w = u - std::floor(u);
        MarkerState m = fm_.markers[w < 0.5 ? lo_i : hi_i];
        m.position = (1 - w) * fm_.markers[lo_i].position + w * fm_.markers[hi_i].position;
        m.K_old = m.K;
        m.has_old = true;
        g_.markers.markers.push_back(m);
    }

    SurfaceMesh& cracks_;
    const CrackFront& front_;
    const FrontMarkers& fm_;
    const GrowthSettings& s_;
    const std::size_t N_, n_, E_;
    const double lo_, hi_;             // contract at or below lo_, split at or above hi_ [m]
    const std::size_t v0_, t0_;        // the mesh's sizes before this step
    std::vector<Vec3> target_;         // each node's window mean
    std::vector<char> moves_;          // whether node i propagates (cleared by undo_bad_triangles)
    std::vector<Vec3> edge_normal_;    // the old front triangle's normal per front edge
    std::vector<char> no_split_;       // edges whose split made a bad triangle
    // One attempt:
    FrontGrowth g_;
    std::vector<int> nodes_;           // the new front
    std::vector<double> sources_;      // per new front node: the old marker index it grew from
    std::vector<long> made_by_node_, made_by_edge_;  // which node (or split edge) made each new vertex
    std::vector<std::size_t> triangle_edge_;         // front edge of each new triangle
    std::vector<Vec3> tgt_;            // targets after merging
    std::vector<long> merged_with_;
    std::vector<int> new_id_;
};

}  // namespace

FrontGrowth grow_front(SurfaceMesh& cracks, const CrackFront& front, const FrontMarkers& fm, const GrowthSettings& s) {
    if (!(s.r_c > 0)) throw std::invalid_argument("grow_front: r_c must be > 0 [m]");
    const std::size_t N = front.nodes.size(), n = fm.per_edge;
    const std::size_t expected = front.closed ? N * n : (N == 0 ? 0 : (N - 1) * n + 1);
    if (fm.markers.size() != expected || fm.closed != front.closed)
        throw std::invalid_argument("grow_front: " + std::to_string(fm.markers.size()) + " markers do not belong to a front of " +
                                    std::to_string(N) + " nodes (expected " + std::to_string(expected) + ")");
    if (N == 0) {  // an empty front grows nothing (the open-front end node needs N > 0)
        FrontGrowth none;
        none.front = front;
        none.markers.closed = fm.closed;
        none.markers.per_edge = fm.per_edge;
        return none;
    }
    if (cracks.region.size() != cracks.triangles.size()) cracks.region.assign(cracks.triangles.size(), 0);
    FrontGrower grower(cracks, front, fm, s);
    grower.choose_targets();
    grower.find_edge_normals();
    const SurfaceMesh original = cracks;
    for (std::size_t attempt = 0;; ++attempt) {
        cracks = original;
        grower.start_attempt();
        grower.merge_short_edges();
        grower.add_new_nodes();
        grower.triangulate_edges();
        if (!grower.undo_bad_triangles() || attempt > N) break;
    }
    return grower.finish();
}

}  // namespace cf::propagate
