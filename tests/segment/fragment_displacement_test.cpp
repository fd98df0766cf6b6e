// Deformed fragment output (ch. 6.4, listing 2): closest-triangle grid against brute force, the
// continuous displacement against a linear field u = A x + b (P1 interpolation reproduces it
// exactly), the crack opening on both faces of a planar cut of a box, the compressive-opening
// removal, and gap closing measured against the crack plane.
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragment_displacement.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/domain/triangle_grid.hpp"
#include "tests/levelset/test_meshes.hpp"
#include "tests/segment/displacement_fixture.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <iostream>
#include <random>

namespace cf {
namespace {

using namespace displacement_fixture;

std::shared_ptr<const CoarseDisplacement> planar_crack_coarse(const Vec3& opening) {
    return std::make_shared<const CoarseDisplacement>(coarse_displacement_from(*planar_crack_solution(opening), true));
}

struct PlanarCut {
    CrackLevelSets cracks;
    Fragments fragments;
    std::vector<SurfaceMesh> meshes;  // [0] below the crack, [1] above
};

PlanarCut cut_at(double z) {
    PlanarCut c;
    c.cracks = CrackLevelSets{kRf, 3, {planar_disk_crack(Vec3(0, 0, z), Vec3::UnitZ(), 1.0, kRf)}};
    c.fragments = find_fragments(broken_object(cube_grid(), c.cracks));
    for (const Fragment& f : c.fragments.fragments) c.meshes.push_back(level_set_to_mesh(f.grid));
    return c;
}

// The fine crack recorded exactly on the coarse sheet's plane z0.
const PlanarCut& planar_cut() {
    static const PlanarCut cut = cut_at(kZ0);
    return cut;
}

// Independent expectation for a vertex of the planar cut: closest coarse point among the cube
// faces and the crack square, u = A y + b there (u_c of a linear field is the field), plus
// side * w * [u] where the fine crack is the plane z0 (side = sign(z - z0)) and w follows the
// documented blend: 1/2 when the crack is the closest, else 1/2 clamp((3 r_f - d_f)/(3 r_f - h)).
// Returns the smallest error over the tie candidates.
double planar_cut_error(const Vec3& x, const Vec3& moved, const Vec3& opening, bool with_opening) {
    double ds = 0;
    const std::vector<Vec3> ys = closest_on_cube(x, &ds);
    const Vec3 yc(std::clamp(x.x(), -0.5, 0.5), std::clamp(x.y(), -0.5, 0.5), kZ0);
    const double dc = (x - yc).norm();
    const double side = x.z() > kZ0 ? 1.0 : -1.0;
    double err = 1e9;
    auto consider = [&](const Vec3& y, bool crack_closest) {
        Vec3 u = field(y);
        if (with_opening && dc <= 3 * kRf) {
            const double w = crack_closest ? 0.5 : 0.5 * std::clamp((3 * kRf - dc) / (3 * kRf - kH), 0.0, 1.0);
            u += side * w * opening;
        }
        err = std::min(err, (moved - x - u).norm());
    };
    if (dc <= ds + 1e-12) consider(yc, true);
    if (ds <= dc + 1e-12)
        for (const Vec3& y : ys) consider(y, false);
    return err;
}

// ---------------------------------------------------------------------------------------------

TEST(TriangleGrid, ClosestAndWithinMatchBruteForce) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(-1, 1), size(-0.08, 0.08);
    std::vector<Triangle3> tris;
    for (int i = 0; i < 600; ++i) {
        const Vec3 c(pos(rng), pos(rng), 0.3 * pos(rng));
        tris.push_back({c + Vec3(size(rng), size(rng), size(rng)), c + Vec3(size(rng), size(rng), size(rng)),
                        c + Vec3(size(rng), size(rng), size(rng))});
    }
    const TriangleGrid grid(tris, 0.05);
    int checked = 0;
    for (int q = 0; q < 1500; ++q) {
        // Points on, near and far from the soup (up to 6 cells beyond its box and more).
        const double spread = q < 1000 ? 1.1 : 4.0;
        const Vec3 x = spread * Vec3(pos(rng), pos(rng), pos(rng));
        int best = -1;
        double dbest = 1e9;
        std::vector<int> near;
        for (std::size_t t = 0; t < tris.size(); ++t) {
            const double d = std::sqrt(closest_point_on_triangle(x, tris[t][0], tris[t][1], tris[t][2]).distance2);
            if (d < dbest) {
                dbest = d;
                best = int(t);
            }
            if (d <= 0.07) near.push_back(int(t));
        }
        const TriangleGrid::Hit h = grid.closest(x);
        ASSERT_EQ(h.triangle, best) << "query " << x.transpose();
        EXPECT_EQ(h.distance, dbest);
        std::vector<int> got;
        for (const auto& w : grid.within(x, 0.07)) got.push_back(w.triangle);
        EXPECT_EQ(got, near);
        ++checked;
    }
    EXPECT_EQ(checked, 1500);
}

TEST(TriangleGrid, RejectsBadCellSizeAndHugeTriangles) {
    const std::vector<Triangle3> one = {Triangle3{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}};
    EXPECT_THROW(TriangleGrid(one, 0.0), std::invalid_argument);
    EXPECT_THROW(TriangleGrid(one, std::nan("")), std::invalid_argument);
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { TriangleGrid(one, 1e-4, 1e6); }, {"cell size"}));
    EXPECT_EQ(TriangleGrid({}, 0.1).closest(Vec3::Zero()).triangle, -1);
}

// (a) Continuous displacement of an uncut cube: every output vertex gets A y + b at its closest
// point y on the cube surface, exactly (linear data on P1 triangles).
TEST(FragmentDisplacement, ContinuousReproducesLinearFieldOnTheSurface) {
    const SurfaceMesh fine = level_set_to_mesh(cube_grid());
    auto coarse = std::make_shared<CoarseDisplacement>();
    coarse->surface = bem::bem_cube_mesh(4, 1.0);
    for (const Vec3& x : coarse->surface.vertices) coarse->surface_displacement.push_back(field(x));
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous;
    const FragmentDeformation def(coarse, nullptr, kRf, opt);
    EXPECT_NEAR(def.cell_size(), (0.25 * 2 + 0.25 * std::sqrt(2.0)) / 3, 1e-12);  // mean edge of the 4x4 grid
    DeformationStats st;
    const std::vector<Vec3> moved = def.deformed(fine.vertices, &st);
    double err = 0, umax = 0;
    for (std::size_t i = 0; i < moved.size(); ++i) {
        double d = 0;
        double e = 1e9;
        for (const Vec3& y : closest_on_cube(fine.vertices[i], &d)) e = std::min(e, (moved[i] - fine.vertices[i] - field(y)).norm());
        err = std::max(err, e);
        umax = std::max(umax, (moved[i] - fine.vertices[i]).norm());
    }
    std::cout << "continuous, " << moved.size() << " vertices: max |u - (A y + b)| = " << err << " m (|u| up to " << umax << " m)\n";
    EXPECT_EQ(st.vertices, moved.size());
    EXPECT_EQ(st.on_crack, 0u);
    EXPECT_GT(moved.size(), 10000u);
    EXPECT_LT(err, 1e-15);  // round-off: 1e-12 of |u| ~ 1e-3 m

    // The scale multiplies the displacement.
    opt.scale = 10;
    const std::vector<Vec3> big = FragmentDeformation(coarse, nullptr, kRf, opt).deformed(fine.vertices);
    double es = 0;
    for (std::size_t i = 0; i < big.size(); ++i)
        es = std::max(es, (big[i] - fine.vertices[i] - 10 * (moved[i] - fine.vertices[i])).norm());
    EXPECT_LT(es, 1e-14);
}

// (b) Planar cut with a uniform tensile opening [u] = (s, 0, d): u_c from the representation
// formula equals the field, the + face (upper fragment) moves by +[u]/2 and the - face by -[u]/2.
TEST(FragmentDisplacement, OpeningMovesTheFacesApartOnBothFragments) {
    const PlanarCut& cut = planar_cut();
    ASSERT_EQ(cut.meshes.size(), 2u);
    const Vec3 opening(1e-3, 0, 4e-3);
    const auto coarse = planar_crack_coarse(opening);
    // u_c at the crack vertices (eq. 2.20 over the ordinary surface) reproduces the linear field.
    double euc = 0;
    for (std::size_t v = 0; v < coarse->cracks.num_vertices(); ++v)
        euc = std::max(euc, (coarse->crack_average[v] - field(coarse->cracks.vertices[v])).norm());
    std::cout << "u_c at " << coarse->cracks.num_vertices() << " crack vertices: max |u_c - (A x + b)| = " << euc << " m\n";
    EXPECT_LT(euc, 1e-10);  // interior quadrature error ~1e-7 relative (interior_evaluation.hpp) of |u| ~ 1e-3 m

    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous_and_opening;
    const FragmentDeformation def(coarse, &cut.cracks, kRf, opt);
    EXPECT_EQ(def.compressive_vertices(), 0u);
    double err = 0;
    for (int f = 0; f < 2; ++f) {
        const std::vector<Vec3>& x = cut.meshes[std::size_t(f)].vertices;
        DeformationStats st;
        const std::vector<Vec3> moved = def.deformed(x, &st);
        double jump = 1e9, face_err = 0;
        std::size_t face = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            err = std::max(err, planar_cut_error(x[i], moved[i], opening, true));
            // Cut-face vertices away from the cube's sides: displacement minus the field at the
            // projection onto the crack plane is exactly +-[u]/2.
            if (std::abs(std::abs(x[i].z() - kZ0) - kH) < 0.1 * kRf && x[i].head<2>().cwiseAbs().maxCoeff() < 0.5 - 3 * kRf) {
                const Vec3 rel = moved[i] - x[i] - field(Vec3(x[i].x(), x[i].y(), kZ0));
                jump = std::min(jump, f == 1 ? rel.z() : -rel.z());  // + face up, - face down
                face_err = std::max(face_err, (rel - (f == 1 ? 0.5 : -0.5) * opening).norm());
                ++face;
            }
        }
        std::cout << (f ? "upper" : "lower") << " fragment: " << x.size() << " vertices, " << face
                  << " on the cut face, max |offset -+ [u]/2| = " << face_err << " m, opened " << st.opened
                  << ", sign from coarse " << st.sign_from_coarse << "\n";
        EXPECT_GE(face, kFaceVertices);
        EXPECT_LT(face_err, 1e-10);
        EXPECT_GT(jump, opening.z() / 2 - 1e-10);
        EXPECT_EQ(st.sign_from_coarse, 0u);  // every opened vertex is inside the fine crack band
        EXPECT_GE(st.opened, face);
    }
    std::cout << "opening, all vertices of both fragments: max error against the closed form " << err << " m\n";
    EXPECT_LT(err, 1e-10);  // |u| ~ 1e-3 m, opening 4e-3 m; the bar is the u_c quadrature error
}

// The face is decided by the fine crack surface, not the coarse sheet: with the recorded crack
// 1.5 r_f above the coarse sheet, the lower fragment's cut face (z1 - h = z0 + 0.63 r_f) lies on
// the coarse sheet's + side but is the - face, and must move by -[u]/2.
TEST(FragmentDisplacement, FaceSignComesFromTheFineCrackSurface) {
    const double z1 = kZ0 + 1.5 * kRf;
    const PlanarCut cut = cut_at(z1);
    ASSERT_EQ(cut.meshes.size(), 2u);
    const Vec3 opening(0, 0, 4e-3);
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous_and_opening;
    const FragmentDeformation def(planar_crack_coarse(opening), &cut.cracks, kRf, opt);
    const bool upper_first = cut.fragments.fragments[0].centroid.z() > z1;
    for (int f = 0; f < 2; ++f) {
        const bool upper = (f == 0) == upper_first;
        const std::vector<Vec3>& x = cut.meshes[std::size_t(f)].vertices;
        const std::vector<Vec3> moved = def.deformed(x);
        double err = 0;
        std::size_t face = 0, coarse_plus = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            if (std::abs(std::abs(x[i].z() - z1) - kH) > 0.1 * kRf || x[i].head<2>().cwiseAbs().maxCoeff() > 0.5 - 4 * kRf)
                continue;
            const Vec3 y(x[i].x(), x[i].y(), kZ0);
            err = std::max(err, (moved[i] - x[i] - field(y) - (upper ? 0.5 : -0.5) * opening).norm());
            coarse_plus += x[i].z() > kZ0;
            ++face;
        }
        std::cout << (upper ? "upper" : "lower") << " fragment, fine crack 1.5 r_f above the sheet: " << face
                  << " cut-face vertices (" << coarse_plus << " on the sheet's + side), max error " << err << " m\n";
        EXPECT_GE(face, 41u * 41u);  // one per voxel inside |x|, |y| < 0.5 - 4 r_f
        EXPECT_EQ(coarse_plus, face);  // both faces are above the coarse sheet
        EXPECT_LT(err, 1e-10);
    }
}

// Compressive opening [u] = (s, 0, -d): removed, the faces only slide by +-s/2; kept, they overlap.
TEST(FragmentDisplacement, CompressiveOpeningIsRemovedOrKept) {
    const PlanarCut& cut = planar_cut();
    const Vec3 opening(1e-3, 0, -4e-3);
    const auto coarse = planar_crack_coarse(opening);
    for (bool remove : {true, false}) {
        DeformationOptions opt;
        opt.mode = DisplacementMode::continuous_and_opening;
        opt.remove_compressive_opening = remove;
        const FragmentDeformation def(coarse, &cut.cracks, kRf, opt);
        EXPECT_EQ(def.compressive_vertices(), remove ? coarse->cracks.num_vertices() : 0u);
        const Vec3 effective = remove ? Vec3(opening.x(), 0, 0) : opening;
        for (const Vec3& o : def.opening()) EXPECT_LT((o - effective).norm(), 1e-18);
        double err = 0;
        for (int f = 0; f < 2; ++f) {
            const std::vector<Vec3>& x = cut.meshes[std::size_t(f)].vertices;
            const std::vector<Vec3> moved = def.deformed(x);
            for (std::size_t i = 0; i < x.size(); ++i) err = std::max(err, planar_cut_error(x[i], moved[i], effective, true));
        }
        std::cout << "compressive opening " << (remove ? "removed" : "kept") << ": max error " << err << " m\n";
        EXPECT_LT(err, 1e-10);
    }
}

// (c) Closing the gaps: cut-face vertices sit h = 0.87 r_f from the crack plane before and on it
// after; vertices away from the crack do not move.
TEST(FragmentDisplacement, CloseGapsPutsCutFacesOnTheCrackPlane) {
    const PlanarCut& cut = planar_cut();
    DeformationOptions opt;
    opt.close_gaps = true;
    const FragmentDeformation def(nullptr, &cut.cracks, kRf, opt);
    double before = 0, after = 0, far_moved = 0;
    std::size_t face = 0, closed = 0;
    for (const SurfaceMesh& m : cut.meshes) {
        DeformationStats st;
        const std::vector<Vec3> moved = def.deformed(m.vertices, &st);
        closed += st.closed;
        for (std::size_t i = 0; i < moved.size(); ++i) {
            const Vec3& x = m.vertices[i];
            if (std::abs(x.z() - kZ0) < 2 * kRf && x.head<2>().cwiseAbs().maxCoeff() < 0.5 - 2 * kRf) {
                before = std::max(before, std::abs(x.z() - kZ0));
                after = std::max(after, std::abs(moved[i].z() - kZ0));
                EXPECT_LT((moved[i] - x).head<2>().norm(), 1e-6 * kRf);  // straight onto the plane
                ++face;
            } else if (std::abs(x.z() - kZ0) > 2 * kRf) {
                far_moved = std::max(far_moved, (moved[i] - x).norm());
            }
        }
    }
    std::cout << "close gaps: " << face << " cut-face vertices (" << closed << " closed in all), max |z - z0| "
              << before / kRf << " r_f before, " << after / kRf << " r_f after\n";
    EXPECT_GE(face, 2 * kFaceVertices);
    EXPECT_GE(closed, face);
    EXPECT_NEAR(before, kH, 0.05 * kRf);
    EXPECT_LT(after, 1e-5 * kRf);  // float storage of the grid values (~1e-7 relative)
    EXPECT_EQ(far_moved, 0.0);
}

// Closing and opening together: the + face ends at z0 + u_z + d/2, the - face at z0 + u_z - d/2.
TEST(FragmentDisplacement, ClosedFacesOpenByTheOpening) {
    const PlanarCut& cut = planar_cut();
    const Vec3 opening(0, 0, 4e-3);
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous_and_opening;
    opt.close_gaps = true;
    const FragmentDeformation def(planar_crack_coarse(opening), &cut.cracks, kRf, opt);
    double err = 0;
    std::size_t face = 0;
    for (int f = 0; f < 2; ++f) {
        const std::vector<Vec3>& x = cut.meshes[std::size_t(f)].vertices;
        const std::vector<Vec3> moved = def.deformed(x);
        for (std::size_t i = 0; i < x.size(); ++i) {
            if (std::abs(x[i].z() - kZ0) > 2 * kRf || x[i].head<2>().cwiseAbs().maxCoeff() > 0.5 - 3 * kRf) continue;
            const Vec3 y(x[i].x(), x[i].y(), kZ0);
            err = std::max(err, (moved[i] - (y + field(y) + (f == 1 ? 0.5 : -0.5) * opening)).norm());
            ++face;
        }
    }
    std::cout << "closed + opened, " << face << " cut-face vertices: max |x_new - (y + u(y) +- [u]/2)| = " << err << " m\n";
    EXPECT_GE(face, 2 * kFaceVertices);
    EXPECT_LT(err, 1e-5 * kRf);  // as the gap closing: float grid values
}

TEST(FragmentDisplacement, SameResultForAnyThreadCount) {
    const PlanarCut& cut = planar_cut();
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous_and_opening;
    opt.close_gaps = true;
    const FragmentDeformation def(planar_crack_coarse(Vec3(1e-3, 2e-3, 4e-3)), &cut.cracks, kRf, opt);
    std::vector<Vec3> one, two;
    DeformationStats s1, s2;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        one = def.deformed(cut.meshes[1].vertices, &s1);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
        two = def.deformed(cut.meshes[1].vertices, &s2);
    }
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]);
    EXPECT_EQ(s1.opened, s2.opened);
    EXPECT_EQ(s1.max_displacement, s2.max_displacement);
}

TEST(FragmentDisplacement, MissingOrInconsistentInputsAreNamed) {
    const PlanarCut& cut = planar_cut();
    const auto coarse = planar_crack_coarse(Vec3(0, 0, 1e-3));
    auto message = [](auto&& make) {
        try {
            make();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    DeformationOptions opt;
    opt.mode = DisplacementMode::continuous;
    EXPECT_NE(message([&] { FragmentDeformation(nullptr, nullptr, kRf, opt); }).find("BEM"), std::string::npos);
    opt.mode = DisplacementMode::continuous_and_opening;
    EXPECT_NE(message([&] { FragmentDeformation(coarse, nullptr, kRf, opt); }).find("crack grids"), std::string::npos);
    EXPECT_NE(message([&] { FragmentDeformation(coarse, &cut.cracks, 2 * kRf, opt); }).find("voxel size"), std::string::npos);
    const CrackLevelSets none{kRf, 3, {}};
    EXPECT_NE(message([&] { FragmentDeformation(coarse, &none, kRf, opt); }).find("crack grids"), std::string::npos);
    auto bad = std::make_shared<CoarseDisplacement>(*coarse);
    bad->crack_opening.pop_back();
    EXPECT_NE(message([&] { FragmentDeformation(bad, &cut.cracks, kRf, opt); }).find("crack opening"), std::string::npos);
    opt.mode = DisplacementMode::none;
    opt.close_gaps = true;
    EXPECT_NE(message([&] { FragmentDeformation(nullptr, nullptr, kRf, opt); }).find("closing gaps"), std::string::npos);
    EXPECT_THROW(displacement_mode_from_name("opening"), std::invalid_argument);
}

}  // namespace
}  // namespace cf
