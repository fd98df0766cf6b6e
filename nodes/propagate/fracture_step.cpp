#include "nodes/propagate/fracture_step.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/propagate/opening_estimate.hpp"
#include "nodes/bem/element_geometry.hpp"
#include "nodes/bem/surface_intersection.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
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

namespace {

// The passes of one BEM time step (propagate_step below calls them in order). The fronts that move
// this step, the marker positions of the sub-step being recorded and the report are shared.
class StepPasses {
public:
    StepPasses(FractureState& state, const ScalarField& toughness, const LevelSet* object, const StepSettings& settings)
        : state_(state), toughness_(toughness), object_(object), settings_(settings) {}

    // The state's resolutions, the propagation law for them and the sub-step count.
    void check_and_set_up() {
        if (!toughness_.source) throw std::invalid_argument("propagate_step: no toughness field");
        const double r_c = state_.r_c, r_f = state_.r_f;
        if (!(r_f > 0) || !(r_c > r_f))
            throw std::invalid_argument("propagate_step: the state needs 0 < r_f < r_c (got r_f = " + graph::format_number(r_f) +
                                        " m, r_c = " + graph::format_number(r_c) + " m)");
        law_ = settings_.law;
        law_.r_c = r_c;
        law_.r_f = r_f;
        per_edge_ = markers_per_edge(r_c, r_f);
        n_ = settings_.substeps > 0 ? settings_.substeps : per_edge_;
        for (const Vec3& v : state_.cracks.vertices)
            if (!v.allFinite()) throw std::invalid_argument("propagate_step: crack mesh has a non-finite vertex");
        rep_.substeps = n_;
    }

    // Fronts that move this step; their SIFs go to nodes and markers.
    void choose_moving_fronts(const std::vector<bem::FrontEdgeSif>& sifs) {
        const std::vector<EdgeSifs> edges = to_edge_sifs(sifs);
        std::set<std::pair<int, int>> have;
        for (const EdgeSifs& e : edges) {
            if (e.v0 < 0 || e.v1 < 0 || std::size_t(std::max(e.v0, e.v1)) >= state_.cracks.num_vertices())
                throw std::invalid_argument("SIF record for edge " + std::to_string(e.v0) + " -> " + std::to_string(e.v1) +
                                            " names a vertex the crack mesh does not have: SIFs and state come from different runs");
            have.insert(edge_key(e.v0, e.v1));
        }
        const auto t0 = Clock::now();
        planar_first_.assign(state_.fronts.size(), 0);
        for (std::size_t f = 0; f < state_.fronts.size(); ++f) {
            FrontState& fs = state_.fronts[f];
            if (!fs.fresh && !any_active(fs.markers)) {
                ++rep_.fronts_stopped;
                continue;
            }
            if (!has_all_edges(fs.front, have)) {
                ++rep_.fronts_waiting;
                continue;
            }
            assign_node_sifs(fs.front, edges);
            if (fs.fresh) {
                fs.markers = place_markers(fs.front, state_.cracks, per_edge_);
                planar_first_[f] = 1;
                fs.fresh = false;
            } else {
                interpolate_front_state(fs.markers, fs.front, true);
            }
            moving_.push_back(f);
        }
        rep_.fronts_propagated = static_cast<int>(moving_.size());
        group_into_rounds();
        rep_.propagate_seconds += seconds_since(t0);
    }

    // The n sub-steps: markers advance, their strips are tested and recorded, markers re-spaced.
    void run_substeps(const SubstepObserver& observer) {
        CrackRecorder recorder(state_.grids);
        for (std::size_t f : moving_) travelled_[f].assign(state_.fronts[f].markers.markers.size(), 0.0);
        for (int k = 0; k < n_; ++k) {
            auto t0 = Clock::now();
            advance_markers(k);
            rep_.propagate_seconds += seconds_since(t0);
            t0 = Clock::now();
            for (const std::vector<std::size_t>& round : rounds_) record_round(round, recorder);
            rep_.record_seconds += seconds_since(t0);
            t0 = Clock::now();
            for (std::size_t f : moving_) respace(state_.fronts[f].markers);
            rep_.propagate_seconds += seconds_since(t0);
            if (observer) observer(k, recorder);
        }
        state_.grids = recorder.release();  // recording is done; growth only samples the grids
    }

    // Whether the triangle (a, b, c) touches or crosses the ordinary BEM surface (the assembly's own
    // test, bem::triangles_intersect); the surface's element geometry is built on first use.
    bool crosses_bem_surface(const Vec3& a, const Vec3& b, const Vec3& c) {
        if (surface_elements_.empty())
            surface_elements_ = bem::element_geometries(*settings_.bem_surface, "ordinary BEM surface");
        bem::ElementGeometry t;
        t.p = {a, b, c};
        const Vec3 n = (b - a).cross(c - a);
        if (!(n.norm() > 0)) return true;  // degenerate: never an element
        t.normal = n.normalized();
        t.centroid = (a + b + c) / 3.0;
        t.diameter = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
        for (const bem::ElementGeometry& s : surface_elements_)
            if (bem::triangles_intersect(t, s)) return true;
        return false;
    }

    // New BEM elements (fig. 16), away from the object's surface and from other cracks.
    void grow_fronts() {
        const auto t0 = Clock::now();
        const std::vector<LevelSet>& grids_now = state_.grids.cracks;
        for (std::size_t f : moving_) {
            FrontState& fs = state_.fronts[f];
            const int own = fs.front.region;
            GrowthSettings gs;
            gs.r_c = state_.r_c;
            gs.admissible = [&](const Vec3& p) {
                if (object_ && sample(*object_, p) > -settings_.surface_margin) return false;
                for (std::size_t c = 0; c < grids_now.size(); ++c)
                    if (static_cast<int>(c) != own && sample(grids_now[c], p) < settings_.crack_margin) return false;
                return true;
            };
            if (object_) gs.inside = [&](const Vec3& p) { return sample(*object_, p) < 0; };
            if (settings_.bem_surface) gs.crosses_surface = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
                return crosses_bem_surface(a, b, c);
            };
            const FrontGrowth g = grow_front(state_.cracks, fs.front, fs.markers, gs);
            rep_.openings_estimated +=
                estimate_openings_left_behind(state_.cracks, fs.front, g.front, law_.E, law_.nu, state_.openings);
            fs.front = g.front;
            fs.markers = g.markers;
            rep_.elements_added += g.added_triangles;
            rep_.vertices_added += g.added_vertices;
            rep_.edges_kept += g.kept;
            rep_.edges_split += g.split;
            rep_.edges_contracted += g.contracted;
        }
        for (const auto& [f, d] : travelled_)
            for (double x : d) rep_.max_marker_travel = std::max(rep_.max_marker_travel, x);
        rep_.grow_seconds += seconds_since(t0);
    }

    // The state's step count, openings sized to the grown mesh, marker counts, simulated time.
    StepReport finish() {
        state_.openings.opening.resize(state_.cracks.num_vertices(), Vec3::Zero());
        state_.openings.known.resize(state_.cracks.num_vertices(), 0);
        state_.step += 1;
        state_.elements_added = rep_.elements_added;
        for (const FrontState& fs : state_.fronts) {
            rep_.markers += fs.markers.markers.size();
            for (const MarkerState& m : fs.markers.markers) rep_.active_markers += m.active ? 1 : 0;
        }
        rep_.simulated_time = n_ * substep_duration(state_.r_f, rayleigh_speed(law_.mu(), law_.rho));
        return rep_;
    }

private:
    // Rounds of recording: one front per crack per round (a crack grid records one motion at a time).
    void group_into_rounds() {
        std::map<int, int> seen;
        for (std::size_t f : moving_) {
            const int r = seen[state_.fronts[f].front.region]++;
            if (r >= static_cast<int>(rounds_.size())) rounds_.resize(r + 1);
            rounds_[r].push_back(f);
        }
        for (std::size_t f : moving_)
            if (state_.fronts[f].front.region < 0 || state_.fronts[f].front.region >= state_.num_cracks())
                throw std::invalid_argument("front of crack " + std::to_string(state_.fronts[f].front.region) +
                                            " has no crack grid (the state has " + std::to_string(state_.num_cracks()) + ")");
    }

    // Forward Euler for every marker of every moving front (eq. 4.11); independent per marker.
    void advance_markers(int k) {
        const double w_t = blend_weight(k, n_);
        p0_.clear();
        p1_.clear();
        theta_.clear();
        for (std::size_t f : moving_) {
            FrontMarkers& fm = state_.fronts[f].markers;
            const bool planar = planar_first_[f] && k == 0;
            align_frames_to_polyline(fm);
            std::vector<Vec3>& a = p0_[f];
            std::vector<Vec3>& b = p1_[f];
            a = fm.positions();
            b = a;
            std::vector<double>& th = theta_[f];
            th.assign(fm.markers.size(), 0.0);
            tbb::parallel_for(std::size_t(0), fm.markers.size(), [&](std::size_t i) {
                const MarkerStep st = marker_substep(fm.markers[i], toughness_, law_, w_t, planar);
                b[i] = a[i] + st.displacement;
                th[i] = st.theta;
            });
        }
    }

    // Geometry tests against the grids so far, then recording of the swept strips (ch. 6.2), for
    // the fronts of one round; markers that hit something stop (fig. 27).
    void record_round(const std::vector<std::size_t>& round, CrackRecorder& recorder) {
        std::vector<FrontMotion> motions(state_.num_cracks());
        for (std::size_t f : round) {
            FrontMotion& m = motions[state_.fronts[f].front.region];
            m.p0 = p0_[f];
            m.p1 = p1_[f];
            m.closed = state_.fronts[f].markers.closed;
        }
        std::size_t written = 0;
        const auto tests = recorder.record_substep(motions, object_, &written);
        rep_.voxels_written += written;
        for (std::size_t f : round) {
            FrontMarkers& fm = state_.fronts[f].markers;
            const std::vector<MarkerTest>& t = tests[state_.fronts[f].front.region];
            for (std::size_t i = 0; i < fm.markers.size(); ++i) {
                MarkerState& m = fm.markers[i];
                if (!m.active) continue;
                if (t[i].hit == MarkerHit::none) {
                    const Vec3 d = p1_[f][i] - m.position;
                    travelled_[f][i] += d.norm();
                    m.position = p1_[f][i];
                    if (d.squaredNorm() > 0) {  // remembered for eq. (4.12) in the next BEM step
                        m.last_direction = d.normalized();
                        m.last_theta = theta_[f][i];
                    }
                    continue;
                }
                // Deactivated (fig. 27): the strip up to p1 is recorded so the crack meets the
                // other surface; the marker stays at p0, inside, so the coarse front does too.
                m.active = false;
                if (t[i].hit == MarkerHit::left_object) ++rep_.hits_left_object;
                else if (t[i].hit == MarkerHit::crossed_crack) ++rep_.hits_crossed_crack;
                else ++rep_.hits_self_intersection;
            }
        }
    }

    FractureState& state_;
    const ScalarField& toughness_;
    const LevelSet* object_;
    std::vector<bem::ElementGeometry> surface_elements_;  // of settings_.bem_surface, built on first use
    const StepSettings& settings_;
    PropagationSettings law_;
    int per_edge_ = 0, n_ = 0;  // markers per edge, sub-steps
    StepReport rep_;
    std::vector<std::size_t> moving_;
    std::vector<char> planar_first_;
    std::vector<std::vector<std::size_t>> rounds_;
    std::map<std::size_t, std::vector<double>> travelled_;
    // The sub-step being recorded: marker positions before and after, and the angle each moved at.
    std::map<std::size_t, std::vector<Vec3>> p0_, p1_;
    std::map<std::size_t, std::vector<double>> theta_;
};

}  // namespace

StepReport propagate_step(FractureState& state, const std::vector<bem::FrontEdgeSif>& sifs, const ScalarField& toughness,
                          const LevelSet* object, const StepSettings& settings, const SubstepObserver& observer) {
    StepPasses step(state, toughness, object, settings);
    step.check_and_set_up();
    step.choose_moving_fronts(sifs);
    step.run_substeps(observer);
    step.grow_fronts();
    return step.finish();
}

}  // namespace cf::propagate
