// Touching pairs across sharp folds take higher-order Sauter-Schwab rules (QuadratureSettings::
// fold_angle, fold_order). The truth: a patch test on the thesis' notched bar, whose V notch folds the
// surface at 19 degrees. Uniaxial tension along the notch (y) is a uniform stress whose traction
// sigma n_y e_y vanishes on the notch faces (their normals have no y part), so u = eps x exactly.
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/operators.hpp"
#include "nodes/bem/pair_integrals.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/shape/notched_bar.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace cf::bem {
namespace {

struct PatchResult {
    double u_error = 0;     // relative L2 error of the nodal displacements (their mean translation removed)
    double k_residual = 0;  // K's worst rigid-motion row before its correction
};

PatchResult notched_bar_tension(const QuadratureSettings& q) {
    NotchedBarSpec spec;
    spec.resolution = 0.03;  // the thesis pipeline's 504 triangles
    const SurfaceMesh m = make_notched_bar(spec);
    Material mat;
    mat.E = 1;
    mat.nu = 0.3;
    AssemblyOptions opt;
    opt.single_layer = false;
    opt.quadrature = q;
    const auto ops = assemble_surface_operators(m, mat, opt);
    BoundaryConditions b = parse_boundary_conditions("*: traction 0 0 0");
    for (std::size_t a = 0; a < m.num_triangles(); ++a) b.element_tractions.push_back(Vec3(0, ops->geometry[a].normal.y(), 0));
    const auto sol = solve_sgbem(ops, nullptr, resolve(b, m), {}, nullptr);
    std::vector<Vec3> e;
    Vec3 mean = Vec3::Zero();
    double norm2 = 0;
    for (std::size_t v = 0; v < m.num_vertices(); ++v) {
        const Vec3& x = m.vertices[v];
        const Vec3 exact(-mat.nu * x.x(), x.y(), -mat.nu * x.z());  // sigma_yy = 1, E = 1
        e.push_back(sol->displacement[v] - exact);
        mean += e.back();
        norm2 += exact.squaredNorm();
    }
    mean /= double(e.size());
    double err2 = 0;
    for (const Vec3& d : e) err2 += (d - mean).squaredNorm();
    return {std::sqrt(err2 / norm2), ops->rigid_motion.max_residual};
}

TEST(FoldRules, NotchedBarPatchTestIsSixteenTimesCloserWithThem) {
    QuadratureSettings off;
    off.fold_angle = 0;
    const PatchResult before = notched_bar_tension(off), after = notched_bar_tension(QuadratureSettings{});
    // Measured: 1.8e-3 and 0.144 without, 1.15e-4 and 0.0175 with (order 10 on folds below 60 degrees).
    EXPECT_GT(before.u_error, 1e-3);
    EXPECT_GT(before.k_residual, 0.1);
    EXPECT_LT(after.u_error, 2e-4);
    EXPECT_LT(after.k_residual, 0.025);
}

TEST(FoldRules, OnlyPairsFoldedSharperThanTheAngleChange) {
    // A cube's edges fold at 90 degrees: the same blocks bit for bit with and without fold rules.
    const SurfaceMesh cube = bem_cube_mesh(2, 1.0);
    AssemblyOptions off;
    off.quadrature.fold_angle = 0;
    const auto a = assemble_surface_operators(cube, Material{}, off), b = assemble_surface_operators(cube, Material{}, AssemblyOptions{});
    EXPECT_TRUE(a->V == b->V);
    EXPECT_TRUE(a->K == b->K);
    EXPECT_TRUE(a->D == b->D);
    // Two triangles on the edge (0,0,0)-(1,0,0) folded at 30 degrees: with fold rules their integrals
    // are those of order 10, and closer to order 12's than order 5's are.
    const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.4, -1, 0}, {0.6, -c, s}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}};
    const std::vector<ElementGeometry> g = element_geometries(m, "test");
    auto k_sum = [&](const QuadratureSettings& q) {
        const PairIntegrals p = pair_integrals(g[0], g[1], true, PairQuadrature(q));
        return p.IKb[0] + p.IKb[1] + p.IKb[2];
    };
    QuadratureSettings order10 = off.quadrature, order12 = off.quadrature;
    order10.singular_order = 10;
    order12.singular_order = 12;
    const double with = k_sum(QuadratureSettings{}), plain = k_sum(off.quadrature), ten = k_sum(order10), ref = k_sum(order12);
    EXPECT_EQ(with, ten);
    EXPECT_LT(std::abs(with - ref), 0.5 * std::abs(plain - ref));
    QuadratureSettings blunt;
    blunt.fold_angle = 20;  // the pair's 30 degrees are not sharper than 20
    EXPECT_EQ(k_sum(blunt), plain);
}

}  // namespace
}  // namespace cf::bem
