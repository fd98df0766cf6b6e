// User-given initial cracks (thesis App. A item 12): a penny crack inside a cube and an edge
// crack on its side face, against closed-form areas and distances.
#include "initiation_fixtures.hpp"
#include "nodes/initiate/user_crack.hpp"
#include "nodes/propagate/crack_front.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace cf::initiate {
namespace {

using testing::box_distance;

constexpr double L = 1.0;

ObjectDistance box() {
    return [](const Vec3& p) { return box_distance(p, L / 2); };
}

struct SheetTopology {
    int interior_nodes = 0;
    int boundary_loops = 0;
    bool manifold = true;
    int euler = 0;
};

SheetTopology topology(const SurfaceMesh& m) {
    std::map<std::pair<int, int>, int> edges;
    for (const Tri& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    SheetTopology out;
    std::set<int> boundary;
    for (const auto& [e, n] : edges) {
        if (n > 2) out.manifold = false;
        if (n == 1) boundary.insert(e.first), boundary.insert(e.second);
    }
    out.interior_nodes = static_cast<int>(m.num_vertices() - boundary.size());
    out.euler = static_cast<int>(m.num_vertices()) - static_cast<int>(edges.size()) + static_cast<int>(m.num_triangles());
    out.boundary_loops = static_cast<int>(propagate::extract_fronts(m).size());  // throws if not simple loops
    return out;
}

void expect_planar_disk_sheet(const UserCrack& c, const Vec3& centre, const Vec3& n, double r_c) {
    const SheetTopology t = topology(c.sheet);
    EXPECT_TRUE(t.manifold);
    EXPECT_EQ(t.euler, 1);  // a disk
    EXPECT_EQ(t.boundary_loops, 1);
    EXPECT_GE(t.interior_nodes, 1);
    double longest = 0;
    for (std::size_t k = 0; k < c.sheet.num_triangles(); ++k) {
        EXPECT_GT(triangle_normal(c.sheet, k).dot(n), 1 - 1e-9) << "triangle " << k << " not oriented with +normal";
        const Tri& tr = c.sheet.triangles[k];
        for (int e = 0; e < 3; ++e)
            longest = std::max(longest, (c.sheet.vertices[tr[e]] - c.sheet.vertices[tr[(e + 1) % 3]]).norm());
    }
    for (const Vec3& v : c.sheet.vertices) EXPECT_LT(std::abs((v - centre).dot(n)), 1e-12);
    EXPECT_LE(longest, max_sheet_edge_factor * r_c * (1 + 1e-9));  // size criterion of the mesher
    double sum = 0;
    int count = 0;
    for (const Tri& tr : c.sheet.triangles)
        for (int e = 0; e < 3; ++e) sum += (c.sheet.vertices[tr[e]] - c.sheet.vertices[tr[(e + 1) % 3]]).norm(), ++count;
    std::cout << "mean edge / r_c = " << sum / count / r_c << ", longest / r_c = " << longest / r_c << "\n";
    EXPECT_GT(sum / count, 0.75 * r_c);  // edges ~r_c, not a needlessly fine sheet
    EXPECT_LT(sum / count, 1.1 * r_c);
}

TEST(UserCrack, PennyCrackInsideACube) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const double r_c = 0.05, r_f = 0.01, R = 0.3;
    UserCrackSpec spec;
    spec.centre = Vec3(0.05, -0.02, 0.03);
    spec.normal = Vec3(1, 2, 2);  // |n| = 3
    spec.radius = R;
    const UserCrack c = build_user_crack(spec, cube, box(), r_c, r_f);
    const Vec3 n = spec.normal / 3;
    expect_planar_disk_sheet(c, spec.centre, n, r_c);
    EXPECT_LT((c.plane_normal - n).norm(), 1e-15);
    EXPECT_DOUBLE_EQ(c.margin, 0.01);
    EXPECT_LT((c.inner_point - spec.centre).norm(), 1e-15);  // the centre is deep inside
    // Unclipped (the disk is 0.16 m clear of the faces): the area is pi R^2 up to the inscribed
    // rim polygon with chords ~r_c/2.
    const double area = surface_area(c.sheet);
    std::cout << "penny: " << c.sheet.num_triangles() << " triangles, " << c.sheet.num_vertices() << " vertices, area / pi R^2 = "
              << area / (M_PI * R * R) << "\n";
    EXPECT_NEAR(area / (M_PI * R * R), 1, 0.01);
    for (const Vec3& v : c.sheet.vertices) {
        EXPECT_LE((v - spec.centre).norm(), R * (1 + 1e-12));
        EXPECT_LE(box_distance(v, L / 2), -c.margin);
    }
    // The recorded fan covers the disk: area pi R^2 within its chord error.
    double rec = 0;
    for (const Triangle3& t : c.recorded) rec += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
    EXPECT_NEAR(rec / (M_PI * R * R), 1, 2e-3);
}

TEST(UserCrack, EdgeCrackOnASideFaceStaysInsideByTheMargin) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const double r_c = 0.05, r_f = 0.01, R = 0.3;
    UserCrackSpec spec;
    spec.centre = Vec3(-L / 2, 0.05, 0.1);  // on the face x = -L/2
    spec.normal = Vec3(0, 0, 1);
    spec.front_direction = Vec3(1, 0, 0.7);  // projected into the plane: +x, into the body
    spec.radius = R;
    const UserCrack c = build_user_crack(spec, cube, box(), r_c, r_f);
    expect_planar_disk_sheet(c, spec.centre, Vec3::UnitZ(), r_c);
    EXPECT_TRUE(c.half);
    EXPECT_LT((c.t1 - Vec3::UnitX()).norm(), 1e-15);
    const double m = c.margin;
    // Region: half-disk x >= -L/2 cut at x = -L/2 + m: area R^2 acos(m/R) - m sqrt(R^2 - m^2).
    const double exact = R * R * std::acos(m / R) - m * std::sqrt(R * R - m * m);
    const double area = surface_area(c.sheet);
    std::cout << "edge crack: " << c.sheet.num_triangles() << " triangles, area / exact = " << area / exact
              << " (half-disk pi R^2/2 = " << M_PI * R * R / 2 << ", clipped " << exact << ")\n";
    EXPECT_NEAR(area / exact, 1, 0.01);
    double min_x = 1;
    for (const Vec3& v : c.sheet.vertices) {
        EXPECT_LE(box_distance(v, L / 2), -m * (1 - 1e-9));
        EXPECT_LE((v - spec.centre).norm(), R * (1 + 1e-12));
        min_x = std::min(min_x, v.x());
    }
    EXPECT_LT(min_x, -L / 2 + m + 1e-6);  // the clipped edge follows the margin line
    // The recorded half-disk reaches the face: its straight edge lies on x = -L/2.
    double rec = 0, rec_min_x = 1;
    for (const Triangle3& t : c.recorded) {
        rec += 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
        for (const Vec3& p : t) rec_min_x = std::min(rec_min_x, p.x());
    }
    EXPECT_NEAR(rec / (M_PI * R * R / 2), 1, 2e-3);
    EXPECT_NEAR(rec_min_x, -L / 2, 1e-15);

    // The BEM accepts the sheet (no triangle touches the surface) and, pulled along its normal,
    // the crack opens (+z) at every interior node.
    const auto sol = testing::solve_uniaxial(cube, 1e6, &c.sheet);
    const std::vector<char> interior = bem::crack_interior_nodes(c.sheet);
    double min_opening = 1;
    for (std::size_t v = 0; v < interior.size(); ++v)
        if (interior[v]) min_opening = std::min(min_opening, sol->crack_opening[v].z());
    std::cout << "edge crack under 1 MPa: min interior opening " << min_opening << " m\n";
    EXPECT_GT(min_opening, 0);
}

TEST(UserCrack, BadParametersNameTheParameterAndTheFix) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, L);
    const double r_c = 0.05, r_f = 0.01;
    auto message = [&](UserCrackSpec s) {
        try {
            build_user_crack(s, cube, box(), r_c, r_f);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    UserCrackSpec ok;
    ok.centre = Vec3(0, 0, 0);
    ok.normal = Vec3(0, 0, 1);
    ok.radius = 0.2;
    UserCrackSpec s = ok;
    s.normal = Vec3::Zero();
    EXPECT_NE(message(s).find("parameter 'normal' (0 0 0) is zero"), std::string::npos) << message(s);
    s = ok;
    s.front_direction = Vec3(0, 0, -2);
    EXPECT_NE(message(s).find("parameter 'front_direction' (0 0 -2) is parallel to 'normal'"), std::string::npos) << message(s);
    s = ok;
    s.centre = Vec3(2, 0, 0);
    EXPECT_NE(message(s).find("lies outside the object"), std::string::npos) << message(s);
    s = ok;
    s.radius = 0.02;  // full disk: minimum r_c / 2 = 0.025 m
    EXPECT_NE(message(s).find("parameter 'radius' (0.02 m) is too small"), std::string::npos) << message(s);
    EXPECT_NE(message(s).find("radius >= 0.025 m"), std::string::npos) << message(s);
    s.centre = Vec3(-L / 2, 0, 0);
    s.front_direction = Vec3(1, 0, 0);
    s.radius = 0.06;  // edge crack: minimum r_c + 2 max(r_f, 0.05 r_c) = 0.07 m
    EXPECT_NE(message(s).find("radius >= 0.07 m for an edge crack"), std::string::npos) << message(s);
    // A full disk near a face is clipped into a sliver: too close to the surface.
    s = ok;
    s.centre = Vec3(0, 0, 0.49);
    s.normal = Vec3(1, 0, 0);
    s.radius = 0.2;
    EXPECT_NE(message(s).find("too close to the object's surface"), std::string::npos) << message(s);
    EXPECT_EQ(message(ok), "no error");
}

}  // namespace
}  // namespace cf::initiate
