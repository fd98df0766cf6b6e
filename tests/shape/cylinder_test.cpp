// Cylinder: the mesh is exactly the inscribed regular prism.
#include "nodes/shape/cylinder.hpp"
#include "tests/shape/mesh_checks.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf {
namespace {

using testing::expect_closed_outward;
using testing::region_area;
using testing::region_triangles;

const double pi = std::acos(-1.0);

void expect_prism(const CylinderSpec& s, std::size_t cap_triangles) {
    const SurfaceMesh m = make_cylinder(s);
    expect_closed_outward(m, 2);
    const double n = s.segments, r = s.radius, h = s.height;
    const double polygon = 0.5 * n * r * r * std::sin(2 * pi / n);  // inscribed regular n-gon
    const double side = n * 2 * r * std::sin(pi / n) * h;
    EXPECT_NEAR(signed_volume(m), polygon * h, 1e-13 * polygon * h);
    EXPECT_NEAR(region_area(m, "side"), side, 1e-13 * side);
    EXPECT_NEAR(region_area(m, "top"), polygon, 1e-13 * polygon);
    EXPECT_NEAR(region_area(m, "bottom"), polygon, 1e-13 * polygon);
    EXPECT_EQ(region_triangles(m, "side"), 2u * s.segments * s.rings);
    EXPECT_EQ(region_triangles(m, "top"), cap_triangles);
    EXPECT_EQ(region_triangles(m, "bottom"), cap_triangles);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const Vec3 nrm = triangle_normal(m, t), c = triangle_centroid(m, t) - s.centre;
        switch (m.region_of(t)) {
            case 0:  // side: horizontal, pointing away from the axis
                EXPECT_NEAR(nrm.z(), 0, 1e-14);
                EXPECT_GT(nrm.x() * c.x() + nrm.y() * c.y(), 0);
                break;
            case 1: EXPECT_TRUE(nrm.isApprox(Vec3(0, 0, 1), 1e-14)); EXPECT_NEAR(c.z(), 0.5 * h, 1e-14); break;
            case 2: EXPECT_TRUE(nrm.isApprox(Vec3(0, 0, -1), 1e-14)); EXPECT_NEAR(c.z(), -0.5 * h, 1e-14); break;
            default: ADD_FAILURE() << "region " << m.region_of(t);
        }
    }
}

TEST(Cylinder, FanCapsGiveTheInscribedPrismExactly) {
    CylinderSpec s;
    s.radius = 0.3;
    s.height = 1.7;
    s.centre = Vec3(0.1, 0.2, -0.4);
    s.segments = 7;
    s.rings = 3;
    s.caps = CapStyle::Fan;
    expect_prism(s, 7);
}

TEST(Cylinder, RingCapsGiveTheSamePrism) {
    CylinderSpec s;
    s.radius = 2;
    s.height = 0.5;
    s.segments = 24;
    s.rings = 1;
    s.caps = CapStyle::Rings;
    s.cap_rings = 4;
    expect_prism(s, 24u * (2 * 4 - 1));
}

TEST(Cylinder, ConvergesToTheCircularCylinderAsSegmentsGrow) {
    CylinderSpec s;
    s.segments = 400;
    const SurfaceMesh m = make_cylinder(s);
    const double exact = pi * 0.25 * 1.0;
    // Inscribed n-gon area / circle area = sin(2 pi/n) / (2 pi/n) = 1 - (2 pi/n)^2/6 + ...
    EXPECT_LT(signed_volume(m), exact);
    EXPECT_NEAR(signed_volume(m) / exact, 1 - std::pow(2 * pi / 400, 2) / 6, 1e-9);
}

TEST(Cylinder, BadSpecsAreRejected) {
    CylinderSpec s;
    s.segments = 2;
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { make_cylinder(s); }, {"parameter 'segments' must be >= 3, got 2"}));
    s.segments = 20000;
    s.rings = 20000;
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { make_cylinder(s); },
        {"segments, rings and cap_rings would make 800040000 triangles (limit 4000000); reduce them"}));
}

}  // namespace
}  // namespace cf
