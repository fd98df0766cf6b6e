// The crack-opening estimator (eq. 5.5-5.6) is the inverse of displacement correlation.
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/propagate/crack_front.hpp"
#include "nodes/propagate/fracture_step.hpp"
#include "nodes/propagate/opening_estimate.hpp"

#include <gtest/gtest.h>

using namespace cf;

// One triangle behind a front edge: an opening estimated from K at distance d, read back by
// displacement correlation at that distance, returns K (all three modes).
TEST(OpeningEstimate, DisplacementCorrelationReadsBackTheSifs) {
    SurfaceMesh m;
    const double d = 0.004;
    // Node 2 inside a ring 0-1-3-4: the only interior node, one d behind the edge (0, 1).
    m.vertices = {Vec3(0, -0.01, 0), Vec3(0, 0.01, 0), Vec3(-d, 0, 0), Vec3(-2 * d, 0.01, 0), Vec3(-2 * d, -0.01, 0)};
    m.triangles = {{0, 1, 2}, {1, 3, 2}, {3, 4, 2}, {4, 0, 2}};
    m.region.assign(4, 0);
    const double E = 3.1e9, nu = 0.327;
    std::vector<Vec3> opening(m.num_vertices(), Vec3::Zero());
    const auto records0 = bem::displacement_correlation_sifs(m, opening, E, nu);
    const bem::FrontEdgeSif* rec = nullptr;
    for (const auto& r : records0)
        if (r.v0 == 0 && r.v1 == 1) rec = &r;
    ASSERT_NE(rec, nullptr);
    ASSERT_EQ(rec->interior, 2);
    // The edge's SIFs in the propagation frame (n1 normal, n2 forward, n3 = -e3, K_III re-signed).
    const auto edge = propagate::to_edge_sifs({*rec}).front();
    const propagate::Sifs K{1.2e6, -0.4e6, 0.3e6};
    opening[2] = propagate::opening_from_sifs(K, edge.frame, rec->d, E, nu);
    const auto back = bem::displacement_correlation_sifs(m, opening, E, nu);
    for (const auto& r : back) {
        if (r.v0 != 0 || r.v1 != 1) continue;
        const auto e = propagate::to_edge_sifs({r}).front();
        EXPECT_NEAR(e.K.KI, K.KI, 1e-6 * K.KI);
        EXPECT_NEAR(e.K.KII, K.KII, 1e-6 * K.KI);
        EXPECT_NEAR(e.K.KIII, K.KIII, 1e-6 * K.KI);
    }
}

// Nodes that stay on the front get nothing; nodes left behind get the distance to the new front.
TEST(OpeningEstimate, OnlyNodesLeftBehindGetOpenings) {
    SurfaceMesh m;
    m.vertices = {Vec3(0, 0, 0), Vec3(0, 1e-2, 0), Vec3(5e-3, 0, 0), Vec3(5e-3, 1e-2, 0)};
    propagate::CrackFront old_front, new_front;
    old_front.nodes = {0, 1};
    old_front.closed = false;
    old_front.sifs = {{1e6, 0, 0}, {1e6, 0, 0}};
    old_front.frames = {propagate::FrontFrame{}, propagate::FrontFrame{}};  // n1 = z, n2 = x
    new_front.nodes = {2, 3, 1};
    new_front.closed = false;
    bem::CrackOpeningEstimate est;
    const std::size_t n = propagate::estimate_openings_left_behind(m, old_front, new_front, 3.1e9, 0.327, est);
    EXPECT_EQ(n, 1u);
    EXPECT_TRUE(est.known[0]);
    EXPECT_FALSE(est.known[1]);  // still on the front
    const propagate::Sifs K{1e6, 0, 0};
    const Vec3 expect = propagate::opening_from_sifs(K, propagate::FrontFrame{}, 5e-3, 3.1e9, 0.327);
    EXPECT_NEAR((est.opening[0] - expect).norm(), 0, 1e-15);
    EXPECT_GT(est.opening[0].z(), 0);  // opens along the normal under K_I > 0
}
