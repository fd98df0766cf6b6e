#include "nodes/propagate/fragment_cracks.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/bem/element_geometry.hpp"
#include "nodes/bem/nearly_touching.hpp"
#include "nodes/domain/mesh_topology.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace cf::propagate {

namespace {

using Edge = std::pair<int, int>;
Edge undirected(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Generalised winding number of the closed surface at p (Van Oosterom and Strackee solid angles).
double winding_number(const std::vector<bem::ElementGeometry>& surface, const Vec3& p) {
    double w = 0;
    for (const bem::ElementGeometry& t : surface) {
        const Vec3 a = t.p[0] - p, b = t.p[1] - p, c = t.p[2] - p;
        const double la = a.norm(), lb = b.norm(), lc = c.norm();
        const double num = a.dot(b.cross(c));
        const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        w += 2 * std::atan2(num, den);
    }
    return w / (4 * M_PI);
}

// Whether the crack triangle lies inside the surface and at least `clearance` from every
// surface triangle. Triangles whose bounding spheres are further apart are skipped.
bool clear_inside(const bem::ElementGeometry& crack, const std::vector<bem::ElementGeometry>& surface, double clearance) {
    for (const bem::ElementGeometry& s : surface) {
        if ((crack.centroid - s.centroid).norm() - crack.diameter - s.diameter > clearance) continue;
        if (bem::triangle_distance(crack, s) < clearance) return false;  // brute force: BEM meshes are coarse
    }
    return winding_number(surface, crack.centroid) > 0.5;
}

// ---- Inside the fragment. The fragment's level set is the broken object (eq. 6.1) restricted to
// the fragment, so every crack of the parent run is cut into it: on an incomplete crack's own
// sheet it is about +sqrt(3) r_f / 2 (a slit), not negative. A sheet point p therefore counts as
// `depth` inside when on each side of the sheet, a few voxels off (past the slit's half-thickness
// sqrt(3)/2 r_f, and past up to ~2 r_f between the coarse sheet and the fine recorded surface),
// the fragment is at least `depth` deep. A crack that separated the fragment from another has
// material of this fragment on one side only and fails, as it must: it is now ordinary surface.
constexpr double kSideOffsets[] = {2, 3, 4};  // [r_f]

bool inside_on_both_sides(const LevelSet& fragment, const Vec3& p, const Vec3& n, double depth, double r_f) {
    for (const double side : {1.0, -1.0}) {
        bool found = false;
        for (const double h : kSideOffsets)
            if (sample(fragment, p + side * h * r_f * n) <= -depth) {
                found = true;
                break;
            }
        if (!found) return false;
    }
    return true;
}

struct Admission {
    bool strict = false;  // the mask: r_f deep in the fragment and clear of the surface
    bool ring = false;    // inside the fragment at all and clear of the surface (1-ring additions)
};

std::vector<Admission> admit_triangles(const SurfaceMesh& cracks, const LevelSet& fragment,
                                       const std::vector<bem::ElementGeometry>& surface, double r_f, double clearance) {
    std::vector<Admission> out(cracks.num_triangles());
    tbb::parallel_for(std::size_t(0), cracks.num_triangles(), [&](std::size_t t) {
        const bem::ElementGeometry g = bem::element_geometry(cracks, t);
        bool deep = true, inside = true;
        for (const Vec3& p : {g.p[0], g.p[1], g.p[2], g.centroid}) {
            deep = deep && inside_on_both_sides(fragment, p, g.normal, r_f, r_f);
            inside = inside && inside_on_both_sides(fragment, p, g.normal, 0, r_f);
        }
        if (!inside || !clear_inside(g, surface, clearance)) return;
        out[t].ring = true;
        out[t].strict = deep;
    });
    return out;
}

// ---- The kept sheet as a manifold with boundary (ch. 7.3). Edge multiplicities and per-vertex
// counts of boundary edges are kept up to date as triangles come and go.
class KeptSheet {
public:
    explicit KeptSheet(const SurfaceMesh& m)
        : m_(m), kept_(m.num_triangles(), 0), banned_(m.num_triangles(), 0), boundary_(m.num_vertices(), 0),
          tried_(m.num_vertices(), 0), ring_of_(m.num_vertices()) {
        for (std::size_t t = 0; t < m.num_triangles(); ++t)
            for (int v : m.triangles[t]) ring_of_[v].push_back(static_cast<int>(t));
    }

    void add(std::size_t t) {
        kept_[t] = 1;
        for (int k = 0; k < 3; ++k) bump(m_.triangles[t][k], m_.triangles[t][(k + 1) % 3], +1);
    }
    // Removed for good: a triangle dropped once is never added back (so the closure terminates).
    void ban(std::size_t t) {
        if (kept_[t])
            for (int k = 0; k < 3; ++k) bump(m_.triangles[t][k], m_.triangles[t][(k + 1) % 3], -1);
        kept_[t] = 0;
        banned_[t] = 1;
    }

    // Pinched front nodes (more than two boundary edges) first get the admissible triangles of
    // their 1-ring; a node still pinched after that loses all its triangles. Then the triangles
    // whose three nodes are front nodes go; repeated until nothing changes.
    void close(const std::vector<Admission>& admitted) {
        for (;;) {
            while (!pinched_.empty()) {
                const int v = *pinched_.begin();
                bool added = false;
                if (!tried_[v]) {
                    tried_[v] = 1;
                    for (int t : ring_of_[v])
                        if (!kept_[t] && !banned_[t] && admitted[t].ring) {
                            add(t);
                            added = true;
                        }
                }
                if (!added)
                    for (int t : ring_of_[v])
                        if (kept_[t]) ban(t);
            }
            std::vector<std::size_t> dead;
            for (std::size_t t = 0; t < kept_.size(); ++t) {
                const Tri& tri = m_.triangles[t];
                if (kept_[t] && boundary_[tri[0]] > 0 && boundary_[tri[1]] > 0 && boundary_[tri[2]] > 0) dead.push_back(t);
            }
            if (dead.empty()) return;
            for (std::size_t t : dead) ban(t);
        }
    }

    const std::vector<char>& kept() const { return kept_; }

private:
    void bump(int a, int b, int d) {
        int& c = count_[undirected(a, b)];
        const int before = c;
        c += d;
        if (c > 2)
            throw std::invalid_argument("parent crack sheets: edge " + std::to_string(a) + "-" + std::to_string(b) +
                                        " belongs to more than two triangles (non-manifold crack mesh)");
        const int delta = (c == 1) - (before == 1);
        if (delta == 0) return;
        for (int v : {a, b}) {
            boundary_[v] += delta;
            if (boundary_[v] > 2) pinched_.insert(v);
            else pinched_.erase(v);
        }
    }

    const SurfaceMesh& m_;
    std::vector<char> kept_, banned_;
    std::vector<int> boundary_;
    std::vector<char> tried_;
    std::vector<std::vector<int>> ring_of_;
    std::map<Edge, int> count_;
    std::set<int> pinched_;
};

// ---- Checks of the parent state, so a mismatch is reported instead of read out of bounds.
void check_parent(const FractureState& p) {
    const SurfaceMesh& c = p.cracks;
    if (!c.region.empty() && c.region.size() != c.num_triangles())
        throw std::invalid_argument("parent fracture state: " + std::to_string(c.region.size()) + " region ids for " +
                                    std::to_string(c.num_triangles()) + " crack triangles");
    for (std::size_t t = 0; t < c.num_triangles(); ++t) {
        for (int v : c.triangles[t])
            if (v < 0 || static_cast<std::size_t>(v) >= c.num_vertices())
                throw std::invalid_argument("parent fracture state: crack triangle " + std::to_string(t) +
                                            " names vertex " + std::to_string(v) + " of " + std::to_string(c.num_vertices()));
        if (c.region_of(t) < 0 || c.region_of(t) >= p.num_cracks())
            throw std::invalid_argument("parent fracture state: crack triangle " + std::to_string(t) + " is in crack " +
                                        std::to_string(c.region_of(t)) + " but the state has " +
                                        std::to_string(p.num_cracks()) + " crack grids");
    }
    for (std::size_t f = 0; f < p.fronts.size(); ++f) {
        const FrontState& fs = p.fronts[f];
        for (int v : fs.front.nodes)
            if (v < 0 || static_cast<std::size_t>(v) >= c.num_vertices())
                throw std::invalid_argument("parent fracture state: front " + std::to_string(f) + " names vertex " +
                                            std::to_string(v) + " of " + std::to_string(c.num_vertices()));
        const std::size_t edges = fs.front.num_edges(), n = static_cast<std::size_t>(std::max(fs.markers.per_edge, 1));
        const std::size_t expected = fs.front.closed ? edges * n : edges * n + 1;
        if (!fs.fresh && fs.markers.markers.size() != expected)
            throw std::invalid_argument("parent fracture state: front " + std::to_string(f) + " has " +
                                        std::to_string(fs.markers.markers.size()) + " markers for " + std::to_string(edges) +
                                        " edges of " + std::to_string(n) + " (expected " + std::to_string(expected) + ")");
    }
}

// A stopped or fresh marker on the straight front edge a -> b: the frame of the sheet there
// (n1 the triangle normal, n2 = n3 x n1 forward, ch. 4.5.2), no SIF history.
MarkerState edge_marker(const Vec3& a, const Vec3& b, const Vec3& normal, double s, bool active) {
    MarkerState m;
    m.position = a + s * (b - a);
    const FrontFrame f = orthonormalised(normal, b - a);
    m.n1 = f.n1;
    m.n2 = f.n2;
    m.active = active;
    return m;
}

// ---- restrict_to_fragment's steps, in the order it calls them.

// The fragment inputs checked against the parent; returns the clearance from the surface [m].
double checked_clearance(const FractureState& parent, const LevelSet& fragment, const SurfaceMesh& surface,
                         const FragmentCrackSettings& settings) {
    const double r_f = parent.r_f;
    if (fragment.empty())
        throw std::invalid_argument("fragment level set is empty: pass the fragment's grid from segment.fragments");
    if (!(std::abs(fragment.voxel_size - r_f) <= 1e-9 * r_f))
        throw std::invalid_argument("fragment level set has voxel size " + graph::format_number(fragment.voxel_size) +
                                    " m but the parent's cracks were recorded at r_f = " + graph::format_number(r_f) +
                                    " m: segment the parent's broken object, do not resample it");
    const MeshTopologyReport topo = check_topology(surface);
    if (!topo.is_closed_manifold() || !(signed_volume(surface) > 0))
        throw std::invalid_argument("fragment surface must be a closed, outward-oriented BEM mesh: " + topo.describe() +
                                    (signed_volume(surface) > 0 ? "" : ", enclosed volume not positive (inward?)"));
    const double clearance = fragment_crack_clearance(parent.r_c, r_f, settings);
    if (!(clearance >= 0) || !std::isfinite(clearance))
        throw std::invalid_argument("fragment crack clearance must be a finite distance >= 0 m, got " +
                                    graph::format_number(clearance));
    return clearance;
}

// 1. The mask (strictly admitted triangles), then its manifold closure: per parent triangle, kept or not.
std::vector<char> kept_triangles(const SurfaceMesh& pc, const std::vector<Admission>& admitted) {
    KeptSheet sheet(pc);
    for (std::size_t t = 0; t < pc.num_triangles(); ++t)
        if (admitted[t].strict) sheet.add(t);
    sheet.close(admitted);
    return sheet.kept();
}

// Parent vertex -> fragment vertex (-1: dropped), and back.
struct Renumbering {
    std::vector<int> new_vertex, old_vertex;
};

// 2. The kept triangles copied into `out`, vertices and cracks in the parent's order (with the
// crack grids of the cracks that keep a triangle), and the counts of kept and dropped triangles.
Renumbering copy_kept_triangles(const FractureState& parent, const std::vector<char>& kept,
                                const std::vector<Admission>& admitted, FragmentCracks& out) {
    const SurfaceMesh& pc = parent.cracks;
    Renumbering ren;
    std::vector<int>& new_vertex = ren.new_vertex;
    new_vertex.assign(pc.num_vertices(), -1);
    std::vector<int> new_region(parent.num_cracks(), -1);
    for (std::size_t t = 0; t < pc.num_triangles(); ++t) {
        if (!kept[t]) continue;
        for (int v : pc.triangles[t]) new_vertex[v] = 0;
        new_region[pc.region_of(t)] = 0;
    }
    SurfaceMesh& cracks = out.state.cracks;
    for (std::size_t v = 0; v < pc.num_vertices(); ++v)
        if (new_vertex[v] == 0) {
            new_vertex[v] = static_cast<int>(ren.old_vertex.size());
            ren.old_vertex.push_back(static_cast<int>(v));
            cracks.vertices.push_back(pc.vertices[v]);
        }
    for (int r = 0; r < parent.num_cracks(); ++r)
        if (new_region[r] == 0) {
            new_region[r] = static_cast<int>(out.state.grids.cracks.size());
            out.state.grids.cracks.push_back(parent.grids.cracks[r]);
            cracks.region_names.push_back(pc.region_name(r));
        }
    for (std::size_t t = 0; t < pc.num_triangles(); ++t) {
        if (!kept[t]) {
            ++out.dropped_triangles;
            continue;
        }
        const Tri& o = pc.triangles[t];
        cracks.triangles.push_back({new_vertex[o[0]], new_vertex[o[1]], new_vertex[o[2]]});
        cracks.region.push_back(new_region[pc.region_of(t)]);
        ++out.kept_triangles;
        if (!admitted[t].strict) ++out.ring_triangles;
    }
    return ren;
}

// 3. Fronts: the boundary loops of the kept sheet. Where a loop is an old front edge for edge,
// the old front (markers, SIFs, freshness) carries over; otherwise old edges keep their markers
// and edges where the fragment cut the crack get stopped markers (they meet its surface).
class FrontCarrier {
public:
    FrontCarrier(const FractureState& parent, const SurfaceMesh& cracks, const Renumbering& ren)
        : parent_(parent), cracks_(cracks), ren_(ren), n_(markers_per_edge(parent.r_c, parent.r_f)) {
        for (std::size_t f = 0; f < parent.fronts.size(); ++f) {
            const CrackFront& fr = parent.fronts[f].front;
            for (std::size_t i = 0; i < fr.num_edges(); ++i)
                old_edge_[{fr.nodes[i], fr.nodes[(i + 1) % fr.nodes.size()]}] = {static_cast<int>(f), static_cast<int>(i)};
        }
        for (std::size_t t = 0; t < cracks.num_triangles(); ++t)
            for (int k = 0; k < 3; ++k)
                edge_triangle_[{cracks.triangles[t][k], cracks.triangles[t][(k + 1) % 3]}] = static_cast<int>(t);
    }

    // The fronts of all loops, ordered by (crack, first old front they touch).
    std::vector<FrontState> fronts() const {
        std::vector<std::pair<std::pair<int, int>, FrontState>> fronts;  // ((region, first old front), state)
        for (CrackFront& loop : extract_fronts(cracks_)) {
            int first_old = 0;
            FrontState fs = carry(std::move(loop), first_old);
            fronts.push_back({{fs.front.region, first_old}, std::move(fs)});
        }
        std::stable_sort(fronts.begin(), fronts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        std::vector<FrontState> out;
        for (auto& [key, fs] : fronts) out.push_back(std::move(fs));
        return out;
    }

private:
    // One loop's front state; `first_old` the smallest old front it shares an edge with (else
    // the number of old fronts).
    FrontState carry(CrackFront loop, int& first_old) const {
        const std::size_t N = loop.nodes.size();
        std::vector<std::pair<int, int>> hit(N, {-1, -1});  // per edge: (old front, edge index) or -1
        first_old = static_cast<int>(parent_.fronts.size());
        bool same = true;
        for (std::size_t i = 0; i < N; ++i) {
            const auto it = old_edge_.find({ren_.old_vertex[loop.nodes[i]], ren_.old_vertex[loop.nodes[(i + 1) % N]]});
            if (it != old_edge_.end()) {
                hit[i] = it->second;
                first_old = std::min(first_old, it->second.first);
            }
            same = same && hit[i].first >= 0 && hit[i].first == hit[0].first;
        }
        same = same && parent_.fronts[hit[0].first].front.closed && parent_.fronts[hit[0].first].front.num_edges() == N;
        FrontState fs;
        if (same) {
            fs = parent_.fronts[hit[0].first];  // unchanged: the whole front state, in its own node order
            for (int& v : fs.front.nodes) v = ren_.new_vertex[v];
            fs.front.region = loop.region;
            return fs;
        }
        fs.front = std::move(loop);
        fs.fresh = false;
        fs.markers.closed = true;
        fs.markers.per_edge = n_;
        for (std::size_t i = 0; i < N; ++i) add_edge_markers(fs, i, hit[i]);
        return fs;
    }

    // The markers of edge i of a changed front: an old edge's own markers, markers on the coarse
    // edge for an edge of a fresh parent front (active, as place_markers puts them), stopped ones
    // on a new edge.
    void add_edge_markers(FrontState& fs, std::size_t i, std::pair<int, int> hit) const {
        const std::size_t N = fs.front.nodes.size();
        const int a = fs.front.nodes[i], b = fs.front.nodes[(i + 1) % N];
        const auto [f, e] = hit;
        const FrontState* old = f >= 0 ? &parent_.fronts[f] : nullptr;
        if (old && !old->fresh) {
            if (old->markers.per_edge != n_)
                throw std::invalid_argument("parent fracture state: front " + std::to_string(f) + " has " +
                                            std::to_string(old->markers.per_edge) + " markers per edge, but r_c / r_f gives " +
                                            std::to_string(n_));
            const auto& m = old->markers.markers;
            fs.markers.markers.insert(fs.markers.markers.end(), m.begin() + std::ptrdiff_t(e) * n_,
                                      m.begin() + std::ptrdiff_t(e + 1) * n_);
            return;
        }
        const Vec3 normal = triangle_normal(cracks_, std::size_t(edge_triangle_.at({a, b})));
        for (int k = 0; k < n_; ++k)
            fs.markers.markers.push_back(edge_marker(cracks_.vertices[a], cracks_.vertices[b], normal,
                                                     static_cast<double>(k) / n_, old != nullptr));
    }

    const FractureState& parent_;
    const SurfaceMesh& cracks_;
    const Renumbering& ren_;
    const int n_;
    std::map<Edge, std::pair<int, int>> old_edge_;  // directed parent edge -> (front, edge index)
    std::map<Edge, int> edge_triangle_;             // directed new edge -> new triangle
};

}  // namespace

double fragment_crack_clearance(double r_c, double r_f, const FragmentCrackSettings& settings) {
    return settings.clearance >= 0 ? settings.clearance : std::max(r_f, 0.05 * r_c);
}

FragmentCracks restrict_to_fragment(const FractureState& parent, const LevelSet& fragment, const SurfaceMesh& surface,
                                    const FragmentCrackSettings& settings) {
    FragmentCracks out;
    out.state = start_fracture_state(parent.r_c, parent.r_f, parent.grids.half_width, surface.num_triangles());
    check_parent(parent);
    if (parent.cracks.num_triangles() == 0) return out;
    const double clearance = checked_clearance(parent, fragment, surface, settings);

    // 1. The mask, then the manifold closure.
    const std::vector<bem::ElementGeometry> surf = bem::element_geometries(surface, "fragment surface");
    const std::vector<Admission> admitted = admit_triangles(parent.cracks, fragment, surf, parent.r_f, clearance);
    const std::vector<char> kept = kept_triangles(parent.cracks, admitted);

    // 2. The kept triangles, renumbered.
    const Renumbering ren = copy_kept_triangles(parent, kept, admitted, out);
    if (out.state.cracks.num_triangles() == 0) return out;  // no incomplete crack: start_fracture_state's empty state
    out.state.grids.voxel_size = parent.grids.voxel_size;

    // 3. Fronts carried over or made from the kept sheet's boundary; no openings known yet.
    for (FrontState& fs : FrontCarrier(parent, out.state.cracks, ren).fronts()) out.state.fronts.push_back(std::move(fs));
    out.state.openings.opening.assign(out.state.cracks.num_vertices(), Vec3::Zero());
    out.state.openings.known.assign(out.state.cracks.num_vertices(), 0);
    return out;
}

}  // namespace cf::propagate
