#include "nodes/simplify/degenerate_cleanup.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

namespace cf {

namespace {

// Flips and collapses must not turn a surviving triangle's normal by more than this (cos 60 deg):
// on the flat faces where slivers appear the change is zero; the bound keeps a collapse near a
// crease from folding the surface.
constexpr double kMinNormalCosine = 0.5;

class SliverRemover {
public:
    SliverRemover(SurfaceMesh& mesh, double ratio)
        : m_(mesh), ratio_(ratio), alive_(mesh.triangles.size(), 1), live_(mesh.triangles.size()), star_(mesh.vertices.size()) {
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            for (int v : m_.triangles[t]) star_[v].push_back(int(t));
    }

    DegenerateCleanup run() {
        DegenerateCleanup out;
        // Every admissible operation removes at least one sliver and creates none, so this ends.
        for (bool progress = true; progress;) {
            progress = false;
            for (std::size_t t = 0; t < m_.triangles.size(); ++t) {
                if (!alive_[t] || !sliver(m_.triangles[t])) continue;
                if (fix(int(t), out)) progress = true;
            }
        }
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            if (alive_[t] && sliver(m_.triangles[t])) ++out.left;
        compact();
        return out;
    }

private:
    SurfaceMesh& m_;
    double ratio_;
    std::vector<char> alive_;
    std::size_t live_;
    std::vector<std::vector<int>> star_;  // vertex -> triangles (dead ones filtered on use)

    static Vec3 normal_of(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

    // Same measure as check_topology: |(b-a) x (c-a)| <= ratio * (longest edge)^2.
    bool sliver(const Vec3& a, const Vec3& b, const Vec3& c) const {
        const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
        return normal_of(a, b, c).norm() <= ratio_ * longest;
    }
    bool sliver(const Tri& t) const { return sliver(m_.vertices[t[0]], m_.vertices[t[1]], m_.vertices[t[2]]); }

    static bool turns_too_far(const Vec3& before, const Vec3& after) {
        const double nb = before.norm(), na = after.norm();
        return !(before.dot(after) >= kMinNormalCosine * nb * na);
    }

    // The live triangle holding the directed edge a -> b, or -1.
    int across(int a, int b) const {
        for (int t : star_[a]) {
            if (!alive_[t]) continue;
            const Tri& f = m_.triangles[t];
            for (int k = 0; k < 3; ++k)
                if (f[k] == a && f[(k + 1) % 3] == b) return t;
        }
        return -1;
    }

    bool adjacent(int a, int b) const {
        for (int t : star_[a])
            if (alive_[t] && std::find(m_.triangles[t].begin(), m_.triangles[t].end(), b) != m_.triangles[t].end())
                return true;
        return false;
    }

    std::vector<int> neighbours(int v) const {
        std::vector<int> out;
        for (int t : star_[v])
            if (alive_[t])
                for (int w : m_.triangles[t])
                    if (w != v) out.push_back(w);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    bool fix(int t, DegenerateCleanup& out) {
        const Tri f = m_.triangles[t];
        std::array<double, 3> len{};  // len[k]: edge f[k] -> f[k+1]
        for (int k = 0; k < 3; ++k) len[k] = (m_.vertices[f[(k + 1) % 3]] - m_.vertices[f[k]]).squaredNorm();
        std::array<int, 3> order{0, 1, 2};
        std::sort(order.begin(), order.end(), [&](int i, int j) { return len[i] < len[j]; });
        const int longest = order[2];
        if (flip(t, f[longest], f[(longest + 1) % 3], f[(longest + 2) % 3])) {
            ++out.flips;
            return true;
        }
        for (int k : {order[0], order[1]}) {
            if (collapse(f[k], f[(k + 1) % 3])) {
                ++out.collapses;
                return true;
            }
        }
        return false;
    }

    // Cap (a, b, c) with longest edge a -> b: replace it and the neighbour (b, a, d) by
    // (c, a, d) and (d, b, c).
    bool flip(int t1, int a, int b, int c) {
        const int t2 = across(b, a);
        if (t2 < 0) return false;
        const Tri& g = m_.triangles[t2];
        int d = -1;
        for (int v : g)
            if (v != a && v != b) d = v;
        if (d < 0 || d == c || adjacent(c, d)) return false;
        const Vec3 &pa = m_.vertices[a], &pb = m_.vertices[b], &pc = m_.vertices[c], &pd = m_.vertices[d];
        if (sliver(pc, pa, pd) || sliver(pd, pb, pc)) return false;
        const Vec3 n2 = normal_of(m_.vertices[g[0]], m_.vertices[g[1]], m_.vertices[g[2]]);
        if (!sliver(g)) {
            if (turns_too_far(n2, normal_of(pc, pa, pd)) || turns_too_far(n2, normal_of(pd, pb, pc))) return false;
        } else if (normal_of(pc, pa, pd).dot(normal_of(pd, pb, pc)) <= 0) {
            return false;  // both old triangles flat: at least keep the new pair consistently oriented
        }
        m_.triangles[t1] = Tri{c, a, d};
        m_.triangles[t2] = Tri{d, b, c};
        erase_from_star(b, t1);
        star_[d].push_back(t1);
        erase_from_star(a, t2);
        star_[c].push_back(t2);
        return true;
    }

    // Merges v into u (u survives) at the end point or midpoint that turns the surrounding
    // normals least.
    bool collapse(int u, int v) {
        if (live_ <= 4) return false;  // a tetrahedron cannot lose an edge
        std::vector<int> both, changed;
        for (int t : star_[u])
            if (alive_[t]) (contains(t, v) ? both : changed).push_back(t);
        for (int t : star_[v])
            if (alive_[t] && !contains(t, u)) changed.push_back(t);
        if (both.size() != 2) return false;
        // Link condition: the common neighbours of u and v are exactly the two apexes.
        std::vector<int> apexes;
        for (int t : both)
            for (int w : m_.triangles[t])
                if (w != u && w != v) apexes.push_back(w);
        std::sort(apexes.begin(), apexes.end());
        if (apexes[0] == apexes[1]) return false;
        const std::vector<int> nu = neighbours(u), nv = neighbours(v);
        std::vector<int> common;
        std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
        if (common != apexes) return false;

        const Vec3 pu = m_.vertices[u], pv = m_.vertices[v];
        double best_worst = -std::numeric_limits<double>::infinity();
        Vec3 best = pu;
        for (const Vec3& p : {pu, pv, Vec3(0.5 * (pu + pv))}) {
            double worst = std::numeric_limits<double>::infinity();
            for (int t : changed) {
                std::array<Vec3, 3> before, after;
                for (int k = 0; k < 3; ++k) {
                    const int w = m_.triangles[t][k];
                    before[k] = m_.vertices[w];
                    after[k] = (w == u || w == v) ? p : before[k];
                }
                if (sliver(after[0], after[1], after[2])) {
                    worst = -std::numeric_limits<double>::infinity();
                    break;
                }
                if (sliver(before[0], before[1], before[2])) continue;  // no normal to keep
                const Vec3 nb = normal_of(before[0], before[1], before[2]).normalized();
                const Vec3 na = normal_of(after[0], after[1], after[2]).normalized();
                worst = std::min(worst, nb.dot(na));
            }
            if (worst > best_worst) {
                best_worst = worst;
                best = p;
            }
        }
        if (!(best_worst >= kMinNormalCosine)) return false;

        m_.vertices[u] = best;
        for (int t : both) alive_[t] = 0;
        live_ -= 2;
        for (int t : star_[v]) {
            if (!alive_[t]) continue;
            for (int& w : m_.triangles[t])
                if (w == v) w = u;
            star_[u].push_back(t);
        }
        star_[v].clear();
        return true;
    }

    bool contains(int t, int v) const {
        const Tri& f = m_.triangles[t];
        return f[0] == v || f[1] == v || f[2] == v;
    }

    void erase_from_star(int v, int t) { star_[v].erase(std::remove(star_[v].begin(), star_[v].end(), t), star_[v].end()); }

    // Drops dead triangles (and their region ids) and unused vertices, keeping the order of both.
    void compact() {
        const bool has_regions = m_.region.size() == m_.triangles.size();
        std::vector<int> map(m_.vertices.size(), -1);
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            if (alive_[t])
                for (int v : m_.triangles[t]) map[v] = 0;
        SurfaceMesh out;
        out.region_names = m_.region_names;
        for (std::size_t v = 0; v < m_.vertices.size(); ++v) {
            if (map[v] < 0) continue;
            map[v] = int(out.vertices.size());
            out.vertices.push_back(m_.vertices[v]);
        }
        for (std::size_t t = 0; t < m_.triangles.size(); ++t) {
            if (!alive_[t]) continue;
            const Tri& f = m_.triangles[t];
            out.triangles.push_back(Tri{map[f[0]], map[f[1]], map[f[2]]});
            if (has_regions) out.region.push_back(m_.region[t]);
        }
        m_ = std::move(out);
    }
};

}  // namespace

DegenerateCleanup remove_degenerate_triangles(SurfaceMesh& mesh, double ratio) {
    if (!(ratio >= 0)) throw std::invalid_argument("sliver ratio must be non-negative");
    for (const Tri& t : mesh.triangles)
        for (int v : t)
            if (v < 0 || std::size_t(v) >= mesh.vertices.size())
                throw std::invalid_argument("sliver removal: triangle with vertex index " + std::to_string(v) +
                                            " outside [0, " + std::to_string(mesh.vertices.size()) + ")");
    return SliverRemover(mesh, ratio).run();
}

}  // namespace cf
