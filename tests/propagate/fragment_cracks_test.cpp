// restrict_to_fragment (thesis ch. 7.3, fig. 43): the incomplete cracks a large fragment inherits.
// Parents: a penny crack grown one BEM step in a unit cube (fronts with markers), fresh sheets,
// a fan with a pinched node, and a cube cut by a through crack (real segment.fragments grids with
// the incomplete crack's slit). Every result is checked for the rules (mask depth, surface
// clearance, manifold front, no opening-free triangle, markers, regions, grids), and the cut
// penny is assembled, solved and propagated on the fragment.
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/initiate/surface_queries.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_step.hpp"
#include "nodes/propagate/fragment_cracks.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/shape/box.hpp"
#include "tests/harness/node_harness.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <iostream>
#include <map>
#include <set>

using namespace cf;
using namespace cf::propagate;
using cf::testing::run_node;
using cf::testing::value;

namespace {

constexpr double L = 1.0, r_c = 0.1, r_f = 0.01, sigma = 1e6, E = 3.1e9, nu = 0.327;
constexpr int n_per_edge = 10;  // ceil(r_c / r_f)

Material pmma() {
    Material m;
    m.E = E;
    m.nu = nu;
    m.rho = 1200;
    return m;
}

StepSettings step_settings() {
    StepSettings s;
    s.law.E = E;
    s.law.nu = nu;
    s.law.rho = 1200;
    s.surface_margin = r_f;
    return s;
}

ScalarField toughness(double Kc) { return make_field(std::make_shared<HomogeneousField>(Kc), FieldQuantity::toughness, 2); }

SurfaceMesh box(const Vec3& lo, const Vec3& hi, int subdivisions = 6) {
    BoxSpec b;
    b.size = hi - lo;
    b.centre = 0.5 * (lo + hi);
    b.subdivisions = subdivisions;
    return make_box(b);
}

// A penny crack of radius 0.2 in the unit cube under tension along z, grown by one BEM step
// (fronts with markers, SIF history); the markers of front edge 3 are stopped by hand, so copying
// a stopped edge is checked too.
const FractureState& grown_penny() {
    static const FractureState state = [] {
        const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
        FractureState s = start_fracture_state(r_c, r_f, 3, cube.num_triangles());
        const SurfaceMesh disk = bem::bem_disk_mesh(2, 0.2);
        add_crack(s, disk, mesh_triangles(disk));
        const auto surface = bem::assemble_surface_operators(cube, pmma(), {});
        const auto cracks = bem::append_crack_elements(*surface, nullptr, s.cracks);
        const auto bc = bem::resolve(bem::parse_boundary_conditions("z_max: traction 0 0 " + std::to_string(sigma) +
                                                                    "; z_min: displacement 0 0 0; *: traction 0 0 0"),
                                     cube);
        const auto sol = bem::solve_sgbem(surface, cracks, bc, {}, nullptr);
        const auto sifs = bem::displacement_correlation_sifs(s.cracks, sol->crack_opening, E, nu);
        static const LevelSet cube_ls = level_set_from_mesh(cube, r_f);
        propagate_step(s, sifs, toughness(1e5), &cube_ls, step_settings());
        for (int k = 0; k < n_per_edge; ++k) s.fronts.at(0).markers.markers.at(3 * n_per_edge + k).active = false;
        return s;
    }();
    return state;
}

using Key = std::array<double, 3>;
Key key(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

std::vector<int> boundary_counts(const SurfaceMesh& m) {
    std::map<std::pair<int, int>, int> edges;
    for (const Tri& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    std::vector<int> b(m.num_vertices(), 0);
    for (const auto& [e, c] : edges) {
        EXPECT_LE(c, 2) << "edge " << e.first << "-" << e.second;
        if (c == 1) ++b[e.first], ++b[e.second];
    }
    return b;
}

void expect_same_marker(const MarkerState& a, const MarkerState& b, const std::string& where) {
    EXPECT_EQ(a.position, b.position) << where;
    EXPECT_EQ(a.n1, b.n1) << where;
    EXPECT_EQ(a.n2, b.n2) << where;
    EXPECT_EQ(a.K.KI, b.K.KI) << where;
    EXPECT_EQ(a.K.KII, b.K.KII) << where;
    EXPECT_EQ(a.K.KIII, b.K.KIII) << where;
    EXPECT_EQ(a.K_old.KI, b.K_old.KI) << where;
    EXPECT_EQ(a.has_old, b.has_old) << where;
    EXPECT_EQ(a.last_direction, b.last_direction) << where;
    EXPECT_EQ(a.last_theta, b.last_theta) << where;
    EXPECT_EQ(a.active, b.active) << where;
}

struct EdgeTally {
    std::size_t copied = 0, fresh_old = 0, cut = 0;
};

// Every rule of restrict_to_fragment, checked on its result. Tolerance of the depth checks:
// 0.05 r_f (trilinear interpolation of a box's distance field away from its edges is exact; the
// tolerance only absorbs float storage of the grid).
EdgeTally expect_valid(const FragmentCracks& r, const FractureState& parent, const LevelSet& fragment,
                       const SurfaceMesh& surface, bool convex_fragment) {
    const FractureState& s = r.state;
    EdgeTally tally;
    EXPECT_EQ(s.r_c, parent.r_c);
    EXPECT_EQ(s.r_f, parent.r_f);
    EXPECT_EQ(s.step, 0);
    EXPECT_EQ(s.initiated, std::vector<char>(surface.num_triangles(), 0));
    EXPECT_EQ(r.kept_triangles + r.dropped_triangles, parent.cracks.num_triangles());
    EXPECT_EQ(s.cracks.num_triangles(), r.kept_triangles);
    EXPECT_LE(r.ring_triangles, r.kept_triangles);
    EXPECT_EQ(s.openings.opening.size(), s.cracks.num_vertices());
    EXPECT_EQ(s.openings.known, std::vector<char>(s.cracks.num_vertices(), 0));
    EXPECT_EQ(s.grids.voxel_size, parent.grids.voxel_size);
    EXPECT_EQ(s.grids.half_width, parent.grids.half_width);
    if (s.cracks.num_triangles() == 0) {
        EXPECT_EQ(s.cracks.num_vertices(), 0u);
        EXPECT_TRUE(s.fronts.empty());
        EXPECT_TRUE(s.grids.cracks.empty());
        return tally;
    }
    // Vertices: each used, each a parent vertex (copied bit for bit); regions 0..n-1, one grid each,
    // the parent's grid of that crack (shared), in the parent's order.
    std::map<Key, int> parent_id;
    for (std::size_t v = 0; v < parent.cracks.num_vertices(); ++v) parent_id[key(parent.cracks.vertices[v])] = int(v);
    std::vector<int> pid(s.cracks.num_vertices());
    std::vector<char> used(s.cracks.num_vertices(), 0);
    for (const Tri& t : s.cracks.triangles)
        for (int v : t) used[v] = 1;
    for (std::size_t v = 0; v < s.cracks.num_vertices(); ++v) {
        EXPECT_TRUE(used[v]) << "unused vertex " << v;
        const auto it = parent_id.find(key(s.cracks.vertices[v]));
        EXPECT_NE(it, parent_id.end()) << "vertex " << v << " is not a parent vertex";
        pid[v] = it == parent_id.end() ? -1 : it->second;
    }
    EXPECT_EQ(s.cracks.region.size(), s.cracks.num_triangles());
    std::set<int> regions(s.cracks.region.begin(), s.cracks.region.end());
    EXPECT_EQ(int(regions.size()), s.num_cracks());
    EXPECT_EQ(*regions.begin(), 0);
    EXPECT_EQ(*regions.rbegin(), s.num_cracks() - 1);
    EXPECT_EQ(int(s.cracks.region_names.size()), s.num_cracks());
    std::map<int, int> parent_region;  // new region -> parent region
    std::map<std::array<int, 3>, std::size_t> parent_tri;
    for (std::size_t t = 0; t < parent.cracks.num_triangles(); ++t) {
        const Tri& o = parent.cracks.triangles[t];
        parent_tri[{o[0], o[1], o[2]}] = t;
    }
    for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t) {
        const Tri& n = s.cracks.triangles[t];
        const auto it = parent_tri.find({pid[n[0]], pid[n[1]], pid[n[2]]});
        if (it == parent_tri.end()) {
            ADD_FAILURE() << "triangle " << t << " is not a parent triangle (same orientation)";
            continue;
        }
        const int pr = parent.cracks.region_of(it->second);
        const auto at = parent_region.insert({s.cracks.region[t], pr}).first;
        EXPECT_EQ(at->second, pr) << "one new region from two parent cracks";
    }
    int last = -1;
    for (const auto& [nr, pr] : parent_region) {
        EXPECT_GT(pr, last) << "regions keep the parent's order";
        last = pr;
        EXPECT_EQ(s.grids.cracks.at(nr).grid, parent.grids.cracks.at(pr).grid) << "crack " << nr << " has its parent's grid";
        EXPECT_EQ(s.cracks.region_names.at(nr), parent.cracks.region_name(pr));
    }
    // Inside the fragment and clear of the surface. The strict mask (>= r_f deep) holds at the
    // vertices of all but the 1-ring additions, which are inside at all; on a convex fragment the
    // depth at a vertex is at least that on both sides of the sheet, which is what is tested.
    const double clearance = fragment_crack_clearance(parent.r_c, parent.r_f);
    std::size_t shallow = 0;
    for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t) {
        bool deep = true;
        for (int v : s.cracks.triangles[t]) {
            const Vec3& x = s.cracks.vertices[v];
            if (convex_fragment) {
                const double phi = sample(fragment, x);
                EXPECT_LE(phi, 0.05 * r_f) << "vertex " << v << " outside the fragment";
                deep = deep && phi <= -0.95 * r_f;
            }
            EXPECT_GE(initiate::distance_to_mesh(surface, x), clearance * (1 - 1e-9)) << "vertex " << v;
            EXPECT_TRUE(initiate::inside_closed_mesh(surface, x)) << "vertex " << v;
        }
        if (!deep) ++shallow;
    }
    EXPECT_LE(shallow, r.ring_triangles) << "triangles shallower than r_f that are not 1-ring additions";
    // The front is a manifold boundary (two front edges per front node), and every triangle has a
    // non-front node (an opening unknown).
    const std::vector<int> b = boundary_counts(s.cracks);
    for (std::size_t v = 0; v < b.size(); ++v) EXPECT_TRUE(b[v] == 0 || b[v] == 2) << "vertex " << v << ": " << b[v];
    for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t) {
        const Tri& tri = s.cracks.triangles[t];
        EXPECT_FALSE(b[tri[0]] > 0 && b[tri[1]] > 0 && b[tri[2]] > 0) << "triangle " << t << " has three front nodes";
    }
    // Fronts: exactly the boundary edges, directed as in their triangles, in the right region.
    std::map<std::pair<int, int>, int> boundary_edge;  // directed boundary edge -> region
    {
        std::set<std::pair<int, int>> directed;
        for (const Tri& t : s.cracks.triangles)
            for (int k = 0; k < 3; ++k) directed.insert({t[k], t[(k + 1) % 3]});
        for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t)
            for (int k = 0; k < 3; ++k) {
                const Tri& tri = s.cracks.triangles[t];
                if (!directed.count({tri[(k + 1) % 3], tri[k]})) boundary_edge[{tri[k], tri[(k + 1) % 3]}] = s.cracks.region[t];
            }
    }
    std::map<std::pair<int, int>, std::pair<int, int>> parent_edge;
    for (std::size_t f = 0; f < parent.fronts.size(); ++f) {
        const CrackFront& fr = parent.fronts[f].front;
        for (std::size_t i = 0; i < fr.num_edges(); ++i)
            parent_edge[{fr.nodes[i], fr.nodes[(i + 1) % fr.nodes.size()]}] = {int(f), int(i)};
    }
    std::size_t front_edges = 0;
    for (std::size_t f = 0; f < s.fronts.size(); ++f) {
        const FrontState& fs = s.fronts[f];
        const std::size_t N = fs.front.nodes.size();
        EXPECT_TRUE(fs.front.closed);
        front_edges += fs.front.num_edges();
        bool all_old_same = true;
        for (std::size_t i = 0; i < N; ++i) {
            const int a = fs.front.nodes[i], c = fs.front.nodes[(i + 1) % N];
            const auto be = boundary_edge.find({a, c});
            EXPECT_NE(be, boundary_edge.end()) << "front " << f << " edge " << i << " is not a boundary edge";
            if (be != boundary_edge.end()) {
                EXPECT_EQ(be->second, fs.front.region);
            }
            const auto pe = parent_edge.find({pid[a], pid[c]});
            all_old_same = all_old_same && pe != parent_edge.end();
            if (fs.fresh) continue;
            if (fs.markers.markers.size() != N * n_per_edge) {
                ADD_FAILURE() << "front " << f << ": " << fs.markers.markers.size() << " markers for " << N << " edges";
                break;
            }
            EXPECT_EQ(fs.markers.per_edge, n_per_edge);
            for (int k = 0; k < n_per_edge; ++k) {
                const MarkerState& m = fs.markers.markers[i * n_per_edge + k];
                const std::string where = "front " + std::to_string(f) + " edge " + std::to_string(i) + " marker " + std::to_string(k);
                if (pe != parent_edge.end() && !parent.fronts[pe->second.first].fresh) {
                    expect_same_marker(m, parent.fronts[pe->second.first].markers.markers[pe->second.second * n_per_edge + k], where);
                    continue;
                }
                // Fresh parent edge (active) or cut edge (stopped): on the coarse edge, frame of the sheet.
                const Vec3 on_edge = s.cracks.vertices[a] + (double(k) / n_per_edge) * (s.cracks.vertices[c] - s.cracks.vertices[a]);
                EXPECT_LT((m.position - on_edge).norm(), 1e-12) << where;
                EXPECT_EQ(m.active, pe != parent_edge.end()) << where;
                EXPECT_FALSE(m.has_old) << where;
                EXPECT_NEAR(m.n1.dot(m.n2), 0, 1e-12) << where;
                EXPECT_GT(m.n1.cross(m.n2).dot(s.cracks.vertices[c] - s.cracks.vertices[a]), 0) << where << ": n3 = n1 x n2 not along the edge";
            }
            if (pe == parent_edge.end()) ++tally.cut;
            else if (parent.fronts[pe->second.first].fresh) ++tally.fresh_old;
            else ++tally.copied;
        }
        if (fs.fresh) {
            EXPECT_TRUE(all_old_same) << "a fresh front must be an unchanged fresh parent front";
            EXPECT_TRUE(fs.markers.markers.empty());
            tally.fresh_old += N;
        }
    }
    EXPECT_EQ(front_edges, boundary_edge.size()) << "every boundary edge on exactly one front";
    return tally;
}

// The restricted cracks go through assemble.sgbem and solve.sgbem (balanced tension along z, a
// pure Neumann problem as a free fragment has) and open: the crack-opening unknowns are usable.
bem::BemSolution assemble_and_solve(const SurfaceMesh& surface, const SurfaceMesh& cracks) {
    auto a = run_node("assemble.sgbem", {{"E", E}, {"nu", nu}}, {{"mesh", value(surface)}, {"cracks", value(cracks)}});
    auto s = run_node("solve.sgbem",
                      {{"boundary_conditions",
                        std::string("z_max: traction 0 0 1e6; z_min: traction 0 0 -1e6; *: traction 0 0 0")}},
                      {{"operators", a.outputs.at("operators")}});
    const bem::BemSolution sol = s.outputs.at("solution").get<bem::BemSolution>();
    EXPECT_EQ(sol.crack_opening.size(), cracks.num_vertices());
    const std::vector<int> b = boundary_counts(cracks);
    double mean_open = 0;
    int interior = 0;
    for (std::size_t v = 0; v < cracks.num_vertices(); ++v) {
        EXPECT_TRUE(sol.crack_opening[v].allFinite());
        if (b[v] == 0) mean_open += sol.crack_opening[v].z(), ++interior;
    }
    EXPECT_GT(interior, 0);
    EXPECT_GT(mean_open / std::max(interior, 1), 0) << "tension along z must open a crack in z = 0";
    return sol;
}

}  // namespace

TEST(FragmentCracks, CutPennyKeepsTheInsideWithAManifoldFrontAndStoppedCutEdges) {
    const FractureState& parent = grown_penny();
    ASSERT_FALSE(parent.fronts.at(0).fresh);
    // Fragment: the part x <= 0.1 of the cube; its BEM surface is that box.
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(0.1, 0.5, 0.5));
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    const FragmentCracks r = restrict_to_fragment(parent, fragment, surface);
    std::cout << "cut penny: kept " << r.kept_triangles << ", dropped " << r.dropped_triangles << ", ring "
              << r.ring_triangles << " of " << parent.cracks.num_triangles() << "\n";
    EXPECT_GT(r.kept_triangles, 0u);
    EXPECT_GT(r.dropped_triangles, 0u);
    ASSERT_EQ(r.state.num_cracks(), 1);
    ASSERT_EQ(r.state.fronts.size(), 1u);
    EXPECT_FALSE(r.state.fronts[0].fresh);
    const EdgeTally e = expect_valid(r, parent, fragment, surface, true);
    EXPECT_GT(e.copied, 0u);
    EXPECT_GT(e.cut, 0u);
    // The kept sheet ends before the cut: at least r_f (mask) deep and the clearance r_f from x = 0.1.
    for (const Vec3& v : r.state.cracks.vertices) EXPECT_LE(v.x(), 0.1 - r_f + 1e-12);
}

TEST(FragmentCracks, CutPennyAssemblesSolvesAndPropagatesOnTheFragment) {
    const FractureState& parent = grown_penny();
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(0.1, 0.5, 0.5));
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    FractureState s = restrict_to_fragment(parent, fragment, surface).state;
    const bem::BemSolution sol = assemble_and_solve(surface, s.cracks);
    // One more BEM step of the fragment's fracture: the copied fronts move on, the cut edges stay.
    const auto sifs = bem::displacement_correlation_sifs(s.cracks, sol.crack_opening, E, nu);
    EXPECT_EQ(sifs.size(), s.fronts.at(0).front.num_edges());
    const FractureState before = s;
    StepReport rep;
    ASSERT_NO_THROW(rep = propagate_step(s, sifs, toughness(1e5), &fragment, step_settings()));
    EXPECT_EQ(rep.fronts_propagated, 1);
    EXPECT_GT(rep.max_marker_travel, 0);
    // The cut stays where it is: a front node between two cut edges (all its markers stopped) is
    // still a front node after growth, and no crack vertex left the fragment.
    const FrontState& f0 = before.fronts[0];
    const std::size_t N = f0.front.nodes.size();
    auto edge_stopped = [&](std::size_t i) {
        for (int k = 0; k < n_per_edge; ++k)
            if (f0.markers.markers[(i % N) * n_per_edge + k].active) return false;
        return true;
    };
    std::set<Key> front_after;
    for (int v : s.fronts.at(0).front.nodes) front_after.insert(key(s.cracks.vertices[v]));
    std::size_t pinned = 0;
    for (std::size_t i = 0; i < N; ++i)
        if (edge_stopped(i) && edge_stopped(i + N - 1)) {
            ++pinned;
            EXPECT_TRUE(front_after.count(key(before.cracks.vertices[f0.front.nodes[i]]))) << "cut front node " << i << " moved";
        }
    EXPECT_GT(pinned, 0u);
    for (const Vec3& v : s.cracks.vertices) EXPECT_LT(sample(fragment, v), 0) << "crack vertex outside the fragment";
    EXPECT_GT(s.cracks.num_triangles(), before.cracks.num_triangles()) << "the copied front did not grow";
}

TEST(FragmentCracks, FragmentWithoutTheCrackGetsAnEmptyState) {
    const FractureState& parent = grown_penny();
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(-0.36, 0.5, 0.5));
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    const FragmentCracks r = restrict_to_fragment(parent, fragment, surface);
    EXPECT_EQ(r.kept_triangles, 0u);
    EXPECT_EQ(r.dropped_triangles, parent.cracks.num_triangles());
    EXPECT_EQ(r.state.num_cracks(), 0);
    EXPECT_EQ(r.state.cracks.num_triangles(), 0u);
    EXPECT_TRUE(r.state.fronts.empty());
    EXPECT_FALSE(r.state.has_active_markers());
    expect_valid(r, parent, fragment, surface, true);
}

TEST(FragmentCracks, FragmentContainingTheWholeCrackKeepsItUnchanged) {
    const FractureState& parent = grown_penny();
    {  // the premise: the grown parent has no triangle of three front nodes, so nothing is dropped
        const std::vector<int> b = boundary_counts(parent.cracks);
        for (const Tri& t : parent.cracks.triangles) ASSERT_FALSE(b[t[0]] > 0 && b[t[1]] > 0 && b[t[2]] > 0);
    }
    const SurfaceMesh surface = bem::bem_cube_mesh(4, L);
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    const FragmentCracks r = restrict_to_fragment(parent, fragment, surface);
    EXPECT_EQ(r.dropped_triangles, 0u);
    EXPECT_EQ(r.ring_triangles, 0u);
    const FractureState& s = r.state;
    EXPECT_EQ(s.cracks.vertices, parent.cracks.vertices);
    EXPECT_EQ(s.cracks.triangles, parent.cracks.triangles);
    EXPECT_EQ(s.cracks.region, std::vector<int>(parent.cracks.num_triangles(), 0));
    ASSERT_EQ(s.fronts.size(), parent.fronts.size());
    for (std::size_t f = 0; f < s.fronts.size(); ++f) {
        const FrontState &a = s.fronts[f], &p = parent.fronts[f];
        EXPECT_EQ(a.fresh, p.fresh);
        EXPECT_EQ(a.front.nodes, p.front.nodes);
        EXPECT_EQ(a.front.region, p.front.region);
        ASSERT_EQ(a.front.sifs.size(), p.front.sifs.size());
        for (std::size_t i = 0; i < a.front.sifs.size(); ++i) EXPECT_EQ(a.front.sifs[i].KI, p.front.sifs[i].KI);
        ASSERT_EQ(a.markers.markers.size(), p.markers.markers.size());
        EXPECT_EQ(a.markers.per_edge, p.markers.per_edge);
        for (std::size_t m = 0; m < a.markers.markers.size(); ++m)
            expect_same_marker(a.markers.markers[m], p.markers.markers[m], "marker " + std::to_string(m));
    }
    ASSERT_EQ(s.grids.cracks.size(), 1u);
    EXPECT_EQ(s.grids.cracks[0].grid, parent.grids.cracks[0].grid);
    expect_valid(r, parent, fragment, surface, true);
}

TEST(FragmentCracks, FreshSheetsStayFreshWhenWholeAndGetPlacedMarkersWhenCut) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    FractureState parent = start_fracture_state(r_c, r_f, 2, cube.num_triangles());
    const SurfaceMesh disk = bem::bem_disk_mesh(3, 0.3);
    add_crack(parent, disk, mesh_triangles(disk));
    {
        const LevelSet whole = level_set_from_mesh(cube, r_f);
        const FragmentCracks r = restrict_to_fragment(parent, whole, cube);
        ASSERT_EQ(r.state.fronts.size(), 1u);
        EXPECT_TRUE(r.state.fronts[0].fresh);
        EXPECT_TRUE(r.state.fronts[0].markers.markers.empty());
        EXPECT_EQ(r.state.fronts[0].front.nodes, parent.fronts[0].front.nodes);
        expect_valid(r, parent, whole, cube, true);
    }
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(0.1, 0.5, 0.5));
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    const FragmentCracks r = restrict_to_fragment(parent, fragment, surface);
    ASSERT_EQ(r.state.fronts.size(), 1u);
    EXPECT_FALSE(r.state.fronts[0].fresh);
    const EdgeTally e = expect_valid(r, parent, fragment, surface, true);
    EXPECT_GT(e.fresh_old, 0u);
    EXPECT_GT(e.cut, 0u);
    assemble_and_solve(surface, r.state.cracks);
}

namespace {

// A fan around v = (0.05, 0, 0) in z = 0 whose ring reaches into the fragment's last voxel at R3
// and R6 (x = 0.1 - 0.5 r_f; the fragment is x <= 0.1) or, with `out`, past it (x = 0.1 + 0.5 r_f).
// The mask keeps (v, R4, R5) and the fan R7..R2 but not the four triangles at R3 and R6, so v is a
// pinched front node (four front edges).
SurfaceMesh pinched_fan(bool out) {
    const double xs = out ? 0.1 + 0.5 * r_f : 0.1 - 0.5 * r_f;
    SurfaceMesh m;
    m.vertices = {{0.05, 0, 0},   {-0.01, 0, 0}, {0.0, -0.05, 0}, {0.06, -0.055, 0}, {xs, -0.02, 0},
                  {0.07, -0.006, 0}, {0.07, 0.006, 0}, {xs, 0.02, 0}, {0.06, 0.055, 0}, {0.0, 0.05, 0}};
    for (int i = 1; i <= 9; ++i) m.triangles.push_back({0, i, i % 9 + 1});
    m.region.assign(9, 0);
    m.region_names = {"fan"};
    return m;
}

}  // namespace

TEST(FragmentCracks, PinchedFrontNodeGetsItsRingOrLosesItsTriangles) {
    // The fragment's level set is the box x <= 0.1; its BEM surface lies 2 r_f further out, as a
    // remeshed surface offset outward does, so the last voxel is clear of it.
    const LevelSet fragment = level_set_from_mesh(box(Vec3(-0.3, -0.3, -0.3), Vec3(0.1, 0.3, 0.3)), r_f);
    const SurfaceMesh surface = box(Vec3(-0.32, -0.32, -0.32), Vec3(0.12, 0.32, 0.32));
    for (const bool out : {false, true}) {
        FractureState parent = start_fracture_state(r_c, r_f, 2, surface.num_triangles());
        const SurfaceMesh fan = pinched_fan(out);
        add_crack(parent, fan, mesh_triangles(fan));
        const FragmentCracks r = restrict_to_fragment(parent, fragment, surface);
        expect_valid(r, parent, fragment, surface, true);
        if (!out) {  // the 1-ring is inside: the whole fan, the parent's front
            EXPECT_EQ(r.ring_triangles, 4u);
            EXPECT_EQ(r.kept_triangles, 9u);
            ASSERT_EQ(r.state.fronts.size(), 1u);
            EXPECT_EQ(r.state.fronts[0].front.nodes, parent.fronts[0].front.nodes);
            EXPECT_TRUE(r.state.fronts[0].fresh);
        } else {  // R3 and R6 are outside: v loses its triangles, which is the whole fan
            EXPECT_EQ(r.kept_triangles, 0u);
            EXPECT_EQ(r.state.num_cracks(), 0);
        }
    }
}

TEST(FragmentCracks, SegmentedFragmentKeepsTheIncompleteCrackInsideItsSlit) {
    // A through crack at x = 0.1 (crack 0) splits the cube; a penny in z = 0 (crack 1) crosses it and
    // stays incomplete in both halves. The fragments come from segment's own eq. (6.1) grids, where
    // the penny is a positive slit: its sheet is inside only by the both-sides test.
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const LevelSet object = level_set_from_mesh(cube, r_f);
    FractureState parent = start_fracture_state(r_c, r_f, 2, cube.num_triangles());
    {
        SurfaceMesh through = bem::bem_disk_mesh(2, 0.2);
        for (Vec3& v : through.vertices) v = Vec3(0.1 + v.z(), v.x(), v.y());  // z = 0 -> x = 0.1, normal +x
        const double h = 0.7;
        const std::vector<Triangle3> plane = {{Vec3(0.1, -h, -h), Vec3(0.1, h, -h), Vec3(0.1, h, h)},
                                              {Vec3(0.1, -h, -h), Vec3(0.1, h, h), Vec3(0.1, -h, h)}};
        add_crack(parent, through, plane);
        const SurfaceMesh penny = bem::bem_disk_mesh(3, 0.3);
        add_crack(parent, penny, mesh_triangles(penny));
    }
    const Fragments frags = find_fragments(broken_object(object, parent.grids));
    ASSERT_EQ(frags.fragments.size(), 2u);
    for (const Fragment& f : frags.fragments) {
        const bool left = f.centroid.x() < 0.1;
        // BEM surface: the half box offset r_f outward from the slit's face at 0.1 -+ sqrt(3)/2 r_f.
        const double face = left ? 0.1 - crack_half_thickness(r_f) + r_f : 0.1 + crack_half_thickness(r_f) - r_f;
        const SurfaceMesh surface = left ? box(Vec3(-0.5 - r_f, -0.5 - r_f, -0.5 - r_f), Vec3(face, 0.5 + r_f, 0.5 + r_f))
                                         : box(Vec3(face, -0.5 - r_f, -0.5 - r_f), Vec3(0.5 + r_f, 0.5 + r_f, 0.5 + r_f));
        const FragmentCracks r = restrict_to_fragment(parent, f.grid, surface);
        std::cout << (left ? "left" : "right") << " fragment: kept " << r.kept_triangles << ", ring " << r.ring_triangles
                  << ", cracks " << r.state.num_cracks() << "\n";
        expect_valid(r, parent, f.grid, surface, false);
        if (!left) continue;
        // The through crack is the fragment's surface now (material on one side only): gone. The
        // penny is crack 0 of the fragment, with the parent's grid of crack 1.
        ASSERT_EQ(r.state.num_cracks(), 1);
        EXPECT_EQ(r.state.grids.cracks[0].grid, parent.grids.cracks[1].grid);
        EXPECT_GT(r.kept_triangles, 20u);
        std::size_t in_slit = 0;
        for (const Vec3& v : r.state.cracks.vertices) {
            EXPECT_LT(v.x(), 0.1 - crack_half_thickness(r_f));  // inside at all (1-ring), most r_f deeper
            EXPECT_NEAR(v.z(), 0, 1e-15);
            if (sample(f.grid, v) > 0) ++in_slit;  // what a plain "phi(v) <= -r_f" mask would reject
        }
        EXPECT_EQ(in_slit, r.state.cracks.num_vertices());
        assemble_and_solve(surface, r.state.cracks);
    }
}

TEST(FragmentCracks, BadInputsAreNamed) {
    const FractureState& parent = grown_penny();
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(0.1, 0.5, 0.5));
    const LevelSet coarse = level_set_from_mesh(surface, 2 * r_f);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { restrict_to_fragment(parent, coarse, surface); },
        {"voxel size"}));
    SurfaceMesh inward = surface;
    for (Tri& t : inward.triangles) std::swap(t[1], t[2]);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { restrict_to_fragment(parent, level_set_from_mesh(surface, r_f), inward); },
        {"outward"}));
    EXPECT_THROW(restrict_to_fragment(parent, LevelSet{}, surface), std::invalid_argument);
}

TEST(FragmentCracks, SameResultForAnyThreadCount) {
    const FractureState& parent = grown_penny();
    const SurfaceMesh surface = box(Vec3(-0.5, -0.5, -0.5), Vec3(0.1, 0.5, 0.5));
    const LevelSet fragment = level_set_from_mesh(surface, r_f);
    FragmentCracks r[2];
    for (int threads = 1; threads <= 2; ++threads) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        r[threads - 1] = restrict_to_fragment(parent, fragment, surface);
    }
    EXPECT_EQ(r[0].state.cracks.vertices, r[1].state.cracks.vertices);
    EXPECT_EQ(r[0].state.cracks.triangles, r[1].state.cracks.triangles);
    ASSERT_EQ(r[0].state.fronts.size(), r[1].state.fronts.size());
    for (std::size_t f = 0; f < r[0].state.fronts.size(); ++f)
        EXPECT_EQ(r[0].state.fronts[f].front.nodes, r[1].state.fronts[f].front.nodes);
}
