// The right-hand-side update of ch. 5.2 against the full BEM: when the estimated openings are the
// ones the full BEM solved for, the estimated solve (surface unknowns only, f <- f - B du) must give
// the full solve's surface data: the first row of eq. (4.2) with the crack unknowns known.
#include "nodes/bem/boundary_conditions.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/estimate/estimate_verification.hpp"

#include <gtest/gtest.h>

using namespace cf;

namespace {

void check(const char* loads, bool single_layer) {
    const SurfaceMesh cube = bem::bem_cube_mesh(3, 1.0);
    Material mat;
    bem::AssemblyOptions opt;
    opt.single_layer = single_layer;
    const auto surface = bem::assemble_surface_operators(cube, mat, opt);
    const SurfaceMesh sheet = estimate::rectangle_sheet(Vec3(-0.2, -0.2, 0.05), Vec3(0.4, 0, 0.1), Vec3(0, 0.4, 0), 4, 4);
    const auto cracks = bem::append_crack_elements(*surface, nullptr, sheet);
    const auto bc = bem::resolve(bem::parse_boundary_conditions(loads), cube);
    const auto full = bem::solve_sgbem(surface, cracks, bc, {}, nullptr);
    bem::CrackOpeningEstimate est;
    est.opening = full->crack_opening;
    est.known = bem::crack_interior_nodes(sheet);
    const auto growth = bem::update_estimated_growth(*surface, nullptr, sheet, 0, 0, est, 0);
    const auto estimated = bem::solve_sgbem(surface, nullptr, bc, {}, nullptr, {}, growth);
    double du = 0, dt = 0, u = 0, t = 0;
    for (std::size_t v = 0; v < cube.num_vertices(); ++v) {
        du = std::max(du, (estimated->displacement[v] - full->displacement[v]).norm());
        u = std::max(u, full->displacement[v].norm());
    }
    for (std::size_t a = 0; a < cube.num_triangles(); ++a) {
        dt = std::max(dt, (estimated->traction[a] - full->traction[a]).norm());
        t = std::max(t, full->traction[a].norm());
    }
    EXPECT_LT(du, 1e-9 * u) << loads;
    EXPECT_LT(dt, 1e-9 * t) << loads;
    // And the openings matter: without them the surface data differ visibly.
    const auto none = bem::solve_sgbem(surface, nullptr, bc, {}, nullptr);
    double d0 = 0;
    for (std::size_t v = 0; v < cube.num_vertices(); ++v) d0 = std::max(d0, (none->displacement[v] - full->displacement[v]).norm());
    EXPECT_GT(d0, 1e-3 * u) << loads;
}

}  // namespace

TEST(EstimatedSolve, KnownOpeningsReproduceTheFullSolveMixed) {
    check("z_max: traction 0 0 1e6; z_min: displacement 0 0 0; *: traction 0 0 0", true);
}

TEST(EstimatedSolve, KnownOpeningsReproduceTheFullSolvePureNeumann) {
    check("z_max: traction 0 0 1e6; z_min: traction 0 0 -1e6; *: traction 0 0 0", false);
}
