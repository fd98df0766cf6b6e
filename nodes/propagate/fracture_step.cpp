#include "nodes/propagate/fracture_step.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/propagate/opening_estimate.hpp"

#include <tbb/parallel_for.h>

#include <chrono>
#include <map>
#include <set>
#include <stdexcept>

namespace cf::propagate {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::pair<int, int> edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

bool has_all_edges(const CrackFront& f, const std::set<std::pair<int, int>>& edges) {
    const std::size_t n = f.nodes.size();
    for (std::size_t i = 0; i < f.num_edges(); ++i)
        if (!edges.count(edge_key(f.nodes[i], f.nodes[(i + 1) % n]))) return false;
    return f.num_edges() > 0;
}

bool any_active(const FrontMarkers& m) {
    for (const MarkerState& s : m.markers)
        if (s.active) return true;
    return false;
}

// Slides markers back to equal spacing along their polyline (ch. 4.5.2), edge by edge: the
// markers at coarse front nodes (index i n) and deactivated markers are anchors, and the active
// markers between two anchors are spaced evenly on the polyline between them. A front that
// stopped at the object's surface stays attached there while the rest moves on, and no marker
// slides away from the coarse edge it belongs to (front growth relies on that).
void respace(FrontMarkers& fm) {
    const std::size_t M = fm.markers.size();
    std::vector<std::size_t> anchors;
    for (std::size_t i = 0; i < M; ++i)
        if (!fm.markers[i].active || i % fm.per_edge == 0) anchors.push_back(i);
    if (!fm.closed) {  // the ends of an open front are anchors too
        if (anchors.empty() || anchors.front() != 0) anchors.insert(anchors.begin(), 0);
        if (anchors.back() != M - 1) anchors.push_back(M - 1);
    }
    if (anchors.empty()) {
        const std::vector<Vec3> even = resample_polyline(fm.positions(), true, M, 0);
        for (std::size_t i = 0; i < M; ++i) fm.markers[i].position = even[i];
        return;
    }
    const std::size_t runs = fm.closed ? anchors.size() : anchors.size() - 1;
    for (std::size_t r = 0; r < runs; ++r) {
        const std::size_t a = anchors[r];
        std::size_t b = r + 1 < anchors.size() ? anchors[r + 1] : anchors[0] + M;  // wraps on closed fronts
        if (b - a < 2) continue;
        std::vector<Vec3> run;
        for (std::size_t k = a; k <= b; ++k) run.push_back(fm.markers[k % M].position);
        const std::vector<Vec3> even = resample_polyline(run, false, run.size());
        for (std::size_t k = a + 1; k < b; ++k) fm.markers[k % M].position = even[k - a];
    }
}

// The frames interpolated from the coarse front (ch. 4.5.2) are re-orthonormalised against the
// fine front: n3 follows the marker polyline (central difference), n1 stays the interpolated
// crack normal, n2 = n3 x n1. Where some markers stopped at a surface while their neighbours moved
// on, the fine front no longer runs parallel to the coarse edge it came from, and the coarse
// frame would push markers along the front instead of across it.
void align_frames_to_polyline(FrontMarkers& fm) {
    const std::size_t M = fm.markers.size();
    if (M < 2) return;
    std::vector<Vec3> tangent(M);
    for (std::size_t i = 0; i < M; ++i) {
        const std::size_t prev = i > 0 ? i - 1 : (fm.closed ? M - 1 : 0);
        const std::size_t next = i + 1 < M ? i + 1 : (fm.closed ? 0 : M - 1);
        tangent[i] = fm.markers[next].position - fm.markers[prev].position;
    }
    for (std::size_t i = 0; i < M; ++i) {
        MarkerState& m = fm.markers[i];
        const Vec3 n3_old = m.n1.cross(m.n2);
        Vec3 t = tangent[i] - tangent[i].dot(m.n1) * m.n1;
        if (!(t.norm() > 1e-12 * (1 + tangent[i].norm()))) continue;
        if (t.dot(n3_old) < 0) t = -t;
        const Vec3 n3 = t.normalized();
        m.n2 = n3.cross(m.n1).normalized();
    }
}

}  // namespace

std::vector<EdgeSifs> to_edge_sifs(const std::vector<bem::FrontEdgeSif>& sifs) {
    std::vector<EdgeSifs> out;
    out.reserve(sifs.size());
    for (const bem::FrontEdgeSif& s : sifs) {
        EdgeSifs e;
        e.v0 = s.v0;
        e.v1 = s.v1;
        e.frame.n1 = s.e2;
        e.frame.n2 = s.e1;
        e.frame.n3 = -s.e3;
        e.K = {s.KI, s.KII, -s.KIII};
        out.push_back(e);
    }
    return out;
}

StepReport propagate_step(FractureState& state, const std::vector<bem::FrontEdgeSif>& sifs, const ScalarField& toughness,
                          const LevelSet* object, const StepSettings& settings, const SubstepObserver& observer) {
    if (!toughness.source) throw std::invalid_argument("propagate_step: no toughness field");
    const double r_c = state.r_c, r_f = state.r_f;
    if (!(r_f > 0) || !(r_c > r_f))
        throw std::invalid_argument("propagate_step: the state needs 0 < r_f < r_c (got r_f = " + graph::format_number(r_f) +
                                    " m, r_c = " + graph::format_number(r_c) + " m)");
    PropagationSettings law = settings.law;
    law.r_c = r_c;
    law.r_f = r_f;
    const int per_edge = markers_per_edge(r_c, r_f);
    const int n = settings.substeps > 0 ? settings.substeps : per_edge;
    for (const Vec3& v : state.cracks.vertices)
        if (!v.allFinite()) throw std::invalid_argument("propagate_step: crack mesh has a non-finite vertex");

    StepReport rep;
    rep.substeps = n;
    const std::vector<EdgeSifs> edges = to_edge_sifs(sifs);
    std::set<std::pair<int, int>> have;
    for (const EdgeSifs& e : edges) {
        if (e.v0 < 0 || e.v1 < 0 || std::size_t(std::max(e.v0, e.v1)) >= state.cracks.num_vertices())
            throw std::invalid_argument("SIF record for edge " + std::to_string(e.v0) + " -> " + std::to_string(e.v1) +
                                        " names a vertex the crack mesh does not have: SIFs and state come from different runs");
        have.insert(edge_key(e.v0, e.v1));
    }

    // Fronts that move this step; their SIFs go to nodes and markers.
    auto t0 = Clock::now();
    std::vector<std::size_t> moving;
    std::vector<char> planar_first(state.fronts.size(), 0);
    for (std::size_t f = 0; f < state.fronts.size(); ++f) {
        FrontState& fs = state.fronts[f];
        if (!fs.fresh && !any_active(fs.markers)) {
            ++rep.fronts_stopped;
            continue;
        }
        if (!has_all_edges(fs.front, have)) {
            ++rep.fronts_waiting;
            continue;
        }
        assign_node_sifs(fs.front, edges);
        if (fs.fresh) {
            fs.markers = place_markers(fs.front, state.cracks, per_edge);
            planar_first[f] = 1;
            fs.fresh = false;
        } else {
            interpolate_front_state(fs.markers, fs.front, true);
        }
        moving.push_back(f);
    }
    rep.fronts_propagated = static_cast<int>(moving.size());

    // Rounds of recording: one front per crack per round (a crack grid records one motion at a time).
    std::vector<std::vector<std::size_t>> rounds;
    {
        std::map<int, int> seen;
        for (std::size_t f : moving) {
            const int r = seen[state.fronts[f].front.region]++;
            if (r >= static_cast<int>(rounds.size())) rounds.resize(r + 1);
            rounds[r].push_back(f);
        }
    }
    for (std::size_t f : moving)
        if (state.fronts[f].front.region < 0 || state.fronts[f].front.region >= state.num_cracks())
            throw std::invalid_argument("front of crack " + std::to_string(state.fronts[f].front.region) +
                                        " has no crack grid (the state has " + std::to_string(state.num_cracks()) + ")");
    rep.propagate_seconds += seconds_since(t0);

    CrackRecorder recorder(state.grids);
    std::map<std::size_t, std::vector<double>> travelled;
    for (std::size_t f : moving) travelled[f].assign(state.fronts[f].markers.markers.size(), 0.0);

    for (int k = 0; k < n; ++k) {
        t0 = Clock::now();
        const double w_t = blend_weight(k, n);
        // Forward Euler for every marker of every moving front (eq. 4.11); independent per marker.
        std::map<std::size_t, std::vector<Vec3>> p0, p1;
        std::map<std::size_t, std::vector<double>> theta;  // angle each marker moved at
        for (std::size_t f : moving) {
            FrontMarkers& fm = state.fronts[f].markers;
            const bool planar = planar_first[f] && k == 0;
            align_frames_to_polyline(fm);
            std::vector<Vec3>& a = p0[f];
            std::vector<Vec3>& b = p1[f];
            a = fm.positions();
            b = a;
            std::vector<double>& th = theta[f];
            th.assign(fm.markers.size(), 0.0);
            tbb::parallel_for(std::size_t(0), fm.markers.size(), [&](std::size_t i) {
                const MarkerStep st = marker_substep(fm.markers[i], toughness, law, w_t, planar);
                b[i] = a[i] + st.displacement;
                th[i] = st.theta;
            });
        }
        rep.propagate_seconds += seconds_since(t0);
        // Geometry tests against the grids so far, then recording of the swept strips (ch. 6.2).
        t0 = Clock::now();
        for (const std::vector<std::size_t>& round : rounds) {
            std::vector<FrontMotion> motions(state.num_cracks());
            for (std::size_t f : round) {
                FrontMotion& m = motions[state.fronts[f].front.region];
                m.p0 = p0[f];
                m.p1 = p1[f];
                m.closed = state.fronts[f].markers.closed;
            }
            std::size_t written = 0;
            const auto tests = recorder.record_substep(motions, object, &written);
            rep.voxels_written += written;
            for (std::size_t f : round) {
                FrontMarkers& fm = state.fronts[f].markers;
                const std::vector<MarkerTest>& t = tests[state.fronts[f].front.region];
                for (std::size_t i = 0; i < fm.markers.size(); ++i) {
                    MarkerState& m = fm.markers[i];
                    if (!m.active) continue;
                    if (t[i].hit == MarkerHit::none) {
                        const Vec3 d = p1[f][i] - m.position;
                        travelled[f][i] += d.norm();
                        m.position = p1[f][i];
                        if (d.squaredNorm() > 0) {  // remembered for eq. (4.12) in the next BEM step
                            m.last_direction = d.normalized();
                            m.last_theta = theta[f][i];
                        }
                        continue;
                    }
                    // Deactivated (fig. 27): the strip up to p1 is recorded so the crack meets the
                    // other surface; the marker stays at p0, inside, so the coarse front does too.
                    m.active = false;
                    if (t[i].hit == MarkerHit::left_object) ++rep.hits_left_object;
                    else if (t[i].hit == MarkerHit::crossed_crack) ++rep.hits_crossed_crack;
                    else ++rep.hits_self_intersection;
                }
            }
        }
        rep.record_seconds += seconds_since(t0);
        t0 = Clock::now();
        for (std::size_t f : moving) respace(state.fronts[f].markers);
        rep.propagate_seconds += seconds_since(t0);
        if (observer) observer(k, recorder);
    }

    // New BEM elements (fig. 16), away from the object's surface and from other cracks.
    t0 = Clock::now();
    state.grids = recorder.release();  // recording is done; growth only samples the grids
    const std::vector<LevelSet>& grids_now = state.grids.cracks;
    for (std::size_t f : moving) {
        FrontState& fs = state.fronts[f];
        const int own = fs.front.region;
        GrowthSettings gs;
        gs.r_c = r_c;
        gs.admissible = [&](const Vec3& p) {
            if (object && sample(*object, p) > -settings.surface_margin) return false;
            for (std::size_t c = 0; c < grids_now.size(); ++c)
                if (static_cast<int>(c) != own && sample(grids_now[c], p) < settings.crack_margin) return false;
            return true;
        };
        if (object) gs.inside = [&](const Vec3& p) { return sample(*object, p) < 0; };
        const FrontGrowth g = grow_front(state.cracks, fs.front, fs.markers, gs);
        rep.openings_estimated += estimate_openings_left_behind(state.cracks, fs.front, g.front, law.E, law.nu, state.openings);
        fs.front = g.front;
        fs.markers = g.markers;
        rep.elements_added += g.added_triangles;
        rep.vertices_added += g.added_vertices;
        rep.edges_kept += g.kept;
        rep.edges_split += g.split;
        rep.edges_contracted += g.contracted;
    }
    for (const auto& [f, d] : travelled)
        for (double x : d) rep.max_marker_travel = std::max(rep.max_marker_travel, x);
    rep.grow_seconds += seconds_since(t0);

    state.openings.opening.resize(state.cracks.num_vertices(), Vec3::Zero());
    state.openings.known.resize(state.cracks.num_vertices(), 0);
    state.step += 1;
    state.elements_added = rep.elements_added;
    for (const FrontState& fs : state.fronts) {
        rep.markers += fs.markers.markers.size();
        for (const MarkerState& m : fs.markers.markers) rep.active_markers += m.active ? 1 : 0;
    }
    rep.simulated_time = n * substep_duration(r_f, rayleigh_speed(law.mu(), law.rho));
    return rep;
}

}  // namespace cf::propagate
