// The closest point on a triangle (nodes/domain/triangle_closest_point.hpp) against a brute-force
// reference: the nearest of a dense barycentric lattice of the triangle, which is at most one
// lattice step farther than the true closest point and never nearer. Random triangles, then the
// degenerate ones (collinear corners, a collapsed edge, three equal points), then the features.
#include "nodes/domain/triangle_closest_point.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cf {
namespace {

constexpr int kLattice = 200;

// Nearest lattice point of the triangle to p (the brute-force reference) [m].
double lattice_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    double best = 1e300;
    for (int i = 0; i <= kLattice; ++i)
        for (int j = 0; i + j <= kLattice; ++j) {
            const double s = double(i) / kLattice, t = double(j) / kLattice;
            best = std::min(best, (p - ((1 - s - t) * a + s * b + t * c)).norm());
        }
    return best;
}

double longest_edge(const Vec3& a, const Vec3& b, const Vec3& c) {
    return std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
}

// The answer is a point of the triangle at the distance it reports, no farther than the lattice
// reference and within one lattice step of it.
void expect_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const TriangleClosestPoint q = closest_point_on_triangle(p, a, b, c);
    ASSERT_TRUE(q.point.allFinite());
    EXPECT_GE(q.barycentric.minCoeff(), -1e-12);
    EXPECT_NEAR(q.barycentric.sum(), 1.0, 1e-12);
    EXPECT_LT((q.barycentric[0] * a + q.barycentric[1] * b + q.barycentric[2] * c - q.point).norm(), 1e-12);
    EXPECT_NEAR((p - q.point).squaredNorm(), q.distance2, 1e-12);
    const double reference = lattice_distance(p, a, b, c);
    const double d = std::sqrt(q.distance2);
    EXPECT_LE(d, reference + 1e-12);
    EXPECT_LT(reference - d, longest_edge(a, b, c) / kLattice + 1e-12);
}

TEST(ClosestPointOnTriangle, MatchesDenseSampling) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 200; ++trial) {
        const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
        expect_closest(1.5 * Vec3(u(rng), u(rng), u(rng)), a, b, c);
    }
}

TEST(ClosestPointOnTriangle, DegenerateTriangleIsItsLongestEdge) {
    const TriangleClosestPoint q = closest_point_on_triangle(Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
    EXPECT_NEAR(std::sqrt(q.distance2), 1.0, 1e-15);
    EXPECT_NEAR(q.point.x(), 0.5, 1e-15);
}

TEST(ClosestPointOnTriangle, EdgeCases) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<double> u(-1, 1);
    const auto random_point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
    {
        SCOPED_TRACE("collinear corners, the middle one inside the segment");
        for (int trial = 0; trial < 100; ++trial) {
            const Vec3 a = random_point(), b = random_point();
            const double t = 0.5 * (u(rng) + 1);
            // c on the line through a and b (rounding may leave a tiny area: either way the answer
            // must be the segment's closest point).
            const Vec3 c = a + t * (b - a);
            expect_closest(1.5 * random_point(), a, b, c);
            expect_closest(1.5 * random_point(), c, a, b);
        }
    }
    {
        SCOPED_TRACE("exactly collinear on an axis");
        const Vec3 a(0, 0, 0), b(1, 0, 0), c(3, 0, 0);
        for (const Vec3& p : {Vec3(0.5, 1, 0), Vec3(2, -1, 2), Vec3(-1, 0, 0), Vec3(4, 0, 1)}) {
            const TriangleClosestPoint q = closest_point_on_triangle(p, a, b, c);
            const double x = std::clamp(p.x(), 0.0, 3.0);
            EXPECT_NEAR(std::sqrt(q.distance2), (p - Vec3(x, 0, 0)).norm(), 1e-15);
            EXPECT_NEAR(q.point.x(), x, 1e-15);
        }
    }
    {
        SCOPED_TRACE("a collapsed edge (two equal corners): the segment to the third");
        for (int trial = 0; trial < 100; ++trial) {
            const Vec3 a = random_point(), c = random_point(), p = 1.5 * random_point();
            expect_closest(p, a, a, c);
            expect_closest(p, a, c, a);
            expect_closest(p, c, a, a);
            // Against the segment in closed form.
            const double s = std::clamp((p - a).dot(c - a) / (c - a).squaredNorm(), 0.0, 1.0);
            EXPECT_NEAR(std::sqrt(closest_point_on_triangle(p, a, a, c).distance2), (p - (a + s * (c - a))).norm(), 1e-12);
        }
    }
    {
        SCOPED_TRACE("all three points equal: that point");
        const Vec3 a(0.25, -0.5, 2);
        for (const Vec3& p : {Vec3(1, 1, 1), a, Vec3(0.25, -0.5, 3)}) {
            const TriangleClosestPoint q = closest_point_on_triangle(p, a, a, a);
            EXPECT_EQ(q.point, a);
            EXPECT_EQ(q.distance2, (p - a).squaredNorm());
            EXPECT_DOUBLE_EQ(q.barycentric.sum(), 1.0);
        }
    }
    {
        SCOPED_TRACE("the query point on the triangle: distance zero");
        const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
        for (const Vec3& p : {a, b, c, Vec3(0.5, 0, 0), Vec3(0.25, 0.25, 0)}) EXPECT_EQ(closest_point_on_triangle(p, a, b, c).distance2, 0.0);
    }
}

TEST(ClosestPointOnTriangle, NamesTheFeatureThatHoldsThePoint) {
    using F = TriangleFeature;
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    const struct {
        Vec3 p;
        F feature;
        Vec3 point;
    } cases[] = {
        {Vec3(-1, -1, 1), F::vertex_a, a},          {Vec3(2, -0.5, 0), F::vertex_b, b},
        {Vec3(-0.5, 2, -1), F::vertex_c, c},        {Vec3(0.5, -1, 0), F::edge_ab, Vec3(0.5, 0, 0)},
        {Vec3(1, 1, 3), F::edge_bc, Vec3(0.5, 0.5, 0)}, {Vec3(-2, 0.25, 0), F::edge_ca, Vec3(0, 0.25, 0)},
        {Vec3(0.25, 0.5, -2), F::face, Vec3(0.25, 0.5, 0)},
    };
    for (const auto& k : cases) {
        const TriangleClosestPoint q = closest_point_on_triangle(k.p, a, b, c);
        EXPECT_EQ(q.feature, k.feature) << k.p.transpose();
        EXPECT_LT((q.point - k.point).norm(), 1e-15) << k.p.transpose();
        EXPECT_NEAR(q.distance2, (k.p - k.point).squaredNorm(), 1e-15);
    }
}

TEST(ClosestPointOnTriangle, EdgesOfAFlatTriangleTieToTheFirstEdge) {
    // Edges ab and bc of the collapsed triangle a == c are one segment: ab (the first) wins the tie.
    const Vec3 a(0, 0, 0), b(1, 0, 0);
    const TriangleClosestPoint q = closest_point_on_triangle_edges(Vec3(0.5, 1, 0), a, b, a);
    EXPECT_EQ(q.feature, TriangleFeature::edge_ab);
    EXPECT_EQ(q.barycentric, Vec3(0.5, 0.5, 0));
}

}  // namespace
}  // namespace cf
