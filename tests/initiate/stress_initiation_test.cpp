// Stress-based crack initiation on real SGBEM solutions (thesis ch. 4.4): a cube under uniaxial
// tension / compression, and branching from the faces of a crack parallel to the load.
#include "initiation_fixtures.hpp"
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/initiate/element_stresses.hpp"
#include "nodes/initiate/stress_initiation.hpp"
#include "nodes/initiate/user_crack.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/shape/box.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <map>

namespace cf::initiate {
namespace {

using testing::box_distance;
using testing::solve_uniaxial;
using testing::strength_field;

constexpr double L = 1.0, sigma = 1e6, r_c = 0.2, r_f = 0.02;

propagate::FractureState fresh_state(const SurfaceMesh& cube) {
    return propagate::start_fracture_state(r_c, r_f, 3, cube.num_triangles());
}

// Vertices of crack region r of the state's crack mesh.
std::vector<int> region_vertices(const propagate::FractureState& s, int r) {
    std::vector<int> v;
    for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t)
        if (s.cracks.region_of(t) == r)
            for (int i : s.cracks.triangles[t])
                if (std::find(v.begin(), v.end(), i) == v.end()) v.push_back(i);
    std::sort(v.begin(), v.end());
    return v;
}

Vec3 region_normal(const propagate::FractureState& s, int r) {
    for (std::size_t t = 0; t < s.cracks.num_triangles(); ++t)
        if (s.cracks.region_of(t) == r) return triangle_normal(s.cracks, t);
    return Vec3::Zero();
}

double segment_distance(const Vec3& p, const Segment& s) {
    const Vec3 d = s[1] - s[0];
    const double t = std::clamp((p - s[0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - (s[0] + t * d)).norm();
}

// Number of cracks whose front comes within r_c of p.
int fronts_within(const propagate::FractureState& s, const Vec3& p, double dist) {
    std::vector<char> near(s.num_cracks(), 0);
    for (const propagate::FrontState& f : s.fronts)
        for (std::size_t i = 0; i < f.front.num_edges(); ++i) {
            const Segment seg{s.cracks.vertices[f.front.nodes[i]], s.cracks.vertices[f.front.nodes[(i + 1) % f.front.nodes.size()]]};
            if (segment_distance(p, seg) <= dist) near[f.front.region] = 1;
        }
    return static_cast<int>(std::count(near.begin(), near.end(), 1));
}

// For every initiated element: the crack whose centre is initial_crack_centre of it (exactly).
std::map<int, int> crack_of_element(const propagate::FractureState& s, const std::vector<ElementStress>& els) {
    std::map<int, int> out;
    for (int r = 0; r < s.num_cracks(); ++r) {
        const Vec3 centre = s.cracks.vertices[region_vertices(s, r).front()];  // hexagon vertex 0
        const Vec3 n = region_normal(s, r);
        for (std::size_t e = 0; e < els.size(); ++e)
            if (s.initiated[e] && (initial_crack_centre(els[e].centroid, els[e].normal, n, r_c) - centre).norm() < 1e-12)
                out[static_cast<int>(e)] = r;
    }
    return out;
}

void expect_valid_new_cracks(const propagate::FractureState& s, const std::vector<ElementStress>& els) {
    const auto owner = crack_of_element(s, els);
    ASSERT_EQ(static_cast<int>(owner.size()), s.num_cracks()) << "every crack belongs to one initiated element";
    for (const auto& [e, r] : owner) {
        // Normal along the load axis, every vertex strictly inside the body, hexagon of 7 nodes.
        EXPECT_GT(std::abs(region_normal(s, r).z()), 0.99) << "crack " << r;
        const std::vector<int> v = region_vertices(s, r);
        EXPECT_EQ(v.size(), 7u);
        for (int i : v) EXPECT_LT(box_distance(s.cracks.vertices[i], L / 2), 0) << "crack " << r;
        // Rule (c): the generating element is within r_c of its own crack's front only.
        EXPECT_EQ(fronts_within(s, els[e].centroid, r_c), 1) << "element " << e;
    }
}

TEST(InitiateCracks, UniaxialTensionStartsCracksNormalToTheLoad) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const auto sol = solve_uniaxial(cube, sigma);
    const std::vector<ElementStress> els = surface_element_stresses(*sol);
    propagate::FractureState s = fresh_state(cube);
    CrackInitiationSettings set;
    set.max_cracks = 4;
    const CrackInitiationReport rep = initiate_cracks(s, *sol, strength_field(0.5 * sigma, 2), set);
    std::cout << "over strength " << rep.selection.over_strength << ", near front " << rep.selection.skipped_near_front
              << ", outside " << rep.skipped_outside << ", surface " << rep.skipped_surface << ", crack " << rep.skipped_crack
              << "\n";
    // Every element carries sigma_zz ~ sigma > strength (192 candidates); the limit (d) stops at 4.
    EXPECT_EQ(rep.selection.over_strength, 192);
    EXPECT_EQ(rep.cracks_added, 4);
    EXPECT_GT(rep.selection.over_budget, 0);  // elements far from the 4 new fronts are held back by (d)
    EXPECT_EQ(rep.selection.skipped_near_front + rep.selection.rejected + rep.cracks_added + rep.selection.over_budget, 192);
    EXPECT_EQ(s.num_cracks(), 4);
    EXPECT_EQ(s.cracks_initiated, 4);
    EXPECT_EQ(std::count(s.initiated.begin(), s.initiated.end(), 1), 4);
    EXPECT_EQ(s.fronts.size(), 4u);
    EXPECT_EQ(s.grids.cracks.size(), 4u);
    expect_valid_new_cracks(s, els);

    // (d) reached: nothing more. A larger limit adds cracks on other elements only (b), and
    // rule (c) holds against the first ones.
    propagate::FractureState again = s;
    EXPECT_EQ(initiate_cracks(again, *sol, strength_field(0.5 * sigma, 2), set).cracks_added, 0);
    set.max_cracks = 8;
    const CrackInitiationReport more = initiate_cracks(again, *sol, strength_field(0.5 * sigma, 2), set);
    EXPECT_EQ(more.cracks_added, 4);
    EXPECT_EQ(more.selection.over_strength, 188);  // the 4 initiated elements are out (b)
    EXPECT_EQ(again.cracks_initiated, 8);
    expect_valid_new_cracks(again, els);

    // Without a limit every candidate is decided, whatever order the (almost uniform) stresses put
    // them in: rule (c) must skip some (an initiated element's partner triangle lies inside its
    // hexagon, within r_c of the front), and each of the 188 is skipped, rejected or added.
    propagate::FractureState all = s;
    set.max_cracks = 1000;
    const CrackInitiationReport rest = initiate_cracks(all, *sol, strength_field(0.5 * sigma, 2), set);
    EXPECT_EQ(rest.selection.over_strength, 188);
    EXPECT_GT(rest.selection.skipped_near_front, 0);
    EXPECT_GT(rest.cracks_added, 0);
    EXPECT_EQ(rest.selection.skipped_near_front + rest.selection.rejected + rest.cracks_added, 188);
    EXPECT_EQ(rest.selection.over_budget, 0);
    // Rule (c) as it is applied, in the order cracks were added: each generating element was more
    // than r_c from every front there before it (a later hexagon may come nearer to it).
    const auto owner = crack_of_element(all, els);
    ASSERT_EQ(static_cast<int>(owner.size()), all.num_cracks());
    for (const auto& [e, r] : owner)
        for (const propagate::FrontState& f : all.fronts)
            if (f.front.region < r)
                for (std::size_t i = 0; i < f.front.num_edges(); ++i) {
                    const Segment seg{all.cracks.vertices[f.front.nodes[i]],
                                      all.cracks.vertices[f.front.nodes[(i + 1) % f.front.nodes.size()]]};
                    EXPECT_GT(segment_distance(els[e].centroid, seg), r_c) << "element " << e << ", crack " << r;
                }

    // Strength above the stress: no candidate at all.
    propagate::FractureState strong = fresh_state(cube);
    const CrackInitiationReport none = initiate_cracks(strong, *sol, strength_field(2 * sigma, 2), set);
    EXPECT_EQ(none.selection.over_strength, 0);
    EXPECT_EQ(strong.num_cracks(), 0);
}

// A BEM surface larger than the object (a scene's class (d) fragment keeps its parent's BEM mesh
// where a chip broke off): with the object's level set given, no hexagon starts outside it. Here
// the object is the half x < 0 of the loaded cube; every element is over strength.
TEST(InitiateCracks, HexagonsOutsideTheObjectAreSkipped) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const auto sol = solve_uniaxial(cube, sigma);
    BoxSpec half;
    half.size = Vec3(L / 2, L, L);
    half.centre = Vec3(-L / 4, 0, 0);
    half.subdivisions = 2;
    const LevelSet object = level_set_from_mesh(make_box(half), r_f);
    CrackInitiationSettings set;
    set.max_cracks = 16;
    propagate::FractureState all = fresh_state(cube), inside = fresh_state(cube);
    const CrackInitiationReport without = initiate_cracks(all, *sol, strength_field(0.5 * sigma, 2), set);
    set.object = &object;
    const CrackInitiationReport with = initiate_cracks(inside, *sol, strength_field(0.5 * sigma, 2), set);
    EXPECT_EQ(without.skipped_outside, 0);
    EXPECT_GT(with.skipped_outside, 0);
    EXPECT_GT(with.cracks_added, 0);
    auto on_positive_side = [](const propagate::FractureState& s) {
        int n = 0;
        for (int r = 0; r < s.num_cracks(); ++r) n += s.cracks.vertices[region_vertices(s, r).front()].x() > 0 ? 1 : 0;
        return n;
    };
    EXPECT_GT(on_positive_side(all), 0) << "the test would not tell: no crack started at x > 0 without the object";
    EXPECT_EQ(on_positive_side(inside), 0);
}

// With the object's level set, hexagons start at their depth below the object's surface, not below
// the BEM element: here the BEM cube (side 1) stands 0.02 outside the object (side 0.96), as a
// remesh offset would. Depth below the element (ch. 4.4): 0.2 r_c (reach + 0.25) = 0.05 on the side
// faces (reach 1) and 0.0125 on the top and bottom (reach 0); below the BEM surface instead, the
// centres would lie 0.03 and -0.0075 (outside) from the object's surface.
TEST(InitiateCracks, HexagonsStartAtTheirDepthBelowTheObjectsSurface) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const auto sol = solve_uniaxial(cube, sigma);
    BoxSpec inner;
    inner.size = Vec3(0.96, 0.96, 0.96);
    inner.subdivisions = 2;
    const LevelSet object = level_set_from_mesh(make_box(inner), 0.01);
    CrackInitiationSettings set;
    set.max_cracks = 12;
    set.object = &object;
    propagate::FractureState s = fresh_state(cube);
    const CrackInitiationReport rep = initiate_cracks(s, *sol, strength_field(0.5 * sigma, 2), set);
    ASSERT_GT(rep.cracks_added, 0);
    for (int r = 0; r < s.num_cracks(); ++r) {
        const double d = box_distance(s.cracks.vertices[region_vertices(s, r).front()], 0.48);
        EXPECT_TRUE(std::abs(d + 0.05) < 2e-3 || std::abs(d + 0.0125) < 2e-3) << "crack " << r << " centre at " << d;
    }
}

// A BEM surface standing off the object by more than r_c / 4 (a scene's remeshed body: offset and
// chords): here the BEM cube (side 1) 0.07 outside the object (side 0.86), r_c / 4 = 0.05. By default
// every element is too far out to be moved onto the object, and every hexagon is skipped as outside
// (a shot bunny that no longer broke); with snap_distance above the standoff (a scene sets 1.25 x its
// body's measured standoff) they start at their depth below the object's surface, as above.
TEST(InitiateCracks, SnapDistanceCoversTheBemSurfacesStandoff) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const auto sol = solve_uniaxial(cube, sigma);
    BoxSpec inner;
    inner.size = Vec3(0.86, 0.86, 0.86);  // every element's centroid (at most 0.417 off-centre) over a face of it
    inner.subdivisions = 2;
    const LevelSet object = level_set_from_mesh(make_box(inner), 0.01, 12);  // band 0.12: the standoff inside it
    CrackInitiationSettings set;
    set.max_cracks = 12;
    set.object = &object;
    propagate::FractureState by_default = fresh_state(cube), snapped = fresh_state(cube);
    const CrackInitiationReport none = initiate_cracks(by_default, *sol, strength_field(0.5 * sigma, 2), set);
    EXPECT_EQ(none.cracks_added, 0);
    EXPECT_GT(none.skipped_outside, 0);
    set.snap_distance = 1.25 * 0.07;
    const CrackInitiationReport rep = initiate_cracks(snapped, *sol, strength_field(0.5 * sigma, 2), set);
    ASSERT_GT(rep.cracks_added, 0);
    EXPECT_EQ(rep.skipped_outside, 0);
    for (int r = 0; r < snapped.num_cracks(); ++r) {
        const double d = box_distance(snapped.cracks.vertices[region_vertices(snapped, r).front()], 0.43);
        EXPECT_TRUE(std::abs(d + 0.05) < 2e-3 || std::abs(d + 0.0125) < 2e-3) << "crack " << r << " centre at " << d;
    }
}

TEST(InitiateCracks, CompressionUsesTheCompressiveFactorAndTheMinimalPrincipalStress) {
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const auto sol = solve_uniaxial(cube, -sigma);
    const std::vector<ElementStress> els = surface_element_stresses(*sol);
    CrackInitiationSettings set;
    set.max_cracks = 3;
    // Tensile strength 0.4 sigma: f_c = 2 gives 0.8 sigma < sigma (initiates), f_c = 3 gives
    // 1.2 sigma > sigma (does not).
    propagate::FractureState s = fresh_state(cube);
    const CrackInitiationReport rep = initiate_cracks(s, *sol, strength_field(0.4 * sigma, 2), set);
    EXPECT_EQ(rep.cracks_added, 3);
    expect_valid_new_cracks(s, els);
    for (const auto& [e, r] : crack_of_element(s, els)) {
        const PrincipalStress p = principal_stresses(els[e].sigma);
        EXPECT_NEAR(p.min(), -sigma, 0.05 * sigma) << "element " << e;
        EXPECT_GT(std::abs(p.min_direction().dot(region_normal(s, r))), 1 - 1e-12) << "element " << e;
    }
    propagate::FractureState t = fresh_state(cube);
    EXPECT_EQ(initiate_cracks(t, *sol, strength_field(0.4 * sigma, 3), set).selection.over_strength, 0);
    EXPECT_EQ(t.num_cracks(), 0);
}

TEST(InitiateCracks, HexagonsThatWouldCutTheSurfaceAreSkipped) {
    // A slab 0.05 m thin, exact uniaxial field along x (u = (sigma/E)(x, -nu y, -nu z), q = sigma
    // n_x e_x): every crack plane is normal to x, and a hexagon of radius 0.2 r_c = 0.04 m is
    // wider than the slab is thick, so each candidate cuts the top/bottom faces or lands outside.
    SurfaceMesh slab = bem::bem_cube_mesh(4, L);
    for (Vec3& v : slab.vertices) v.z() *= 0.05;
    const Material mat = testing::test_material();
    auto ops = std::make_shared<bem::SurfaceOperators>();
    ops->mesh = slab;
    ops->elastic = bem::ElasticConstants(mat.E, mat.nu);
    bem::BemSolution sol;
    sol.surface = ops;
    for (const Vec3& x : slab.vertices) sol.displacement.push_back(sigma / mat.E * Vec3(x.x(), -mat.nu * x.y(), -mat.nu * x.z()));
    for (std::size_t t = 0; t < slab.num_triangles(); ++t) sol.traction.push_back(sigma * triangle_normal(slab, t).x() * Vec3::UnitX());
    propagate::FractureState s = fresh_state(slab);
    CrackInitiationSettings set;
    set.max_cracks = 5;
    const CrackInitiationReport rep = initiate_cracks(s, sol, strength_field(0.5 * sigma, 2), set);
    std::cout << "slab: over strength " << rep.selection.over_strength << ", outside " << rep.skipped_outside << ", surface "
              << rep.skipped_surface << "\n";
    EXPECT_GT(rep.selection.over_strength, 0);
    EXPECT_GT(rep.skipped_surface, 0);
    EXPECT_EQ(rep.selection.rejected, rep.skipped_outside + rep.skipped_surface + rep.skipped_crack);
    EXPECT_EQ(rep.selection.rejected + rep.selection.skipped_near_front, rep.selection.over_strength);
    EXPECT_EQ(rep.cracks_added, 0);
    EXPECT_EQ(s.num_cracks(), 0);
}

TEST(InitiateCracks, SolutionOfAnotherMeshIsRefused) {
    const SurfaceMesh cube = bem::bem_cube_mesh(2, L);
    const auto sol = solve_uniaxial(cube, sigma);
    propagate::FractureState s = propagate::start_fracture_state(r_c, r_f, 3, 10);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { initiate_cracks(s, *sol, strength_field(0.5 * sigma, 2), {}); },
        {"tracks 10 surface elements but the BEM solution's surface has 48"}));
}

TEST(InitiateCracks, BranchingFromTheFacesOfACrackParallelToTheLoad) {
    // A penny crack in the plane y = 0 under load along z does not open, so u_c is the uniaxial
    // field and both faces carry sigma e_z e_z (traction-free: sigma n = 0 on them).
    const SurfaceMesh cube = bem::bem_cube_mesh(4, L);
    const double rc = 0.1;
    propagate::FractureState s = propagate::start_fracture_state(rc, r_f, 3, cube.num_triangles());
    UserCrackSpec spec;
    spec.centre = Vec3(0.02, 0, -0.03);
    spec.normal = Vec3(0, 1, 0);
    spec.radius = 0.3;
    const UserCrack penny = build_user_crack(spec, cube, [](const Vec3& p) { return box_distance(p, L / 2); }, rc, r_f);
    propagate::add_crack(s, penny.sheet, penny.recorded);
    const auto sol = solve_uniaxial(cube, sigma, &s.cracks);

    const std::vector<CrackFaceStress> faces = crack_face_stresses(*sol, bem::crack_average_displacement(*sol));
    Mat3 exact = Mat3::Zero();
    exact(2, 2) = sigma;
    double worst = 0;
    for (const CrackFaceStress& f : faces) {
        worst = std::max({worst, (f.plus.sigma - exact).norm() / sigma, (f.minus.sigma - exact).norm() / sigma});
        EXPECT_NEAR(f.plus.normal.y(), -1, 1e-12);  // "+" face bounds the material on the +n side
        EXPECT_NEAR(f.minus.normal.y(), 1, 1e-12);
    }
    std::cout << "crack faces: " << faces.size() << " elements, max |sigma - sigma_exact|_F / sigma = " << worst << "\n";
    EXPECT_LT(worst, 0.05);

    // Only crack faces may initiate (every surface element flagged): branch cracks normal to the
    // load, offset 0.2 r_c (reach + 1/4) = 0.25 r_c off the parent plane into the material.
    std::fill(s.initiated.begin(), s.initiated.end(), 1);
    CrackInitiationSettings set;
    set.max_cracks = 2;
    propagate::FractureState no_branching = s;
    EXPECT_EQ(initiate_cracks(no_branching, *sol, strength_field(0.5 * sigma, 2), set).cracks_added, 0);
    set.branching = true;
    const CrackInitiationReport rep = initiate_cracks(s, *sol, strength_field(0.5 * sigma, 2), set);
    EXPECT_EQ(rep.crack_face_candidates, static_cast<int>(faces.size()));
    EXPECT_EQ(rep.cracks_added, 2);
    EXPECT_EQ(rep.from_crack_faces, 2);
    ASSERT_EQ(s.num_cracks(), 3);
    for (int r = 1; r < 3; ++r) {
        EXPECT_GT(std::abs(region_normal(s, r).z()), 0.99);
        const Vec3 centre = s.cracks.vertices[region_vertices(s, r).front()];
        EXPECT_NEAR(std::abs(centre.y()), 0.25 * rc, 0.01 * 0.25 * rc) << "branch " << r;
        EXPECT_LT(std::hypot(centre.x() - spec.centre.x(), centre.z() - spec.centre.z()), spec.radius - rc) << "branch " << r;
    }
}

}  // namespace
}  // namespace cf::initiate
