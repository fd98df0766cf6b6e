// Crack initiation rules (thesis ch. 4.4) on hand-built element lists.
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/initiate/initiation.hpp"

#include <gtest/gtest.h>

namespace cf::initiate {
namespace {

ScalarField strength(double S, double fc) {
    return make_field(std::make_shared<HomogeneousField>(S), FieldQuantity::strength, fc);
}

ElementStress element(double sxx, double szz, const Vec3& centroid) {
    ElementStress e;
    e.sigma = Mat3::Zero();
    e.sigma(0, 0) = sxx;
    e.sigma(2, 2) = szz;
    e.centroid = centroid;
    e.normal = Vec3::UnitY();
    return e;
}

TEST(SelectInitiations, OrderedByExcessTensileAndCompressive) {
    // Strength 10 MPa, f_c = 3: element 0 exceeds by 2 MPa (tension), element 1 by 5 MPa
    // (compression: 35 - 30), element 2 below both, element 3 by 1 MPa.
    const std::vector<ElementStress> els = {element(12e6, 0, Vec3(0, 0, 0)), element(0, -35e6, Vec3(1, 0, 0)),
                                            element(9e6, -29e6, Vec3(2, 0, 0)), element(11e6, 0, Vec3(3, 0, 0))};
    InitiationSettings s;
    s.r_c = 0.1;
    s.max_cracks = 10;
    const auto out = select_initiations(els, strength(10e6, 3), {}, {}, s);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].element, 1);
    EXPECT_TRUE(out[0].compressive);
    EXPECT_NEAR(out[0].excess, 5e6, 1e-6);
    EXPECT_NEAR(std::abs(out[0].plane_normal.z()), 1, 1e-12);  // crack normal to the compression axis
    EXPECT_EQ(out[1].element, 0);
    EXPECT_FALSE(out[1].compressive);
    EXPECT_NEAR(std::abs(out[1].plane_normal.x()), 1, 1e-12);
    EXPECT_EQ(out[2].element, 3);
}

TEST(SelectInitiations, LimitInitiatedFlagsAndFrontDistance) {
    const std::vector<ElementStress> els = {element(20e6, 0, Vec3(0, 0, 0)), element(15e6, 0, Vec3(0.05, 0, 0)),
                                            element(12e6, 0, Vec3(1, 0, 0)), element(11e6, 0, Vec3(2, 0, 0))};
    InitiationSettings s;
    s.r_c = 0.1;
    s.max_cracks = 3;
    s.existing_cracks = 1;  // (d): two more allowed
    // Element 1 lies within r_c of element 0's new crack front: skipped (c); element 3, far from
    // every front, is left over once the budget is spent (d) and counted so.
    SelectionCounts n;
    auto out = select_initiations(els, strength(10e6, 2), {}, {}, s, {}, &n);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].element, 0);
    EXPECT_EQ(out[1].element, 2);
    EXPECT_EQ(n.over_strength, 4);
    EXPECT_EQ(n.skipped_near_front, 1);
    EXPECT_EQ(n.over_budget, 1);
    // A larger budget takes element 3 too: nothing is held back.
    s.max_cracks = 4;
    EXPECT_EQ(select_initiations(els, strength(10e6, 2), {}, {}, s, {}, &n).size(), 3u);
    EXPECT_EQ(n.over_budget, 0);
    EXPECT_EQ(n.skipped_near_front, 1);
    s.max_cracks = 3;
    // (b): element 0 initiated before; an existing front near element 2 blocks it too.
    const std::vector<Segment> fronts = {{Vec3(1, 0.05, -1), Vec3(1, 0.05, 1)}};
    out = select_initiations(els, strength(10e6, 2), {1, 0, 0, 0}, fronts, s);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].element, 1);
    EXPECT_EQ(out[1].element, 3);
    s.existing_cracks = 3;
    EXPECT_TRUE(select_initiations(els, strength(10e6, 2), {}, {}, s, {}, &n).empty());
    EXPECT_EQ(n.over_budget, 4);  // no budget, no fronts: all four held back
    EXPECT_THROW(select_initiations(els, strength(10e6, 2), {1, 0}, {}, s), std::invalid_argument);
}

TEST(SelectInitiations, StrengthFieldBiasesTowardsWeakRegions) {
    // Same stress everywhere; strength rises with |z| (fig. 18): the weakest element goes first.
    const ScalarField S = make_field(std::make_shared<LayeredField>(20e6, 15e6, 10.0, Vec3::UnitZ()),
                                     FieldQuantity::strength, 2);
    const std::vector<ElementStress> els = {element(10e6, 0, Vec3(0, 0, 0.2)), element(10e6, 0, Vec3(0, 0, 0.01)),
                                            element(10e6, 0, Vec3(0, 0, -0.1))};
    InitiationSettings s;
    s.r_c = 0.05;
    s.max_cracks = 1;
    const auto out = select_initiations(els, S, {}, {}, s);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].element, 1);
}

TEST(HexagonCrack, GeometryAndOffset) {
    const double r_c = 0.05;
    const Vec3 p = Vec3(0, 0, 1), n = Vec3(1, 0, 0), c = Vec3(0.5, 0.1, 0.2);
    const Vec3 centre = initial_crack_centre(c, n, p, r_c);
    // Plane normal orthogonal to the element normal: offset R (1 + 1/4) into the body.
    EXPECT_NEAR((centre - (c - Vec3(0.0125, 0, 0))).norm(), 0, 1e-15);
    const SurfaceMesh h = hexagon_crack(centre, p, r_c, "crack");
    ASSERT_EQ(h.num_vertices(), 7u);
    ASSERT_EQ(h.num_triangles(), 6u);
    EXPECT_EQ(h.vertices[0], centre);
    double area = 0;
    for (std::size_t t = 0; t < 6; ++t) {
        EXPECT_NEAR(triangle_normal(h, t).dot(p), 1, 1e-12);  // in the principal plane, oriented by p
        area += triangle_area(h, t);
    }
    EXPECT_NEAR(area, 1.5 * std::sqrt(3.0) * 0.01 * 0.01, 1e-15);  // regular hexagon, R = 0.2 r_c = 0.01
    for (int k = 1; k <= 6; ++k) {
        EXPECT_NEAR((h.vertices[k] - centre).norm(), 0.01, 1e-15);
        EXPECT_LT((h.vertices[k] - c).dot(n), -0.0024);  // clear of the element plane by >= R/4
    }
    // Tilted plane normal: the rim still stays inside by R/4.
    const Vec3 tilted = Vec3(1, 0, 1).normalized();
    const SurfaceMesh h2 = hexagon_crack(initial_crack_centre(c, n, tilted, r_c), tilted, r_c, "c");
    for (int k = 1; k <= 6; ++k) EXPECT_LE((h2.vertices[k] - c).dot(n), -0.0025 + 1e-12);
}

TEST(AppendCrackSheet, AppendOnlyWithNewRegion) {
    SurfaceMesh cracks;
    const SurfaceMesh a = hexagon_crack(Vec3::Zero(), Vec3::UnitZ(), 0.1, "first");
    const SurfaceMesh b = hexagon_crack(Vec3(1, 0, 0), Vec3::UnitX(), 0.1, "second");
    EXPECT_EQ(append_crack_sheet(cracks, a), 0);
    const SurfaceMesh before = cracks;
    EXPECT_EQ(append_crack_sheet(cracks, b), 1);
    ASSERT_EQ(cracks.num_triangles(), 12u);
    for (std::size_t t = 0; t < 6; ++t) EXPECT_EQ(cracks.triangles[t], before.triangles[t]);
    for (std::size_t v = 0; v < 7; ++v) EXPECT_EQ(cracks.vertices[v], before.vertices[v]);
    EXPECT_EQ(cracks.triangles[6][0], 7);
    EXPECT_EQ(cracks.region[11], 1);
    EXPECT_EQ(cracks.region_name(1), "second");
}

}  // namespace
}  // namespace cf::initiate
