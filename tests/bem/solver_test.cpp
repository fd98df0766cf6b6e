// Solver-level checks: the registered verification cases, bad inputs, incremental cracks.
#include "nodes/bem/assembly_step.hpp"
#include "nodes/bem/bem_verification.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/bem/tip_elements.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

using namespace cf;
using namespace cf::bem;

namespace {
const VerificationCase& find_case(const std::string& name) {
    static std::vector<VerificationCase> cases = [] {
        std::vector<VerificationCase> c;
        add_bem_verification_cases(c);
        return c;
    }();
    for (const auto& c : cases)
        if (c.name == name) return c;
    throw std::runtime_error("no case " + name);
}
void expect_case(const std::string& name) {
    const VerificationResult r = find_case(name).run();
    std::cout << name << ": error " << r.error << " (tolerance " << r.tolerance << ") " << r.details << "\n";
    EXPECT_TRUE(r.passed) << r.details;
}
}  // namespace

TEST(BemVerification, operator_symmetry) { expect_case("operator_symmetry"); }
TEST(BemVerification, rigid_body_kernel) { expect_case("rigid_body_kernel"); }
TEST(BemVerification, cube_tension_neumann) { expect_case("cube_tension_neumann"); }
TEST(BemVerification, cube_tension_mixed) { expect_case("cube_tension_mixed"); }
TEST(BemVerification, sphere_radial_traction) { expect_case("sphere_radial_traction"); }
TEST(BemVerification, pressure_sphere) { expect_case("pressure_sphere"); }
TEST(BemVerification, penny_crack_opening) { expect_case("penny_crack_opening"); }
TEST(BemVerification, penny_crack_sif) { expect_case("penny_crack_sif"); }
TEST(BemVerification, penny_crack_sif_displacement_correlation) { expect_case("penny_crack_sif_displacement_correlation"); }
TEST(BemVerification, elliptical_crack_sif) { expect_case("elliptical_crack_sif"); }
TEST(BemVerification, penny_crack_energy) { expect_case("penny_crack_energy"); }

namespace {
Material unit_material() {
    Material m;
    m.E = 1;
    m.nu = 0.3;
    return m;
}
// The crack tests' body: a 10 m cube of unit material whose top and bottom are pulled apart.
struct PulledCube {
    std::shared_ptr<const SurfaceOperators> ops;
    ResolvedConditions bc;
};
PulledCube pulled_cube() {
    AssemblyOptions opt;
    opt.single_layer = false;
    PulledCube c;
    c.ops = assemble_surface_operators(bem_cube_mesh(3, 10.0), unit_material(), opt);
    c.bc = resolve(parse_boundary_conditions("z_max: traction 0 0 1; z_min: traction 0 0 -1; *: traction 0 0 0"), c.ops->mesh);
    return c;
}
SurfaceMesh first_rings(const SurfaceMesh& disk, int rings) {
    // The disk builder numbers vertices ring by ring, so its first 6 r^2 triangles and
    // 1 + 3 r (r+1) vertices form the disk of r rings.
    SurfaceMesh m = disk;
    m.triangles.resize(6 * rings * rings);
    m.region.resize(m.triangles.size());
    m.vertices.resize(1 + 3 * rings * (rings + 1));
    return m;
}
}  // namespace

TEST(BemCracks, AppendOnlyAssemblyAndSchurExtensionMatchFullSolve) {
    const auto [o, bc] = pulled_cube();
    const SurfaceMesh disk = bem_disk_mesh(6, 1.0);
    const SurfaceMesh small = first_rings(disk, 4);
    const auto c1 = append_crack_elements(*o, nullptr, small);
    const auto s1 = solve_sgbem(o, c1, bc, {}, nullptr);
    const auto c2 = append_crack_elements(*o, c1, disk);
    const auto s2 = solve_sgbem(o, c2, bc, {}, s1.get());
    const auto full = append_crack_elements(*o, nullptr, disk);
    const auto s3 = solve_sgbem(o, full, bc, {}, nullptr);
    // Every element pair computed exactly once: the two appends together equal one full assembly.
    EXPECT_EQ(c2->pairs_computed, full->pairs_computed);
    EXPECT_EQ(c2->pairs_computed_last, full->pairs_computed - c1->pairs_computed);
    EXPECT_LT((c2->Y() - full->Y()).norm(), 1e-13 * full->Y().norm());
    EXPECT_LT((c2->X - full->X).norm(), 1e-13 * full->X.norm());
    EXPECT_LT((c2->W - full->W).norm(), 1e-13 * full->W.norm());
    // The surface factor is reused and the Schur factor extended, giving the full solve's answer.
    EXPECT_TRUE(s2->reused_surface_factor);
    EXPECT_TRUE(s2->extended_schur);
    EXPECT_FALSE(s3->extended_schur);
    EXPECT_EQ(s2->schur_rows_added, 3u * (6 * 4 + 6 * 5));  // old front ring 4 and new ring 5 become interior
    double diff = 0, ref = 0;
    for (std::size_t v = 0; v < disk.num_vertices(); ++v) {
        diff = std::max(diff, (s2->crack_opening[v] - s3->crack_opening[v]).norm());
        ref = std::max(ref, s3->crack_opening[v].norm());
    }
    EXPECT_LT(diff, 1e-9 * ref);
    // A step that added nothing (the loop's last re-solve): no new rows, the same answer.
    const auto c4 = append_crack_elements(*o, c2, disk);
    const auto s4 = solve_sgbem(o, c4, bc, {}, s2.get());
    EXPECT_TRUE(s4->extended_schur);
    EXPECT_EQ(s4->schur_rows_added, 0u);
    for (std::size_t v = 0; v < disk.num_vertices(); ++v)
        EXPECT_LT((s4->crack_opening[v] - s2->crack_opening[v]).norm(), 1e-12 * ref) << "node " << v;
    // Opening points along +n (tension opens the crack) and front nodes carry none.
    EXPECT_GT(s3->crack_opening[0].z(), 0);
    EXPECT_EQ(s3->crack_opening.back().norm(), 0.0);
}

namespace {
// Two crack sheets in one mesh, numbered as the append-only assembly requires: disk A's first `rings`
// rings, then all of disk B, then A's further rings appended after B.
SurfaceMesh two_sheets(const SurfaceMesh& a, int first_rings_a, int rings_a, const SurfaceMesh& b) {
    const SurfaceMesh a0 = first_rings(a, first_rings_a), a1 = first_rings(a, rings_a);
    const int na0 = static_cast<int>(a0.num_vertices()), nb = static_cast<int>(b.num_vertices());
    SurfaceMesh m = a0;
    for (const Vec3& p : b.vertices) m.vertices.push_back(p);
    for (const Tri& t : b.triangles) m.triangles.push_back({t[0] + na0, t[1] + na0, t[2] + na0});
    for (std::size_t v = a0.num_vertices(); v < a1.num_vertices(); ++v) m.vertices.push_back(a1.vertices[v]);
    for (std::size_t t = a0.num_triangles(); t < a1.num_triangles(); ++t) {
        Tri r = a1.triangles[t];
        for (int& v : r) v = v < na0 ? v : v + nb;
        m.triangles.push_back(r);
    }
    m.region.assign(m.triangles.size(), 0);
    return m;
}
}  // namespace

// Square-root front elements: a step keeps the previous Schur factor on every node whose basis did not
// change (here all of a sheet whose front stood still), not only on nodes whose elements are all plain,
// and gives the fresh factorisation's answer.
TEST(BemCracks, SquareRootSchurKeepsTheNodesOfASheetThatStoodStill) {
    const auto [o, bc] = pulled_cube();
    const SurfaceMesh a = bem_disk_mesh(5, 1.5, Vec3(-2.2, 0, 0)), b = bem_disk_mesh(3, 1.0, Vec3(2.2, 0.3, 0));
    std::shared_ptr<const CrackOperators> p1, tip;
    std::shared_ptr<const BemSolution> sol;
    for (int rings = 3; rings <= 5; ++rings) {  // A grows by a ring a step, B stands
        const SurfaceMesh m = two_sheets(a, 3, rings, b);
        p1 = append_crack_elements(*o, p1, m);
        tip = tip_crack_operators(*o, *p1, tip.get());
        sol = solve_sgbem(o, tip, bc, {}, sol.get());
    }
    const auto fresh = solve_sgbem(o, tip, bc, {}, nullptr);
    // Every node of both sheets carries an unknown (front nodes their square-root coefficient). Kept at
    // the last step: all of B's nodes and A's rings 0-2, whose elements were plain at the step before and
    // still are; A's rings 3 (its elements were front elements) and 4 (a front ring then) changed.
    auto disk_nodes = [](int r) { return 1 + 3 * r * (r + 1); };
    const std::size_t dofs = disk_nodes(5) + disk_nodes(3), kept = disk_nodes(3) + disk_nodes(2);
    EXPECT_TRUE(sol->extended_schur);
    EXPECT_EQ(sol->schur_rows_added, 3 * (dofs - kept));
    EXPECT_EQ(fresh->schur_rows_added, 3 * dofs);
    double diff = 0, ref = 0;
    for (std::size_t v = 0; v < tip->cracks.num_vertices(); ++v) {
        diff = std::max({diff, (sol->crack_opening[v] - fresh->crack_opening[v]).norm(),
                         (sol->front_coefficient[v] - fresh->front_coefficient[v]).norm()});
        ref = std::max({ref, fresh->crack_opening[v].norm(), fresh->front_coefficient[v].norm()});
    }
    EXPECT_GT(ref, 0);
    EXPECT_LT(diff, 1e-9 * ref);
}

// Square-root blocks built from the step before (its corrections kept where the front stood still, its
// blocks kept where nothing changed) are bit for bit those integrated from scratch: the solver's Schur
// reuse relies on it. Sheet A grows by a ring a step, sheet B stands; then a step adds nothing.
TEST(BemCracks, SquareRootBlocksFromTheStepBeforeEqualFreshOnes) {
    const auto [o, bc] = pulled_cube();
    const SurfaceMesh a = bem_disk_mesh(5, 1.5, Vec3(-2.2, 0, 0)), b = bem_disk_mesh(3, 1.0, Vec3(2.2, 0.3, 0));
    std::shared_ptr<const CrackOperators> p1, tip;
    for (int rings : {3, 4, 5, 5}) {
        const SurfaceMesh m = two_sheets(a, 3, rings, b);
        p1 = append_crack_elements(*o, p1, m);
        const auto before = tip;
        tip = tip_crack_operators(*o, *p1, before.get());
        const auto fresh = tip_crack_operators(*o, *p1, nullptr);
        if (before) {
            EXPECT_GT(tip->tip_pairs_reused, 0) << rings;
        }
        ASSERT_EQ(tip->W.cols(), fresh->W.cols());
        ASSERT_EQ(tip->HY.rows(), fresh->HY.rows());
        // Exact equality of every entry (cwiseEqual: no tolerance).
        EXPECT_TRUE(tip->W.cwiseEqual(fresh->W).all()) << rings;
        EXPECT_TRUE(tip->X.cwiseEqual(fresh->X).all()) << rings;
        EXPECT_TRUE(tip->HY.cwiseEqual(fresh->HY).all()) << rings;
        EXPECT_GT(fresh->HY.cwiseAbs().maxCoeff(), 0);
    }
}

// The square-root corrections made inside the append from its P1 blocks (TipCorrectionsOfAppend) give
// bit for bit the square-root blocks integrated without them, and the append's own blocks do not
// change. Corrections of another append are refused.
TEST(BemCracks, SquareRootCorrectionsMadeInTheAppendEqualIntegratedOnes) {
    const auto [o, bc] = pulled_cube();
    const SurfaceMesh a = bem_disk_mesh(5, 1.5, Vec3(-2.2, 0, 0)), b = bem_disk_mesh(3, 1.0, Vec3(2.2, 0.3, 0));
    std::shared_ptr<const CrackOperators> p1, p1_obs, tip, tip_obs;
    for (int rings : {3, 4, 5, 5}) {
        const SurfaceMesh m = two_sheets(a, 3, rings, b);
        const std::size_t old_tris = p1 ? p1->geometry.size() : 0;
        TipCorrectionsOfAppend corrections(*o, m);
        p1 = append_crack_elements(*o, p1, m);
        p1_obs = append_crack_elements(*o, p1_obs, m, -1, &corrections);
        EXPECT_TRUE(p1_obs->HY.cwiseEqual(p1->HY).all()) << rings;
        EXPECT_TRUE(p1_obs->W.cwiseEqual(p1->W).all()) << rings;
        EXPECT_TRUE(p1_obs->X.cwiseEqual(p1->X).all()) << rings;
        tip = tip_crack_operators(*o, *p1, tip.get());
        tip_obs = tip_crack_operators(*o, *p1_obs, tip_obs.get(), &corrections);
        EXPECT_EQ(tip->tip_pairs_in_append, 0);
        EXPECT_EQ(tip_obs->tip_pairs_computed, tip->tip_pairs_computed) << rings;
        if (m.num_triangles() > old_tris) {
            EXPECT_GT(tip_obs->tip_pairs_in_append, 0) << rings;
            EXPECT_LE(tip_obs->tip_pairs_in_append, tip_obs->tip_pairs_computed) << rings;
        } else {
            EXPECT_EQ(tip_obs->tip_pairs_in_append, 0) << rings;
        }
        EXPECT_TRUE(tip_obs->W.cwiseEqual(tip->W).all()) << rings;
        EXPECT_TRUE(tip_obs->X.cwiseEqual(tip->X).all()) << rings;
        EXPECT_TRUE(tip_obs->HY.cwiseEqual(tip->HY).all()) << rings;
        EXPECT_GT(tip->HY.cwiseAbs().maxCoeff(), 0);
        // These corrections belong to p1_obs, not to p1 (another append of the same mesh).
        EXPECT_THROW(tip_crack_operators(*o, *p1, nullptr, &corrections), std::logic_error);
    }
}

// The append's element tasks run in colour order per node without a barrier between colours: the
// blocks must not depend on how many threads run them (each column summed in one fixed order).
TEST(BemCracks, AppendBitIdenticalForOneAndTwoThreads) {
    const auto [o, bc] = pulled_cube();
    const SurfaceMesh a = bem_disk_mesh(5, 1.5, Vec3(-2.2, 0, 0)), b = bem_disk_mesh(3, 1.0, Vec3(2.2, 0.3, 0));
    std::shared_ptr<const CrackOperators> one, two;
    for (int rings : {2, 4, 5}) {
        const SurfaceMesh m = two_sheets(a, 3, rings, b);
        TipCorrectionsOfAppend c1(*o, m), c2(*o, m);
        {
            tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
            one = append_crack_elements(*o, one, m, -1, &c1);
        }
        {
            tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
            two = append_crack_elements(*o, two, m, -1, &c2);
        }
        EXPECT_TRUE(one->W.cwiseEqual(two->W).all()) << rings;
        EXPECT_TRUE(one->X.cwiseEqual(two->X).all()) << rings;
        EXPECT_TRUE(one->HY.cwiseEqual(two->HY).all()) << rings;
        EXPECT_GT(one->HY.cwiseAbs().maxCoeff(), 0) << rings;
        const auto t1 = tip_crack_operators(*o, *one, nullptr, &c1), t2 = tip_crack_operators(*o, *two, nullptr, &c2);
        EXPECT_TRUE(t1->HY.cwiseEqual(t2->HY).all()) << rings;
        EXPECT_TRUE(t1->W.cwiseEqual(t2->W).all()) << rings;
    }
}

TEST(BemCracks, BadCrackInputsGiveClearErrors) {
    AssemblyOptions opt;
    opt.single_layer = false;
    const auto o = assemble_surface_operators(bem_cube_mesh(2, 2.0), unit_material(), opt);
    // Crossing the surface: a disk of radius 1.5 in a cube of half-width 1.
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { append_crack_elements(*o, nullptr, bem_disk_mesh(3, 1.5)); },
        {"strictly inside"}));
    // Degenerate crack triangle.
    SurfaceMesh d = bem_disk_mesh(2, 0.5);
    d.vertices.push_back(Vec3(0.1, 0, 0));
    d.vertices.push_back(Vec3(0.2, 0, 0));
    d.triangles.push_back({0, static_cast<int>(d.vertices.size()) - 2, static_cast<int>(d.vertices.size()) - 1});
    d.region.push_back(0);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { append_crack_elements(*o, nullptr, d); },
        {"degenerate"}));
    // Changing an already assembled element is refused (append-only).
    const SurfaceMesh disk = bem_disk_mesh(2, 0.5);
    const auto c1 = append_crack_elements(*o, nullptr, disk);
    SurfaceMesh moved = disk;
    moved.vertices[0].z() += 0.01;
    EXPECT_THROW(append_crack_elements(*o, c1, moved), std::invalid_argument);
}

TEST(BemBoundaryConditions, UncoveredAndUnknownRegionsAreListed) {
    const SurfaceMesh m = bem_cube_mesh(1, 1.0);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { resolve(parse_boundary_conditions("z_max: traction 0 0 1; z_min: displacement 0 0 0"), m); },
        {"0 ('x_min'), 1 ('x_max'), 2 ('y_min'), 3 ('y_max')"}));
    EXPECT_THROW(resolve(parse_boundary_conditions("top: traction 0 0 1; *: traction 0 0 0"), m), std::invalid_argument);
    EXPECT_THROW(parse_boundary_conditions("z_max: tracton 0 0 1"), std::invalid_argument);
    EXPECT_THROW(parse_boundary_conditions("z_max: traction 0 0"), std::invalid_argument);
    EXPECT_THROW(parse_boundary_conditions("z_max traction 0 0 1"), std::invalid_argument);
    const auto bc = resolve(parse_boundary_conditions(" z_min : displacement 0 0 0 ;*: traction 1 2 3;"), m);
    EXPECT_EQ(bc.dirichlet[8], 1);  // z_min triangles are 8, 9
    EXPECT_EQ(bc.traction[0], Vec3(1, 2, 3));
}

TEST(BemBoundaryConditions, PressureIsMinusPTimesEachElementsNormalAndAddsToATraction) {
    // Unit cube: face normals are +-e_x, +-e_y, +-e_z, so -p n is known by hand per face.
    const SurfaceMesh m = bem_cube_mesh(1, 1.0);
    const auto bc = resolve(parse_boundary_conditions("z_max: pressure 2e5; z_max: traction 1 2 3; x_min: pressure -7; "
                                                      "z_min: displacement 0 0 0; *: traction 0 0 0"),
                            m);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const std::string r = m.region_name(m.region_of(t));
        if (r == "z_max") {
            EXPECT_EQ(bc.traction[t], Vec3(1, 2, 3 - 2e5)) << t;
        } else if (r == "x_min") {
            EXPECT_EQ(bc.traction[t], Vec3(-7, 0, 0)) << t;  // n = -e_x, p = -7: t = -7 e_x
        } else if (r == "z_min") {
            EXPECT_EQ(bc.dirichlet[t], 1) << t;
        } else {
            EXPECT_EQ(bc.traction[t], Vec3::Zero()) << t;
        }
    }
    // '*' may be a pressure: every other region gets -p n.
    const auto all = resolve(parse_boundary_conditions("*: pressure 1"), m);
    for (std::size_t t = 0; t < m.num_triangles(); ++t) EXPECT_NEAR((all.traction[t] + triangle_normal(m, t)).norm(), 0, 1e-15);
    // A pressure on a Dirichlet region names the region, in either order.
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [] { parse_boundary_conditions("z_min: displacement 0 0 0; z_min: pressure 1e5"); }, {"region 'z_min'", "Dirichlet"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [] { parse_boundary_conditions("*: pressure 1e5; *: displacement 0 0 0"); }, {"'*'", "Dirichlet"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([] { parse_boundary_conditions("top: pressure 1; top: pressure 2"); },
                                                           {"region 'top'", "twice"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([] { parse_boundary_conditions("top: pressure"); }, {"one finite number"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([] { parse_boundary_conditions("top: pressure 1 2"); }, {"unexpected '2'"}));
}

TEST(BemBoundaryConditions, AConditionOnAnEmptyRegionIsAnError) {
    SurfaceMesh m = bem_cube_mesh(1, 1.0);
    m.region_names.push_back("lid");  // named, but no triangle carries it
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { resolve(parse_boundary_conditions("lid: pressure 1e5; *: traction 0 0 0"), m); }, {"region 'lid'", "no triangles"}));
    EXPECT_NO_THROW(resolve(parse_boundary_conditions("*: traction 0 0 0"), m));  // '*' over an empty region is fine
}

TEST(BemSolve, UnbalancedNeumannLoadIsRefusedWithResultants) {
    AssemblyOptions opt;
    opt.single_layer = false;
    const auto o = assemble_surface_operators(bem_cube_mesh(1, 1.0), unit_material(), opt);
    const auto bc = resolve(parse_boundary_conditions("z_max: traction 0 0 1; *: traction 0 0 0"), o->mesh);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { solve_sgbem(o, nullptr, bc, {}, nullptr); },
        {"not balanced: net force 0 0 1 N"}));
    // Dirichlet regions need V.
    const auto bc2 = resolve(parse_boundary_conditions("z_min: displacement 0 0 0; *: traction 0 0 0"), o->mesh);
    EXPECT_THROW(solve_sgbem(o, nullptr, bc2, {}, nullptr), std::invalid_argument);
}

TEST(BemSolve, DenseCholeskyMatchesEigenAndIsThreadCountIndependent) {
    // 300 unknowns: three 128-wide panels, so the parallel panel and trailing updates both run.
    const Eigen::Index n = 300;
    Matrix B = Matrix::Random(n, n);
    const Matrix A = B * B.transpose() + n * Matrix::Identity(n, n);
    const Matrix rhs = Matrix::Random(n, 7);
    Matrix x1, x2;
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
        DenseCholesky c(A);
        ASSERT_TRUE(c.ok());
        x1 = c.solve(rhs);
    }
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        DenseCholesky c(A);
        x2 = c.solve(rhs);
    }
    EXPECT_TRUE(x1 == x2);
    const Matrix ref = A.llt().solve(rhs);
    EXPECT_LT((x1 - ref).norm(), 1e-12 * ref.norm());
    // Not positive definite: reported, not thrown.
    Matrix N = A;
    N(200, 200) = -1;
    EXPECT_FALSE(DenseCholesky(N).ok());
    // S += W^T W on the lower triangle.
    const Matrix W = Matrix::Random(40, n);
    Matrix S = A;
    add_lower_gram(S, W);
    const Matrix full = A + W.transpose() * W;
    EXPECT_LT((Matrix(S.triangularView<Eigen::Lower>()) - Matrix(full.triangularView<Eigen::Lower>())).norm(), 1e-13 * full.norm());
}

TEST(BemSolve, MixedSolveBitIdenticalForOneAndTwoThreads) {
    const SurfaceMesh m = bem_cube_mesh(4, 1.0);  // 219 Neumann unknowns: two factorisation panels
    const auto bc = resolve(parse_boundary_conditions("z_min: displacement 0 0 0; z_max: traction 0 0 1; *: traction 0 0 0"), m);
    std::shared_ptr<const BemSolution> a, b;
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
        a = solve_sgbem(assemble_surface_operators(m, unit_material(), AssemblyOptions{}), nullptr, bc, {}, nullptr);
    }
    {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
        b = solve_sgbem(assemble_surface_operators(m, unit_material(), AssemblyOptions{}), nullptr, bc, {}, nullptr);
    }
    EXPECT_TRUE(a->displacement == b->displacement);
    EXPECT_TRUE(a->traction == b->traction);
}

// Surface blocks and a factorisation from an earlier run on the same surface (a rigid body's next
// fracture run, or its class (d) fragment, thesis ch. 7.3) are used as they are, and the solution is
// bit-identical to assembling and factorising again; blocks of another material are not used.
TEST(BemSolve, GivenSurfaceBlocksAndFactorAreReusedOnlyWhenTheyMatch) {
    const SurfaceMesh m = bem_cube_mesh(2, 1.0);
    AssemblyRequest first;
    first.mesh = &m;
    first.material = unit_material();
    first.options.single_layer = false;
    AssemblyReport rep;
    const BemOperators a = assemble_step(first, rep);
    EXPECT_FALSE(rep.surface_reused);
    BoundaryConditions b = parse_boundary_conditions("z_max: traction 0 0 1; z_min: traction 0 0 -1; *: traction 0 0 0");
    const ResolvedConditions bc = resolve(b, m);
    const auto fresh = solve_sgbem(a.surface, nullptr, bc, {}, nullptr);

    AssemblyRequest again = first;
    again.surface_blocks = a.surface;
    const BemOperators a2 = assemble_step(again, rep);
    EXPECT_TRUE(rep.surface_reused);
    EXPECT_EQ(a2.surface, a.surface);
    const auto reused = solve_sgbem(a2.surface, nullptr, bc, {}, nullptr, {}, nullptr, fresh->system);
    EXPECT_TRUE(reused->reused_surface_factor);
    EXPECT_EQ(reused->system, fresh->system);
    EXPECT_TRUE(reused->displacement == fresh->displacement);

    // Another Young's modulus: the blocks do not match and are assembled anew; a factor of other
    // operators is not used either.
    AssemblyRequest stiffer = again;
    stiffer.material.E *= 2;
    const BemOperators a3 = assemble_step(stiffer, rep);
    EXPECT_FALSE(rep.surface_reused);
    EXPECT_NE(a3.surface, a.surface);
    const auto other = solve_sgbem(a3.surface, nullptr, bc, {}, nullptr, {}, nullptr, fresh->system);
    EXPECT_FALSE(other->reused_surface_factor);
    for (std::size_t v = 0; v < m.num_vertices(); ++v)
        EXPECT_LT((2 * other->displacement[v] - fresh->displacement[v]).norm(), 1e-9 * fresh->displacement[v].norm() + 1e-15);
}
