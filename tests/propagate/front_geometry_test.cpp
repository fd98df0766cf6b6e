// Crack-front geometry (thesis ch. 4.5.2, fig. 16) on hand-built sheets.
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/propagate/front_growth.hpp"
#include "tests/harness/expect_error.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>

namespace cf::propagate {
namespace {

// Regular hexagon of circumradius R in z = 0 with a centre node, normal +z.
SurfaceMesh hexagon(double R) {
    SurfaceMesh m;
    m.vertices.push_back(Vec3::Zero());
    for (int k = 0; k < 6; ++k) m.vertices.push_back(R * Vec3(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0));
    for (int k = 0; k < 6; ++k) m.triangles.push_back({0, 1 + k, 1 + (k + 1) % 6});
    m.region.assign(6, 0);
    return m;
}

// A strip: front nodes 0..4 at (i, 0, 0), interior row 5..9 at (i, 1, 0); front edges run +x,
// the crack lies at y > 0, so the front moves towards -y.
SurfaceMesh strip() {
    SurfaceMesh m;
    for (int i = 0; i < 5; ++i) m.vertices.push_back(Vec3(i, 0, 0));
    for (int i = 0; i < 5; ++i) m.vertices.push_back(Vec3(i, 1, 0));
    for (int i = 0; i < 4; ++i) {
        m.triangles.push_back({i, i + 1, 5 + i + 1});
        m.triangles.push_back({i, 5 + i + 1, 5 + i});
    }
    m.region.assign(8, 0);
    return m;
}

CrackFront strip_front() {
    CrackFront f;
    f.nodes = {0, 1, 2, 3, 4};
    f.closed = false;
    return f;
}

void expect_append_only(const SurfaceMesh& before, const SurfaceMesh& after) {
    ASSERT_GE(after.num_vertices(), before.num_vertices());
    for (std::size_t v = 0; v < before.num_vertices(); ++v) EXPECT_EQ(after.vertices[v], before.vertices[v]);
    for (std::size_t t = 0; t < before.num_triangles(); ++t) EXPECT_EQ(after.triangles[t], before.triangles[t]);
    EXPECT_EQ(after.region.size(), after.triangles.size());
}

void expect_flat_up(const SurfaceMesh& m, std::size_t from) {
    for (std::size_t t = from; t < m.num_triangles(); ++t) {
        EXPECT_GT(triangle_area(m, t), 0) << t;
        EXPECT_NEAR(triangle_normal(m, t).z(), 1, 1e-12) << "triangle " << t << " flipped";
    }
}

GrowthSettings growth(double r_c) {
    GrowthSettings g;
    g.r_c = r_c;
    return g;
}

TEST(CrackFront, ExtractHexagonFrontWithOutwardFrames) {
    const SurfaceMesh h = hexagon(1);
    const auto fronts = extract_fronts(h);
    ASSERT_EQ(fronts.size(), 1u);
    EXPECT_TRUE(fronts[0].closed);
    ASSERT_EQ(fronts[0].nodes.size(), 6u);
    // Order follows the triangle orientation a -> b: 1, 2, ..., 6.
    for (int k = 0; k < 6; ++k) EXPECT_EQ(fronts[0].nodes[k], 1 + k);
    EXPECT_TRUE(extract_fronts(SurfaceMesh{}).empty());
}

TEST(CrackFront, NodeSifsAreEdgeAveragesAndFramesOrthonormal) {
    const SurfaceMesh h = hexagon(1);
    CrackFront f = extract_fronts(h)[0];
    std::vector<EdgeSifs> edges;
    for (int k = 0; k < 6; ++k) {
        EdgeSifs e;
        e.v0 = f.nodes[k];
        e.v1 = f.nodes[(k + 1) % 6];
        e.K = {double(k), 2.0 * k, -1.0};
        const Vec3 t = (h.vertices[e.v1] - h.vertices[e.v0]).normalized();
        e.frame = orthonormalised(Vec3::UnitZ(), t);
        edges.push_back(e);
    }
    assign_node_sifs(f, edges);
    // Node k sits between edges k-1 and k: K_I = ((k-1 mod 6) + k) / 2.
    EXPECT_NEAR(f.sifs[0].KI, (5 + 0) / 2.0, 1e-15);
    EXPECT_NEAR(f.sifs[3].KI, (2 + 3) / 2.0, 1e-15);
    EXPECT_NEAR(f.sifs[3].KII, (4 + 6) / 2.0, 1e-15);
    EXPECT_NEAR(f.sifs[3].KIII, -1, 1e-15);
    for (int k = 0; k < 6; ++k) {
        const FrontFrame& fr = f.frames[k];
        EXPECT_NEAR(fr.n1.dot(fr.n2), 0, 1e-15);
        EXPECT_NEAR(fr.n2.norm(), 1, 1e-15);
        EXPECT_NEAR((fr.n1.cross(fr.n2) - fr.n3).norm(), 0, 1e-15);
        // At a hexagon corner the averaged forward normal is radial.
        EXPECT_NEAR(fr.n2.dot(h.vertices[f.nodes[k]].normalized()), 1, 1e-12);
    }
    edges.pop_back();
    EXPECT_THROW(assign_node_sifs(f, edges), std::invalid_argument);
}

TEST(FrontMarkers, PlacementAndIndexInterpolation) {
    EXPECT_EQ(markers_per_edge(0.01, 0.0005), 20);
    EXPECT_EQ(markers_per_edge(0.01, 0.0003), 34);  // ceil(33.3)
    const SurfaceMesh h = hexagon(1);
    CrackFront f = extract_fronts(h)[0];
    f.sifs.resize(6);
    f.frames.resize(6);
    for (int k = 0; k < 6; ++k) {
        f.sifs[k] = {double(k), 0, 0};
        f.frames[k] = orthonormalised(Vec3::UnitZ(), Vec3(-std::sin(k * M_PI / 3), std::cos(k * M_PI / 3), 0));
    }
    const FrontMarkers fm = place_markers(f, h, 4);
    ASSERT_EQ(fm.markers.size(), 24u);
    for (int k = 0; k < 6; ++k) EXPECT_NEAR((fm.markers[4 * k].position - h.vertices[f.nodes[k]]).norm(), 0, 1e-15);
    // Thesis: K(p_k) = (k-1)/n K_j + (n+1-k)/n K_i, k = 1..n; here marker 4*2 + 3 (k = 4): 3/4 K_3 + 1/4 K_2.
    EXPECT_NEAR(fm.markers[11].K.KI, 0.75 * 3 + 0.25 * 2, 1e-15);
    EXPECT_NEAR(fm.markers[23].K.KI, 0.75 * 0 + 0.25 * 5, 1e-15);  // wraps to node 0
    EXPECT_NEAR(fm.markers[11].n1.dot(fm.markers[11].n2), 0, 1e-15);
    EXPECT_NEAR(fm.markers[11].n2.norm(), 1, 1e-15);
}

TEST(FrontMarkers, ResampleEquallySpaced) {
    const std::vector<Vec3> square = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    const auto loop = resample_polyline(square, true, 8, 0);
    ASSERT_EQ(loop.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(polyline_length({loop[i], loop[(i + 1) % 8]}, false), 0.5, 1e-15);
    const std::vector<Vec3> uneven = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(3, 0, 0)};
    const auto open = resample_polyline(uneven, false, 4, 0);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(open[i].x(), i, 1e-15);
    const auto shifted = resample_polyline(square, true, 4, 0.5);
    EXPECT_NEAR((shifted[0] - Vec3(0.5, 0, 0)).norm(), 0, 1e-15);
    EXPECT_NEAR((shifted[3] - Vec3(0, 0.5, 0)).norm(), 0, 1e-15);
}

FrontMarkers strip_markers(const SurfaceMesh& m, const std::function<Vec3(const Vec3&)>& move) {
    FrontMarkers fm = place_markers(strip_front(), m, 5);  // odd n: symmetric windows
    for (auto& mk : fm.markers) mk.position = move(mk.position);
    return fm;
}

// A notch of the surface reaching in between two front nodes: both targets are admissible, but
// the new triangles over the notch would cross the surface, so the nodes next to it stay.
TEST(FrontGrowth, TrianglesCrossingAConcaveSurfaceAreNotMade) {
    SurfaceMesh m = strip();
    const SurfaceMesh before = m;
    const FrontMarkers fm = strip_markers(m, [](const Vec3& p) -> Vec3 { return p - Vec3(0, 0.8, 0); });
    GrowthSettings free = growth(1.0);
    SurfaceMesh m_free = m;
    const FrontGrowth all = grow_front(m_free, strip_front(), fm, free);
    EXPECT_EQ(all.added_triangles, 8u);  // every node moves: two triangles per edge (case a)
    // The notch: x in (1.3, 1.7), y in (-0.6, -0.2), outside the object; no node lies in it.
    GrowthSettings notched = growth(1.0);
    notched.inside = [](const Vec3& p) { return !(p.x() > 1.3 && p.x() < 1.7 && p.y() > -0.6 && p.y() < -0.2); };
    const FrontGrowth g = grow_front(m, strip_front(), fm, notched);
    expect_append_only(before, m);
    for (std::size_t t = before.num_triangles(); t < m.num_triangles(); ++t) {
        const Tri& tri = m.triangles[t];
        for (int i = 0; i <= 8; ++i)
            for (int j = 0; i + j <= 8; ++j) {
                const Vec3 p = (i * m.vertices[tri[0]] + j * m.vertices[tri[1]] + (8 - i - j) * m.vertices[tri[2]]) / 8.0;
                EXPECT_TRUE(notched.inside(p)) << "triangle " << t << " reaches into the notch at " << p.transpose();
            }
    }
    EXPECT_LT(g.added_triangles, all.added_triangles);
    EXPECT_GT(g.added_triangles, 0u);  // away from the notch the front still grows
}

// Degenerate fronts, one scope each: what grow_front does with them.
TEST(FrontGrowth, EdgeCases) {
    {
        SCOPED_TRACE("a front with no markers is refused, naming the counts, and appends nothing");
        SurfaceMesh m = strip();
        FrontMarkers fm = place_markers(strip_front(), m, 5);
        fm.markers.clear();
        EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
            [&] { grow_front(m, strip_front(), fm, growth(1.0)); },
            {"0 markers do not belong to a front of 5 nodes (expected 21)"}));
        EXPECT_EQ(m.num_triangles(), 8u);
        EXPECT_EQ(m.num_vertices(), 10u);
    }
    {
        SCOPED_TRACE("an empty front (no nodes, no markers) grows nothing");
        SurfaceMesh m = strip();
        const SurfaceMesh before = m;
        CrackFront empty;
        empty.closed = false;
        FrontMarkers none;
        none.closed = false;
        none.per_edge = 5;
        const FrontGrowth g = grow_front(m, empty, none, growth(1.0));
        EXPECT_EQ(g.added_vertices, 0u);
        EXPECT_EQ(g.added_triangles, 0u);
        EXPECT_TRUE(g.front.nodes.empty());
        EXPECT_TRUE(g.markers.markers.empty());
        expect_append_only(before, m);
        EXPECT_EQ(m.num_triangles(), before.num_triangles());
    }
    {
        SCOPED_TRACE("markers that did not move: no node moves, nothing is appended, the front stays");
        SurfaceMesh m = strip();
        const SurfaceMesh before = m;
        const FrontMarkers fm = strip_markers(m, [](const Vec3& p) -> Vec3 { return p; });
        const FrontGrowth g = grow_front(m, strip_front(), fm, growth(1.0));
        EXPECT_EQ(g.added_vertices, 0u);
        EXPECT_EQ(g.added_triangles, 0u);
        EXPECT_EQ(g.front.nodes, strip_front().nodes);
        EXPECT_EQ(m.num_triangles(), before.num_triangles());
    }
    {
        SCOPED_TRACE("a target edge length of zero is refused");
        SurfaceMesh m = strip();
        const FrontMarkers fm = strip_markers(m, [](const Vec3& p) -> Vec3 { return p - Vec3(0, 0.5, 0); });
        EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { grow_front(m, strip_front(), fm, growth(0.0)); },
                                                               {"r_c must be > 0"}));
    }
}

TEST(FrontGrowth, CaseA_UniformAdvance) {
    SurfaceMesh m = strip();
    const SurfaceMesh before = m;
    const FrontMarkers fm = strip_markers(m, [](const Vec3& p) -> Vec3 { return p - Vec3(0, 0.5, 0); });
    const FrontGrowth g = grow_front(m, strip_front(), fm, growth(1.0));
    expect_append_only(before, m);
    expect_flat_up(m, before.num_triangles());
    EXPECT_EQ(g.kept, 4);
    EXPECT_EQ(g.added_vertices, 5u);
    EXPECT_EQ(g.added_triangles, 8u);
    ASSERT_EQ(g.front.nodes.size(), 5u);
    // The window of 5 markers centred on a node averages to node - 0.5 e_y (ends: the end marker).
    for (int i = 0; i <= 4; ++i) EXPECT_NEAR((m.vertices[g.front.nodes[i]] - Vec3(i, -0.5, 0)).norm(), 0, 1e-14);
    for (std::size_t i = 0; i + 1 < g.front.nodes.size(); ++i) {
        const double L = (m.vertices[g.front.nodes[i + 1]] - m.vertices[g.front.nodes[i]]).norm();
        EXPECT_GT(L, 0.2);
        EXPECT_LT(L, 1.4);
    }
    EXPECT_EQ(g.markers.markers.size(), 4u * 5 + 1);
    EXPECT_TRUE(g.markers.markers[7].has_old);
}

TEST(FrontGrowth, CaseB_SpreadingFrontSplitsEdges) {
    SurfaceMesh m = strip();
    const SurfaceMesh before = m;
    const FrontMarkers fm = strip_markers(m, [](const Vec3& p) { return Vec3(1.6 * p.x(), -0.6, 0); });
    const FrontGrowth g = grow_front(m, strip_front(), fm, growth(1.0));
    expect_append_only(before, m);
    expect_flat_up(m, before.num_triangles());
    // Every new edge is 1.6 long: each splits, 3 triangles each.
    EXPECT_EQ(g.split, 4);
    EXPECT_EQ(g.added_triangles, 12u);
    ASSERT_EQ(g.front.nodes.size(), 9u);
    EXPECT_NEAR((m.vertices[g.front.nodes[0]] - Vec3(0, -0.6, 0)).norm(), 0, 1e-14);  // end node follows its marker
    // The inserted node of edge 1-2 is the mean of the 6 markers spanning it: the middle.
    EXPECT_NEAR((m.vertices[g.front.nodes[3]] - Vec3(1.6 * 1.5, -0.6, 0)).norm(), 0, 1e-14);
    for (std::size_t i = 0; i + 1 < g.front.nodes.size(); ++i) {
        const double L = (m.vertices[g.front.nodes[i + 1]] - m.vertices[g.front.nodes[i]]).norm();
        EXPECT_GT(L, 0.2);
        EXPECT_LT(L, 1.4);
    }
    EXPECT_EQ(g.markers.markers.size(), 8u * 5 + 1);  // n markers per new edge
}

TEST(FrontGrowth, CaseC_ConvergingFrontContracts) {
    SurfaceMesh m = strip();
    const SurfaceMesh before = m;
    // Pairs of nodes converge: node positions x -> 2 floor(x/2) + 0.5 +- 0.05 (close pairs).
    const FrontMarkers fm = strip_markers(m, [](const Vec3& p) { return Vec3(0.1 * p.x() + 2, -0.5, 0); });
    const FrontGrowth g = grow_front(m, strip_front(), fm, growth(1.0));
    expect_append_only(before, m);
    expect_flat_up(m, before.num_triangles());
    EXPECT_EQ(g.contracted, 2);  // (0,1) and (2,3) merge greedily; (1,2) and (3,4) join merged nodes
    EXPECT_EQ(g.front.nodes.size(), 3u);
}

TEST(FrontGrowth, OnlyOneNodeMoves) {
    SurfaceMesh m = strip();
    const SurfaceMesh before = m;
    FrontMarkers fm = place_markers(strip_front(), m, 5);
    for (int k = 8; k <= 12; ++k) fm.markers[k].position -= Vec3(0, 0.5, 0);  // the window of node 2 only
    const FrontGrowth g = grow_front(m, strip_front(), fm, growth(1.0));
    expect_append_only(before, m);
    expect_flat_up(m, before.num_triangles());
    EXPECT_EQ(g.added_vertices, 1u);
    EXPECT_EQ(g.added_triangles, 2u);
    EXPECT_EQ(g.front.nodes, (std::vector<int>{0, 1, 10, 3, 4}));
    EXPECT_NEAR((m.vertices[10] - Vec3(2, -0.5, 0)).norm(), 0, 1e-14);
}

TEST(FrontGrowth, ModeIPennyGrowsPlanarWithEdgesInRange) {
    // A hexagonal crack of radius r_c under uniform mode I (K = 2 K_c): n sub-steps move every
    // marker 0.75 r_c outward in the crack plane; the grown sheet stays planar, the old sheet
    // is untouched, and the new front edges lie in (0.2, 1.4) r_c.
    const double r_c = 0.01, r_f = 0.001;
    SurfaceMesh m = hexagon(r_c);
    const SurfaceMesh before = m;
    CrackFront f = extract_fronts(m)[0];
    std::vector<EdgeSifs> edges;
    for (std::size_t k = 0; k < 6; ++k) {
        EdgeSifs e;
        e.v0 = f.nodes[k];
        e.v1 = f.nodes[(k + 1) % 6];
        e.K = {2e6, 0, 0};
        e.frame = orthonormalised(Vec3::UnitZ(), m.vertices[e.v1] - m.vertices[e.v0]);
        edges.push_back(e);
    }
    assign_node_sifs(f, edges);
    const int n = markers_per_edge(r_c, r_f);
    FrontMarkers fm = place_markers(f, m, n);
    const ScalarField Kc = make_field(std::make_shared<HomogeneousField>(1e6), FieldQuantity::toughness, 2);
    PropagationSettings s;
    s.r_c = r_c;
    s.r_f = r_f;
    double moved = 0;
    for (int k = 0; k < n; ++k) moved = std::max(moved, advance_markers(fm, Kc, s, k, n, k == 0));
    EXPECT_NEAR(moved, 0.75 * r_f, 1e-15);
    for (const auto& mk : fm.markers) EXPECT_EQ(mk.position.z(), 0.0);
    const FrontGrowth g = grow_front(m, f, fm, growth(r_c));
    expect_append_only(before, m);
    expect_flat_up(m, before.num_triangles());
    ASSERT_GE(g.front.nodes.size(), 6u);
    for (std::size_t i = 0; i < g.front.nodes.size(); ++i) {
        const double L = (m.vertices[g.front.nodes[(i + 1) % g.front.nodes.size()]] - m.vertices[g.front.nodes[i]]).norm();
        EXPECT_GT(L, 0.2 * r_c);
        EXPECT_LT(L, 1.4 * r_c);
    }
    // The grown sheet is a single closed front again.
    const auto fronts = extract_fronts(m);
    ASSERT_EQ(fronts.size(), 1u);
    EXPECT_EQ(fronts[0].nodes.size(), g.front.nodes.size());
    std::cout << "hexagon r_c grew to " << g.front.nodes.size() << " front nodes: " << g.kept << " kept, " << g.split
              << " split, " << g.contracted << " contracted; " << g.added_triangles << " triangles added\n";
}

}  // namespace
}  // namespace cf::propagate
