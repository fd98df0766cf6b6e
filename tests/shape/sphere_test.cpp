// Icosphere: counts, vertices on the sphere, inscribed-polyhedron bounds, O(h^2) convergence.
#include "nodes/shape/icosphere.hpp"
#include "tests/shape/mesh_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

using testing::expect_closed_outward;

const double pi = std::acos(-1.0);

// Distance from the centre to the nearest face plane, after checking the polyhedron is convex
// (every vertex on the inner side of every face plane), so it contains the ball of that radius.
double inradius_of_convex(const SurfaceMesh& m, const Vec3& c) {
    double r_in = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Vec3 n = triangle_normal(m, t);
        const Vec3& a = m.vertices[m.triangles[t][0]];
        for (const Vec3& p : m.vertices) EXPECT_LE(n.dot(p - a), 1e-12) << "not convex at triangle " << t;
        r_in = std::min(r_in, n.dot(a - c));
    }
    return r_in;
}

TEST(Icosphere, CountsAndVerticesOnTheSphere) {
    for (int k = 0; k <= 4; ++k) {
        const SphereSpec s{0.7, Vec3(1, -2, 0.5), k, SphereProjection::PerLevel};
        const SurfaceMesh m = make_icosphere(s);
        EXPECT_EQ(m.num_triangles(), icosphere_triangle_count(k));
        EXPECT_EQ(m.num_triangles(), 20u << (2 * k));
        EXPECT_EQ(m.num_vertices(), 10u * (1u << (2 * k)) + 2);
        expect_closed_outward(m, 2);
        for (const Vec3& p : m.vertices) EXPECT_NEAR((p - s.centre).norm(), 0.7, 1e-15);
        EXPECT_EQ(m.region_names, std::vector<std::string>{"surface"});
    }
}

TEST(Icosphere, VolumeAndAreaBoundedByInscribedPolyhedronAndConvergeQuadratically) {
    const double r = 0.5, exact_v = 4.0 / 3.0 * pi * r * r * r, exact_a = 4 * pi * r * r;
    std::vector<double> err_v, err_a;
    for (int k = 0; k <= 6; ++k) {
        const SurfaceMesh m = make_icosphere(SphereSpec{r, Vec3::Zero(), k, SphereProjection::PerLevel});
        const double v = signed_volume(m), a = surface_area(m);
        // Inscribed: below the sphere; convex and containing the ball of its inradius: above that.
        EXPECT_LT(v, exact_v);
        EXPECT_LT(a, exact_a);
        if (k <= 3) {
            const double r_in = inradius_of_convex(m, Vec3::Zero());
            EXPECT_GT(v, 4.0 / 3.0 * pi * r_in * r_in * r_in);
            EXPECT_GT(a, 4 * pi * r_in * r_in);
        }
        err_v.push_back((exact_v - v) / exact_v);
        err_a.push_back((exact_a - a) / exact_a);
    }
    // Level 0 is the regular icosahedron: circumradius r = a sqrt(10 + 2 sqrt 5) / 4, V = 5/12 (3 + sqrt 5) a^3.
    const double edge = 4 * r / std::sqrt(10 + 2 * std::sqrt(5.0));
    EXPECT_NEAR(err_v[0], 1 - 5.0 / 12.0 * (3 + std::sqrt(5.0)) * edge * edge * edge / exact_v, 1e-14);
    // Halving the edge length quarters the error (O(h^2)) once the mesh resolves the sphere.
    // Halving the edge length quarters the error (O(h^2)): the ratio of successive errors tends
    // to 4, and its distance from 4 (the O(h^4) term) itself shrinks about fourfold per level.
    for (int k = 4; k <= 6; ++k) {
        EXPECT_NEAR(err_v[k - 1] / err_v[k], 4.0, 0.02) << k;
        EXPECT_NEAR(err_a[k - 1] / err_a[k], 4.0, 0.02) << k;
    }
    for (int k = 3; k <= 5; ++k) {
        const double now = 4 - err_v[k - 1] / err_v[k], next = 4 - err_v[k] / err_v[k + 1];
        EXPECT_GT(now, 0) << k;
        EXPECT_GT(now / next, 3.5) << k;
    }
    EXPECT_LT(err_v[6], 2e-4);
}

TEST(Icosphere, NearestLevelForATargetCount) {
    EXPECT_EQ(icosphere_level_for(1), 0);
    EXPECT_EQ(icosphere_level_for(49), 0);
    EXPECT_EQ(icosphere_level_for(50), 0);  // tie between 20 and 80: the smaller mesh
    EXPECT_EQ(icosphere_level_for(51), 1);
    EXPECT_EQ(icosphere_level_for(300), 2);
    EXPECT_EQ(icosphere_level_for(1000), 3);
    EXPECT_EQ(icosphere_level_for(1e12), max_icosphere_level);
}

TEST(Icosphere, ProjectionsDifferAndPerLevelIsMoreUniform) {
    auto area_ratio = [](const SurfaceMesh& m) {
        double lo = 1e300, hi = 0;
        for (std::size_t t = 0; t < m.num_triangles(); ++t) {
            lo = std::min(lo, triangle_area(m, t));
            hi = std::max(hi, triangle_area(m, t));
        }
        return hi / lo;
    };
    const SurfaceMesh per_level = make_icosphere(SphereSpec{1, Vec3::Zero(), 4, SphereProjection::PerLevel});
    const SurfaceMesh once = make_icosphere(SphereSpec{1, Vec3::Zero(), 4, SphereProjection::Once});
    expect_closed_outward(once, 2);
    for (const Vec3& p : once.vertices) EXPECT_NEAR(p.norm(), 1, 1e-15);
    double largest_shift = 0;  // same vertex numbering, different positions
    for (std::size_t i = 0; i < once.num_vertices(); ++i)
        largest_shift = std::max(largest_shift, (per_level.vertices[i] - once.vertices[i]).norm());
    EXPECT_GT(largest_shift, 1e-2);
    EXPECT_LT(area_ratio(per_level), area_ratio(once));
    // Level 1 splits only once, so both projections coincide there.
    const SurfaceMesh a = make_icosphere(SphereSpec{1, Vec3::Zero(), 1, SphereProjection::PerLevel});
    const SurfaceMesh b = make_icosphere(SphereSpec{1, Vec3::Zero(), 1, SphereProjection::Once});
    for (std::size_t i = 0; i < a.num_vertices(); ++i) EXPECT_TRUE(a.vertices[i].isApprox(b.vertices[i], 1e-15));
}

TEST(Icosphere, BadSpecsAreRejected) {
    EXPECT_THROW(make_icosphere(SphereSpec{0, Vec3::Zero(), 1, SphereProjection::PerLevel}), std::invalid_argument);
    EXPECT_THROW(make_icosphere(SphereSpec{1, Vec3::Zero(), 9, SphereProjection::PerLevel}), std::invalid_argument);
}

}  // namespace
}  // namespace cf
