#include "nodes/simplify/quality_repair.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace cf {

namespace {

constexpr double kFlatFlipDeg = 160;      // a flip moves the surface only between nearly coplanar triangles
constexpr double kMaxNormalTurnCos = 0.7071;  // cos 45 deg: a collapse or move must not bend the surface more

// One candidate change: triangles `removed` are replaced by `added` (added[i] takes the place of
// removed[from[i]] for the normal check, or -1 if new), vertices in `moved` get new positions.
struct Change {
    std::vector<int> removed;
    std::vector<Tri> added;
    std::vector<int> from;
    std::vector<std::pair<int, Vec3>> moved;
    int kind = 0;  // 0 flip, 1 collapse, 2 move, 3 split (moved[0] is then the new vertex)
};

class QualityImprover {
public:
    QualityImprover(SurfaceMesh& m, const QualityBounds& b, const SurfaceProjection& project)
        : m_(m), b_(b), project_(project), alive_(m.triangles.size(), 1), star_(m.vertices.size()) {
        for (std::size_t t = 0; t < m_.triangles.size(); ++t) add_triangle_index(int(t));
    }

    QualityRepair run(int max_passes) {
        QualityRepair out;
        for (int pass = 0; pass < max_passes; ++pass) {
            bool changed = false;
            for (std::size_t t = 0; t < m_.triangles.size(); ++t) {
                if (!alive_[t] || !bad(int(t))) continue;
                if (fix(int(t), out)) changed = true;
            }
            if (!changed) break;
        }
        compact();
        out.after = measure_quality(m_, b_.min_angle_deg, b_.min_dihedral_deg);
        return out;
    }

private:
    SurfaceMesh& m_;
    QualityBounds b_;
    const SurfaceProjection& project_;
    std::vector<char> alive_;
    std::vector<std::vector<int>> star_;          // vertex -> triangles (dead ones filtered on use)
    std::unordered_map<long long, int> half_;     // directed edge -> live triangle

    static long long key(int a, int b) { return (static_cast<long long>(a) << 32) | static_cast<long long>(static_cast<unsigned>(b)); }

    void add_triangle_index(int t) {
        const Tri& f = m_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            star_[f[k]].push_back(t);
            half_[key(f[k], f[(k + 1) % 3])] = t;
        }
    }
    void remove_triangle_index(int t) {
        const Tri& f = m_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            auto it = half_.find(key(f[k], f[(k + 1) % 3]));
            if (it != half_.end() && it->second == t) half_.erase(it);
            auto& s = star_[f[k]];
            s.erase(std::remove(s.begin(), s.end(), t), s.end());
        }
        alive_[t] = 0;
    }
    int across(int a, int b) const {  // live triangle holding directed edge a -> b, or -1
        const auto it = half_.find(key(a, b));
        return it == half_.end() ? -1 : it->second;
    }

    Vec3 normal(const Tri& f, const Change* c = nullptr) const {
        const Vec3 a = pos(f[0], c), b = pos(f[1], c), cc = pos(f[2], c);
        return (b - a).cross(cc - a);
    }
    Vec3 pos(int v, const Change* c) const {
        if (c)
            for (const auto& [w, p] : c->moved)
                if (w == v) return p;
        return m_.vertices[v];
    }
    double angle_q(const Tri& f, const Change* c = nullptr) const {
        return min_triangle_angle_deg(pos(f[0], c), pos(f[1], c), pos(f[2], c)) / b_.min_angle_deg;
    }
    double dihedral_q(const Vec3& n1, const Vec3& n2) const { return dihedral_deg(n1, n2) / b_.min_dihedral_deg; }

    bool bad(int t) const {
        const Tri& f = m_.triangles[t];
        if (angle_q(f) < 1) return true;
        const Vec3 n = normal(f);
        for (int k = 0; k < 3; ++k) {
            const int o = across(f[(k + 1) % 3], f[k]);
            if (o >= 0 && dihedral_q(n, normal(m_.triangles[o])) < 1) return true;
        }
        return false;
    }

    // Worst normalised quality over the triangles `tris` and every edge they have (neighbours
    // looked up in `tris` first, then among the live triangles not in `excluded`); -inf if an
    // edge has no neighbour or two (the change would break the manifold).
    double score(const std::vector<Tri>& tris, const std::vector<int>& excluded, const Change* c) const {
        double s = std::numeric_limits<double>::infinity();
        std::unordered_map<long long, int> local;
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const Tri& f = tris[i];
            if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return -std::numeric_limits<double>::infinity();
            for (int k = 0; k < 3; ++k)
                if (!local.emplace(key(f[k], f[(k + 1) % 3]), int(i)).second) return -std::numeric_limits<double>::infinity();
        }
        for (std::size_t i = 0; i < tris.size(); ++i) {
            const Tri& f = tris[i];
            s = std::min(s, angle_q(f, c));
            const Vec3 n = normal(f, c);
            for (int k = 0; k < 3; ++k) {
                const int a = f[k], b = f[(k + 1) % 3];
                // A directed edge also held by a live outside triangle: two triangles on one side.
                const int same = across(a, b);
                if (same >= 0 && std::find(excluded.begin(), excluded.end(), same) == excluded.end())
                    return -std::numeric_limits<double>::infinity();
                Vec3 n2;
                const auto it = local.find(key(b, a));
                if (it != local.end()) {
                    n2 = normal(tris[it->second], c);
                } else {
                    const int o = across(b, a);
                    if (o < 0 || std::find(excluded.begin(), excluded.end(), o) != excluded.end())
                        return -std::numeric_limits<double>::infinity();
                    n2 = normal(m_.triangles[o], c);
                }
                s = std::min(s, dihedral_q(n, n2));
            }
        }
        return s;
    }

    double before_score(const Change& ch) const {
        std::vector<Tri> tris;
        for (int t : ch.removed) tris.push_back(m_.triangles[t]);
        return score(tris, ch.removed, nullptr);
    }

    // Quality after the change, or -inf if it is not admissible.
    double after_score(const Change& ch) const {
        for (std::size_t i = 0; i < ch.added.size(); ++i) {
            if (ch.from[i] < 0 || ch.kind == 0) continue;
            const Tri& old = m_.triangles[ch.removed[ch.from[i]]];
            if (angle_q(old) < 1) continue;  // a bad triangle has no normal worth keeping
            const Vec3 nb = normal(old), na = normal(ch.added[i], &ch);
            if (!(nb.dot(na) >= kMaxNormalTurnCos * nb.norm() * na.norm())) return -std::numeric_limits<double>::infinity();
        }
        return score(ch.added, ch.removed, &ch);
    }

    void apply(const Change& ch) {
        for (int t : ch.removed) remove_triangle_index(t);
        for (const auto& [v, p] : ch.moved) {
            if (std::size_t(v) == m_.vertices.size()) {  // a split's new vertex
                m_.vertices.push_back(p);
                star_.emplace_back();
            }
            m_.vertices[v] = p;
        }
        for (const Tri& f : ch.added) {
            m_.triangles.push_back(f);
            alive_.push_back(1);
            add_triangle_index(int(m_.triangles.size()) - 1);
        }
    }

    std::vector<int> live_star(int v) const { return star_[v]; }  // star_ holds live triangles only

    std::vector<int> neighbours(int v) const {
        std::vector<int> out;
        for (int t : star_[v])
            for (int w : m_.triangles[t])
                if (w != v) out.push_back(w);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    Vec3 projected(const Vec3& p) const { return project_ ? project_(p) : p; }

    // Edge k of triangle t = (a, b, c), from a to b, with the neighbour o = (b, a, d) across it;
    // false on a border edge or a degenerate neighbour.
    struct EdgePair {
        int a, b, c, o, d;
    };
    bool edge_pair(int t, int k, EdgePair& e) const {
        const Tri& f = m_.triangles[t];
        e.a = f[k], e.b = f[(k + 1) % 3], e.c = f[(k + 2) % 3];
        e.o = across(e.b, e.a);
        if (e.o < 0) return false;
        e.d = -1;
        for (int v : m_.triangles[e.o])
            if (v != e.a && v != e.b) e.d = v;
        return e.d >= 0;
    }

    // Flip of edge a -> b of triangle t = (a, b, c) with the neighbour (b, a, d).
    bool flip_change(int t, int k, Change& ch) const {
        EdgePair e;
        if (!edge_pair(t, k, e) || e.d == e.c) return false;
        const Tri& f = m_.triangles[t];
        const int a = e.a, b = e.b, c = e.c, o = e.o, d = e.d;
        const double dih = dihedral_deg(normal(f), normal(m_.triangles[o]));
        if (!(dih >= kFlatFlipDeg || dih < b_.min_dihedral_deg)) return false;
        ch = Change{};
        ch.kind = 0;
        ch.removed = {t, o};
        ch.added = {Tri{c, a, d}, Tri{d, b, c}};
        ch.from = {0, 1};
        return true;
    }

    // Collapse of edge (u, v): v merges into u, which moves to p.
    bool collapse_change(int u, int v, const Vec3& p, Change& ch) const {
        std::vector<int> both;
        for (int t : star_[u])
            if (std::find(m_.triangles[t].begin(), m_.triangles[t].end(), v) != m_.triangles[t].end()) both.push_back(t);
        if (both.size() != 2) return false;
        std::vector<int> apexes;
        for (int t : both)
            for (int w : m_.triangles[t])
                if (w != u && w != v) apexes.push_back(w);
        std::sort(apexes.begin(), apexes.end());
        if (apexes[0] == apexes[1]) return false;
        const std::vector<int> nu = neighbours(u), nv = neighbours(v);
        std::vector<int> common;
        std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
        if (common != apexes) return false;  // link condition
        ch = Change{};
        ch.kind = 1;
        for (int t : star_[u]) ch.removed.push_back(t);
        for (int t : star_[v])
            if (std::find(ch.removed.begin(), ch.removed.end(), t) == ch.removed.end()) ch.removed.push_back(t);
        for (std::size_t i = 0; i < ch.removed.size(); ++i) {
            const int t = ch.removed[i];
            if (std::find(both.begin(), both.end(), t) != both.end()) continue;
            Tri f = m_.triangles[t];
            for (int& w : f)
                if (w == v) w = u;
            ch.added.push_back(f);
            ch.from.push_back(int(i));
        }
        ch.moved = {{u, p}};
        return true;
    }

    // Split of edge a -> b of triangle t = (a, b, c) and its neighbour (b, a, d) at p (a new vertex).
    bool split_change(int t, int k, const Vec3& p, Change& ch) const {
        EdgePair e;
        if (!edge_pair(t, k, e)) return false;
        const int a = e.a, b = e.b, c = e.c, o = e.o, d = e.d;
        const int m = int(m_.vertices.size());
        ch = Change{};
        ch.kind = 3;
        ch.removed = {t, o};
        ch.added = {Tri{a, m, c}, Tri{m, b, c}, Tri{b, m, d}, Tri{m, a, d}};
        ch.from = {-1, -1, -1, -1};
        ch.moved = {{m, p}};
        return true;
    }

    void move_change(int v, const Vec3& p, Change& ch) const {
        ch = Change{};
        ch.kind = 2;
        ch.removed = star_[v];
        ch.added.clear();
        for (std::size_t i = 0; i < ch.removed.size(); ++i) {
            ch.added.push_back(m_.triangles[ch.removed[i]]);
            ch.from.push_back(int(i));
        }
        ch.moved = {{v, p}};
    }

    bool fix(int t, QualityRepair& out) {
        // The triangle and, for a bad dihedral, its neighbour across that edge.
        std::vector<int> targets{t};
        {
            const Tri& f = m_.triangles[t];
            const Vec3 n = normal(f);
            for (int k = 0; k < 3; ++k) {
                const int o = across(f[(k + 1) % 3], f[k]);
                if (o >= 0 && dihedral_q(n, normal(m_.triangles[o])) < 1) targets.push_back(o);
            }
        }
        Change best, ch;
        double best_gain = 0;
        auto consider = [&](const Change& c) {
            const double before = before_score(c), after = after_score(c);
            if (after > before && after - before > best_gain) {
                best_gain = after - before;
                best = c;
            }
        };
        for (int s : targets) {
            const Tri f = m_.triangles[s];
            for (int k = 0; k < 3; ++k) {
                if (flip_change(s, k, ch)) consider(ch);
                const int u = f[k], v = f[(k + 1) % 3];
                const Vec3 pu = m_.vertices[u], pv = m_.vertices[v], mid = 0.5 * (pu + pv);
                if (project_ && split_change(s, k, projected(mid), ch)) consider(ch);
                for (const Vec3& p : {pu, pv, mid, projected(mid)})
                    if (collapse_change(u, v, p, ch)) consider(ch);
                const std::vector<int> nb = neighbours(u);
                Vec3 centre = Vec3::Zero();
                for (int w : nb) centre += m_.vertices[w];
                centre /= double(nb.size());
                for (const Vec3& p : {projected(centre), projected(0.5 * (centre + pu))}) {
                    move_change(u, p, ch);
                    consider(ch);
                }
            }
        }
        if (best_gain <= 0) return false;
        apply(best);
        (best.kind == 0 ? out.flips : best.kind == 1 ? out.collapses : best.kind == 2 ? out.moves : out.splits) += 1;
        return true;
    }

    // Drops dead triangles and unused vertices, keeping the order of both.
    void compact() {
        std::vector<int> map(m_.vertices.size(), -1);
        SurfaceMesh out;
        out.region_names = m_.region_names;
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            if (alive_[t])
                for (int v : m_.triangles[t]) map[v] = 0;
        for (std::size_t v = 0; v < m_.vertices.size(); ++v) {
            if (map[v] < 0) continue;
            map[v] = int(out.vertices.size());
            out.vertices.push_back(m_.vertices[v]);
        }
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            if (alive_[t]) out.triangles.push_back(Tri{map[m_.triangles[t][0]], map[m_.triangles[t][1]], map[m_.triangles[t][2]]});
        m_ = std::move(out);
    }
};

}  // namespace

QualityRepair improve_quality(SurfaceMesh& mesh, const QualityBounds& bounds, const SurfaceProjection& project, int max_passes) {
    if (!(bounds.min_angle_deg > 0 && bounds.min_angle_deg < 60))
        throw std::invalid_argument("minimum triangle angle must lie in (0, 60) degrees");
    if (!(bounds.min_dihedral_deg > 0 && bounds.min_dihedral_deg < 180))
        throw std::invalid_argument("minimum dihedral angle must lie in (0, 180) degrees");
    for (const Tri& t : mesh.triangles)
        for (int v : t)
            if (v < 0 || std::size_t(v) >= mesh.vertices.size())
                throw std::invalid_argument("quality repair: triangle with vertex index " + std::to_string(v) + " outside [0, " +
                                            std::to_string(mesh.vertices.size()) + ")");
    mesh.region.clear();  // the remesher assigns regions afterwards
    return QualityImprover(mesh, bounds, project).run(max_passes);
}

}  // namespace cf
