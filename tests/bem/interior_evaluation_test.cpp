// Interior displacement and stress by the representation formula (eq. 2.20, 2.23) and the crack's
// average displacement (ch. 6.4), against closed-form fields and symmetry.
#include "nodes/bem/bem_verification.hpp"
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>

using namespace cf;
using namespace cf::bem;

namespace {

Material unit_material() {
    Material m;
    m.E = 1;
    m.nu = 0.3;
    return m;
}

// Uniaxial tension sigma_zz = 1 (E = 1, nu = 0.3): u = (-nu x, -nu y, z).
Vec3 uniaxial_u(const Vec3& x) { return Vec3(-0.3 * x.x(), -0.3 * x.y(), x.z()); }
Mat3 uniaxial_stress() {
    Mat3 s = Mat3::Zero();
    s(2, 2) = 1;
    return s;
}

// A solution holding the exact boundary data of the uniaxial field on the unit cube (no solve), so
// that only the interior quadrature is measured.
std::shared_ptr<BemSolution> exact_cube_data(int m) {
    AssemblyOptions opt;
    opt.single_layer = false;
    auto sol = std::make_shared<BemSolution>();
    // Operators are needed only for geometry and constants; a 1-element-per-face cube keeps this cheap.
    sol->surface = assemble_surface_operators(bem_cube_mesh(m, 1.0), unit_material(), opt);
    for (const Vec3& x : sol->surface->mesh.vertices) sol->displacement.push_back(uniaxial_u(x));
    for (const auto& g : sol->surface->geometry) sol->traction.push_back(uniaxial_stress() * g.normal);
    return sol;
}

std::shared_ptr<const BemSolution> solved_cube_tension(int m) {
    AssemblyOptions opt;
    opt.single_layer = false;
    const auto o = assemble_surface_operators(bem_cube_mesh(m, 1.0), unit_material(), opt);
    const auto bc = resolve(parse_boundary_conditions("z_max: traction 0 0 1; z_min: traction 0 0 -1; *: traction 0 0 0"), o->mesh);
    return solve_sgbem(o, nullptr, bc, {}, nullptr);
}

double max_abs(const Mat3& a) { return a.cwiseAbs().maxCoeff(); }

}  // namespace

// With exact P1/P0 data of a linear field the representation formula is exact, so what remains is
// the adaptive quadrature error, also very close to the surface (h = 1/3 here).
TEST(BemInterior, ExactLinearDataDownToTinyDistances) {
    const auto sol = exact_cube_data(3);
    std::vector<Vec3> pts;
    for (double d : {0.25, 0.1, 1e-2, 1e-3, 1e-4}) {
        pts.push_back(Vec3(0.1, -0.2, 0.5 - d));        // below the top face, inside an element
        pts.push_back(Vec3(0.5 - d, 0.5 - d, 0.0));     // near a cube edge
        pts.push_back(Vec3(-0.5 + d, 0.5 - d, -0.5 + d));  // near a corner
        pts.push_back(Vec3(1.0 / 6, 0.5 - d, 0.1));     // under a mesh edge of the y_max face
    }
    const auto u = interior_displacement(*sol, pts);
    const auto s = interior_stress(*sol, pts);
    double eu = 0, es = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        eu = std::max(eu, (u[i] - uniaxial_u(pts[i])).norm());
        es = std::max(es, max_abs(s[i] - uniaxial_stress()));
    }
    std::cout << "exact data, distances 0.25 .. 1e-4: max |u error| " << eu << ", max stress error " << es << "\n";
    EXPECT_LT(eu, 1e-6);  // |u| is up to 0.5
    EXPECT_LT(es, 1e-5);  // sigma_zz = 1
}

// The stress is built from analytic kernel derivatives: compare with central differences of u.
TEST(BemInterior, GradientMatchesFiniteDifferencesOfDisplacement) {
    const auto sol = solved_cube_tension(2);
    // A generic (non-linear) field: perturb the data with a quadratic so that grad u varies.
    auto data = std::make_shared<BemSolution>(*sol);
    for (std::size_t v = 0; v < data->displacement.size(); ++v) {
        const Vec3 x = data->surface->mesh.vertices[v];
        data->displacement[v] += Vec3(x.y() * x.z(), x.x() * x.x(), 0.5 * x.x() * x.y());
    }
    for (std::size_t e = 0; e < data->traction.size(); ++e) data->traction[e] += 0.3 * data->surface->geometry[e].centroid;
    const Vec3 x0(0.11, -0.07, 0.23);
    // A fine rule everywhere (every leaf at distance >= 20 sizes), so that switching rules between
    // the stencil points does not show up in the differences.
    InteriorQuadrature fine;
    fine.leaf_ratio = 20;
    const Mat3 G = interior_displacement_gradient(*data, {x0}, true, fine)[0];
    const double h = 1e-3;
    Mat3 fd;
    for (int l = 0; l < 3; ++l) {
        Vec3 e = Vec3::Zero();
        e[l] = h;
        const auto u = interior_displacement(*data, {x0 + e, x0 - e, x0 + 2 * e, x0 - 2 * e}, true, fine);
        fd.col(l) = (8 * (u[0] - u[1]) - (u[2] - u[3])) / (12 * h);  // fourth order
    }
    std::cout << "grad u vs central differences: " << max_abs(G - fd) << " (|G| " << max_abs(G) << ")\n";
    EXPECT_LT(max_abs(G - fd), 1e-6 * max_abs(G));
}

// Cube patch test with the solved data (pure Neumann, eq. 7.4; 108 triangles, h = 1/3).
TEST(BemInterior, CubePatchTestFromSolvedData) {
    const auto sol = solved_cube_tension(3);
    std::vector<Vec3> pts;
    const double d = 0.05;  // distance to the nearest face: 0.15 h
    for (double x : {-0.5 + d, 0.0, 0.5 - d})
        for (double y : {-0.5 + d, 0.13, 0.5 - d})
            for (double z : {-0.5 + d, -0.21, 0.5 - d}) pts.push_back(Vec3(x, y, z));
    const auto u = interior_displacement(*sol, pts);
    const auto s = interior_stress(*sol, pts);
    double eu = 0, es = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        eu = std::max(eu, (u[i] - uniaxial_u(pts[i])).norm() / 0.5);
        es = std::max(es, max_abs(s[i] - uniaxial_stress()));
    }
    std::cout << "cube patch, points >= 0.05 from the surface: rel. u error " << eu << ", stress error " << es << "\n";
    EXPECT_LT(eu, 1e-3);
    EXPECT_LT(es, 1e-3);
}

// Sphere R = 1 under face-normal traction 1: hydrostatic stress I and u = 0.4 x everywhere inside
// (faceted patch test, sgbem-math §4). Points up to r = 0.9 (the facets are at r >= 0.95).
TEST(BemInterior, SphereRadialTractionUniformStress) {
    const SurfaceMesh m = bem_icosphere_mesh(2, 1.0);
    AssemblyOptions opt;
    opt.single_layer = false;
    const auto o = assemble_surface_operators(m, unit_material(), opt);
    BoundaryConditions b = parse_boundary_conditions("*: traction 0 0 0");
    for (std::size_t a = 0; a < m.num_triangles(); ++a) b.element_tractions.push_back(triangle_normal(m, a));
    const auto sol = solve_sgbem(o, nullptr, resolve(b, m), {}, nullptr);
    std::vector<Vec3> pts = {Vec3::Zero()};
    for (double r : {0.3, 0.6, 0.9}) {
        pts.push_back(r * Vec3(1, 0, 0));
        pts.push_back(r * Vec3(0.3, -0.5, 0.81).normalized());
        pts.push_back(r * Vec3(-0.7, 0.7, -0.1).normalized());
    }
    const auto u = interior_displacement(*sol, pts);
    const auto s = interior_stress(*sol, pts);
    double eu = 0, es = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        eu = std::max(eu, (u[i] - 0.4 * pts[i]).norm() / 0.4);
        es = std::max(es, max_abs(s[i] - Mat3::Identity()));
    }
    std::cout << "sphere: rel. u error " << eu << ", stress error " << es << "\n";
    EXPECT_LT(eu, 1e-3);
    EXPECT_LT(es, 1e-3);
}

// Penny crack (radius 1) at the centre of a cube [-5,5]^3 under remote tension along z. The set-up is
// symmetric under z -> -z, so the crack's average displacement has no normal component on the crack
// plane; the representation formula including the crack term jumps across the sheet by the opening.
TEST(BemInterior, PennyCrackAverageDisplacementAndJump) {
    const PennyRun run = run_penny_crack(5, 3);
    const BemSolution& sol = *run.solution;
    const auto uc = crack_average_displacement(sol);
    const SurfaceMesh& crack = sol.cracks->cracks;
    ASSERT_EQ(uc.size(), crack.num_vertices());
    double cod_max = 0, uc_n = 0;
    for (std::size_t v = 0; v < uc.size(); ++v) {
        cod_max = std::max(cod_max, sol.crack_opening[v].norm());
        uc_n = std::max(uc_n, std::abs(uc[v].z()));
    }
    // The in-plane part is the far-field Poisson contraction -nu eps x: at most 0.3 * 1 * 1 here.
    double uc_t = 0;
    for (std::size_t v = 0; v < uc.size(); ++v)
        uc_t = std::max(uc_t, (uc[v].head<2>() + 0.3 * crack.vertices[v].head<2>()).norm());
    std::cout << "penny: max COD " << cod_max << ", max |u_c . n| " << uc_n << ", centre u_c " << uc[0].transpose()
              << ", max in-plane deviation from -nu x " << uc_t << "\n";
    EXPECT_LT(uc_n, 1e-4 * cod_max);
    EXPECT_LT(uc[0].norm(), 1e-4 * cod_max);
    // Jump across the sheet at crack nodes (the opening is P1, so compare with nodal values).
    double ejump = 0, eavg = 0;
    for (std::size_t v = 0; v < crack.num_vertices(); ++v) {
        if (crack.vertices[v].head<2>().norm() > 0.8) continue;
        const Vec3 x = crack.vertices[v];
        const double eps = 1e-4;
        const auto u = interior_displacement(sol, {x + Vec3(0, 0, eps), x - Vec3(0, 0, eps)});
        ejump = std::max(ejump, (u[0] - u[1] - sol.crack_opening[v]).norm());
        eavg = std::max(eavg, std::abs(0.5 * (u[0] + u[1]).z() - uc[v].z()));
    }
    std::cout << "penny: max |u(+eps) - u(-eps) - [u]| " << ejump << ", max |normal average - u_c . n| " << eavg << "\n";
    EXPECT_LT(ejump, 1e-3 * cod_max);
    EXPECT_LT(eavg, 1e-3 * cod_max);
}

// The gradient's kernel terms four rule points at a time give the one-at-a-time sums to the bit:
// a solved penny crack in a cube (surface tractions and displacements, crack openings), points far
// from and close to the surface and the sheet (every leaf rule: 6 points, 4 x 4 and 6 x 6, so full
// and partial batches of four, and deep subdivision), with and without the crack term.
TEST(BemInterior, GradientFourPointsAtATimeIsThePointByPointSum) {
    const PennyRun run = run_penny_crack(5, 3);
    const BemSolution& sol = *run.solution;
    std::vector<Vec3> points;
    for (int i = 0; i < 40; ++i) {
        const double t = (i + 0.5) / 40;
        points.emplace_back(0.9 * std::cos(7 * t) * t, 0.8 * std::sin(5 * t) * t, 0.02 + 0.9 * (t - 0.5));  // through the body
    }
    // Near a face of the cube and near the sheet (the sheet is z = 0 inside radius 1).
    const double face = sol.surface->mesh.vertices[0].cwiseAbs().maxCoeff();
    for (const double gap : {1e-1, 1e-2, 1e-3, 1e-4}) {
        points.emplace_back(0.3, -0.2, face - gap);
        points.emplace_back(0.25, 0.1, gap);
    }
    for (const bool cracks : {true, false}) {
        InteriorQuadrature one;
        one.four_points_at_a_time = false;
        const std::vector<Mat3> want = interior_displacement_gradient(sol, points, cracks, one);
        const std::vector<Mat3> got = interior_displacement_gradient(sol, points, cracks);
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t i = 0; i < got.size(); ++i)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    EXPECT_EQ(std::memcmp(&got[i](r, c), &want[i](r, c), sizeof(double)), 0)
                        << "point " << points[i].transpose() << " (" << r << ", " << c << "): " << got[i](r, c) << " vs "
                        << want[i](r, c) << (cracks ? ", with" : ", without") << " the crack term";
        double largest = 0;
        for (const Mat3& g : want) largest = std::max(largest, max_abs(g));
        EXPECT_GT(largest, 0);
    }
}

TEST(BemInterior, PointsOnSheetsOrSurfaceAreRejectedOrTraced) {
    const auto sol = exact_cube_data(1);
    // A point on the surface gets the boundary trace (exact here: the field is linear).
    const Vec3 p(0.2, -0.1, 0.5);
    EXPECT_LT((interior_displacement(*sol, {p})[0] - uniaxial_u(p)).norm(), 1e-14);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { interior_stress(*sol, {p}); },
        {"lies on the surface"}));
}

// Degenerate queries, one scope each: no points, points on the surface's vertices and edges,
// crack terms requested from a solution without cracks, a point outside the body, and arrays
// that do not match the mesh.
TEST(BemInterior, EdgeCases) {
    const auto sol = exact_cube_data(2);
    {
        SCOPED_TRACE("no points: empty results");
        EXPECT_TRUE(interior_displacement(*sol, {}).empty());
        EXPECT_TRUE(interior_displacement_gradient(*sol, {}).empty());
        EXPECT_TRUE(interior_stress(*sol, {}).empty());
    }
    {
        SCOPED_TRACE("points on a surface vertex, an edge and a corner get the boundary trace");
        for (const Vec3& p : {Vec3(0, 0, 0.5), Vec3(0.25, 0.5, 0.5), Vec3(0.5, 0.5, 0.5), Vec3(-0.5, -0.5, -0.5)})
            EXPECT_LT((interior_displacement(*sol, {p})[0] - uniaxial_u(p)).norm(), 1e-14) << p.transpose();
    }
    {
        SCOPED_TRACE("crack terms requested from a solution without cracks change nothing");
        const std::vector<Vec3> pts = {Vec3(0.1, 0.2, 0.3), Vec3(-0.3, 0.05, -0.2)};
        const auto with = interior_displacement(*sol, pts, true), without = interior_displacement(*sol, pts, false);
        for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(with[i], without[i]);
        const auto s_with = interior_stress(*sol, pts, true), s_without = interior_stress(*sol, pts, false);
        for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(s_with[i], s_without[i]);
    }
    {
        SCOPED_TRACE("a point outside the body: the representation formula of exact data gives zero");
        for (const Vec3& p : {Vec3(1.5, 0.2, 0.1), Vec3(0, 0, -2)}) {
            const Vec3 u = interior_displacement(*sol, {p})[0];
            std::cout << "outside " << p.transpose() << ": |u| " << u.norm() << "\n";
            EXPECT_LT(u.norm(), 1e-9) << p.transpose();  // measured 1.8e-11 and 1.6e-14
        }
    }
    {
        SCOPED_TRACE("arrays that do not match the mesh are refused");
        BemSolution broken = *sol;
        broken.displacement.pop_back();
        EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { interior_displacement(broken, {Vec3::Zero()}); },
                                                               {"do not match its surface mesh"}));
    }
}
