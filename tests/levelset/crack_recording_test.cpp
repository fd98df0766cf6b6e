// Crack grids (ch. 6.2): thickened distance against exact and OpenVDB reference values,
// incremental union, parallel recording independent of scheduling, and the marker tests of
// fig. 27 / eq. (6.2).
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace cf {
namespace {

constexpr double kRf = 0.02;
const double kThick = std::sqrt(3.0) * kRf / 2;

// A straight front along y at x = x0 (z = 0), n markers over y in [-0.3, 0.3].
std::vector<Vec3> line_front(double x0, int n = 13) {
    std::vector<Vec3> f;
    for (int i = 0; i < n; ++i) f.emplace_back(x0, -0.3 + 0.6 * i / (n - 1), 0);
    return f;
}
FrontMotion advance(double x0, double x1) { return FrontMotion{line_front(x0), line_front(x1), false}; }

TEST(CrackGrid, ThickenedDistanceOfAPlanarSheetIsExact) {
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_triangles(0, strip_triangles(advance(-0.2, 0.2)));  // sheet x in [-0.2,0.2], y in [-0.3,0.3]
    const LevelSet crack = rec.snapshot().cracks[0];
    // Above the sheet interior: |z| - sqrt(3) r_f / 2.
    for (double z : {0.0, 0.005, -0.013, 0.03, -0.041})
        EXPECT_NEAR(sample(crack, Vec3(0.011, 0.017, z)), std::abs(z) - kThick, 1e-5) << "z=" << z;
    // Beyond the front edge at x = 0.2: distance to the edge line.
    EXPECT_NEAR(sample(crack, Vec3(0.24, 0.0, 0.0)), 0.04 - kThick, 1e-5);
    // Outside the band: background +3 r_f.
    EXPECT_NEAR(sample(crack, Vec3(0, 0, 0.2)), 3 * kRf, 1e-7);
    // The thin volume Phi_f < 0 encloses the surface: every voxel centre on the sheet is negative.
    EXPECT_LT(sample(crack, Vec3(0.1, 0.1, 0)), 0);
}

TEST(CrackGrid, RasteriserAgreesWithOpenVdbMeshToUnsignedDistance) {
    // A tilted, curved strip: three markers moving obliquely.
    FrontMotion m{{Vec3(0, 0, 0), Vec3(0.1, 0.13, 0.02), Vec3(0.2, 0.21, 0.09)},
                  {Vec3(0.07, -0.05, 0.11), Vec3(0.18, 0.06, 0.15), Vec3(0.3, 0.17, 0.22)}, false};
    const auto tris = strip_triangles(m);
    ASSERT_EQ(tris.size(), 4u);
    CrackRecorder rec(kRf);
    rec.add_crack();
    const std::size_t written = rec.add_triangles(0, tris);
    const LevelSet mine = rec.snapshot().cracks[0];
    const LevelSet ref = reference_strip_level_set(tris, kRf);
    EXPECT_GT(written, 1000u);
    // Compare on a lattice of voxel centres well inside the band (OpenVDB's band edge differs).
    double worst = 0;
    int n = 0;
    for (int i = -10; i <= 25; ++i)
        for (int j = -10; j <= 25; ++j)
            for (int k = -5; k <= 20; ++k) {
                const Vec3 p(i * kRf, j * kRf, k * kRf);
                const double a = sample(mine, p), b = sample(ref, p);
                if (b > 2 * kRf) continue;
                worst = std::max(worst, std::abs(a - b));
                ++n;
            }
    EXPECT_GT(n, 500);
    EXPECT_LT(worst, 1e-3 * kRf);  // float storage, both exact distances
}

// A long, thin, oblique fan (a stopped marker far behind a moving neighbour): its box spans
// many blocks the triangle's band never reaches, which the recorder skips by the distance from
// each block's centre to the triangle. Every voxel of the band must still match the exact
// thickened distance, and none beyond it may be set.
// Exact distance from p to triangle (a, b, c) [m], independent of the recorder's closest-point
// routine: the foot on the plane if it lies inside, else the nearest edge.
double exact_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    auto seg = [](const Vec3& x, const Vec3& u, const Vec3& v) {
        const double t = std::clamp((x - u).dot(v - u) / (v - u).squaredNorm(), 0.0, 1.0);
        return (x - (u + t * (v - u))).norm();
    };
    const double edges = std::min({seg(p, a, b), seg(p, b, c), seg(p, c, a)});
    const Vec3 nn = (b - a).cross(c - a);
    if (nn.norm() < 1e-14) return edges;
    const Vec3 n = nn.normalized();
    const Vec3 q = p - n.dot(p - a) * n;
    const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                        (a - c).cross(q - c).dot(n) >= 0;
    return inside ? (p - q).norm() : edges;
}

// Strips recorded sub-step by sub-step whose quads are twisted (their two triangles not coplanar)
// and tilted towards each axis in turn: the recorder walks a quad's two halves together, and a
// voxel must still hold the thickened distance to the nearest triangle of every strip so far,
// whatever the order and grouping; voxels beyond the reach stay at the background.
TEST(CrackGrid, TwistedStripsRecordedInSubStepsGiveTheExactDistance) {
    for (int axis = 0; axis < 3; ++axis) {
        // A front of 6 markers along the first in-plane direction; each sub-step moves every
        // marker along the second one by 0.6-1.1 r_f, and along the normal by a marker-dependent
        // amount (the twist).
        const int a0 = (axis + 1) % 3, a1 = (axis + 2) % 3;
        auto marker = [&](int i, int step) {
            Vec3 x = Vec3::Zero();
            x[a0] = (i - 2.5) * 1.7 * kRf;
            x[a1] = step * (0.6 + 0.1 * i) * kRf;
            x[axis] = 0.25 * kRf * std::sin(0.9 * i + 0.7 * step) + 0.05 * step * kRf * i;
            return x;
        };
        CrackRecorder rec(kRf);
        rec.add_crack();
        std::vector<Triangle3> all;
        for (int step = 0; step < 5; ++step) {
            FrontMotion m{{}, {}, false};
            for (int i = 0; i < 6; ++i) {
                m.p0.push_back(marker(i, step));
                m.p1.push_back(marker(i, step + 1));
            }
            const std::vector<Triangle3> tris = strip_triangles(m);
            ASSERT_EQ(tris.size(), 10u);
            rec.add_triangles(0, tris);
            all.insert(all.end(), tris.begin(), tris.end());
        }
        const LevelSet g = rec.snapshot().cracks[0];
        const double band = 3 * kRf, reach = band + kThick;
        std::size_t in_band = 0;
        double worst = 0;
        for (int i = -12; i <= 12; ++i)
            for (int j = -12; j <= 12; ++j)
                for (int k = -8; k <= 16; ++k) {
                    Vec3 p;
                    p[a0] = i * kRf;
                    p[axis] = j * kRf;
                    p[a1] = k * kRf;
                    double d = std::numeric_limits<double>::infinity();
                    for (const Triangle3& t : all) d = std::min(d, exact_triangle_distance(p, t[0], t[1], t[2]));
                    const double v = sample(g, p);  // a voxel centre: the voxel's own value
                    if (d < reach - 1e-6 * kRf) {
                        ++in_band;
                        worst = std::max(worst, std::abs(v - (d - kThick)));
                    } else if (d > reach + 1e-6 * kRf) {
                        EXPECT_EQ(v, float(band)) << "axis " << axis << " voxel " << i << " " << j << " " << k;
                    }
                }
        EXPECT_GT(in_band, 1000u) << "axis " << axis;
        EXPECT_LT(worst, 1e-5 * kRf) << "axis " << axis << ": worst deviation from the exact thickened distance [m]";
    }
}

TEST(CrackGrid, LongObliqueFanTriangleMatchesTheExactDistance) {
    const Triangle3 fan = {Vec3(0, 0, 0), Vec3(0.61, 0.43, 0.29), Vec3(0.63, 0.41, 0.31)};
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_triangles(0, {fan});
    const LevelSet g = rec.snapshot().cracks[0];
    const double band = 3 * kRf;  // half_width 3 (the recorder's default)
    const double reach = band + kThick;
    std::size_t in_band = 0;
    double worst = 0;
    for (int i = -6; i <= 38; ++i)
        for (int j = -6; j <= 28; ++j)
            for (int k = -6; k <= 22; ++k) {
                const Vec3 p(i * kRf, j * kRf, k * kRf);
                const double d = exact_triangle_distance(p, fan[0], fan[1], fan[2]);
                // At a voxel centre trilinear sampling returns the voxel's own value; voxels
                // never set hold the background, the band width.
                const double v = sample(g, p);
                if (d < reach - 1e-6 * kRf) {
                    ++in_band;
                    worst = std::max(worst, std::abs(v - (d - kThick)));
                } else if (d > reach + 1e-6 * kRf) {
                    EXPECT_EQ(v, float(band)) << "voxel " << i << " " << j << " " << k << " beyond the band, distance " << d;
                }
            }
    EXPECT_GT(in_band, 2000u);
    EXPECT_LT(worst, 1e-5 * kRf) << "worst deviation from the exact thickened distance [m]";  // float storage
}

TEST(CrackGrid, IncrementalRecordingEqualsRecordingEverythingAtOnce) {
    CrackRecorder inc(kRf), all(kRf);
    inc.add_crack();
    all.add_crack();
    std::vector<Triangle3> every;
    std::vector<std::size_t> per_step;
    for (int s = 0; s < 4; ++s) {
        const auto strip = strip_triangles(advance(-0.2 + 0.1 * s, -0.1 + 0.1 * s));
        std::size_t w = 0;
        inc.record_substep({advance(-0.2 + 0.1 * s, -0.1 + 0.1 * s)}, nullptr, &w);
        every.insert(every.end(), strip.begin(), strip.end());
        per_step.push_back(w);
    }
    all.add_triangles(0, every);
    const LevelSet a = inc.snapshot().cracks[0], b = all.snapshot().cracks[0];
    EXPECT_EQ(active_voxel_count(a), active_voxel_count(b));
    for (double x = -0.3; x <= 0.3; x += 0.013)
        for (double z = -0.07; z <= 0.07; z += 0.011) EXPECT_EQ(sample(a, Vec3(x, 0.05, z)), sample(b, Vec3(x, 0.05, z)));
    // Only the new strip is voxelised: equal strips cost the same work whatever the size of the
    // crack recorded so far. The count is the voxels a strip sets or lowers; from the second
    // sub-step on, part of each strip's band lies behind the front, where the earlier strips
    // are closer, so sub-steps 2, 3, 4 write the same number and the first writes more.
    EXPECT_GT(per_step[0], per_step[1]);
    EXPECT_NEAR(double(per_step[2]) / double(per_step[1]), 1.0, 0.05);
    EXPECT_NEAR(double(per_step[3]) / double(per_step[1]), 1.0, 0.05);
}

// Stopped markers (p1 == p0) sweep nothing new: their pairs give no triangles, and leaving them
// out does not change the grid, because their segment is the end edge of the previous strip.
// Next to a moving marker the strip's quad collapses to one triangle: the other half is a
// segment on its edge, and leaving it out does not change the grid either.
TEST(CrackGrid, StoppedMarkerPairsAddNothing) {
    FrontMotion second = advance(-0.1, 0.0);
    for (int i = 0; i < 6; ++i) second.p1[i] = second.p0[i];  // markers 0..5 stopped
    const auto tris = strip_triangles(second);
    // Pairs 0-1 .. 4-5 do not move; pair 5-6 sweeps one fan triangle from the stopped marker 5;
    // pairs 6-7 .. 11-12 sweep two triangles each.
    EXPECT_EQ(tris.size(), 1u + 2u * 6);
    std::vector<Triangle3> all = tris;
    all.push_back({second.p0[5], second.p1[6], second.p1[5]});  // the fan's collapsed other half
    for (int i = 0; i < 5; ++i) {  // what the stopped pairs would add: degenerate triangles
        all.push_back({second.p0[i], second.p0[i + 1], second.p1[i + 1]});
        all.push_back({second.p0[i], second.p1[i + 1], second.p1[i]});
    }
    CrackRecorder skipped(kRf), full(kRf);
    for (CrackRecorder* r : {&skipped, &full}) {
        r->add_crack();
        r->add_triangles(0, strip_triangles(advance(-0.2, -0.1)));
    }
    skipped.add_triangles(0, tris);
    full.add_triangles(0, all);
    const LevelSet a = skipped.snapshot().cracks[0], b = full.snapshot().cracks[0];
    EXPECT_EQ(active_voxel_count(a), active_voxel_count(b));
    double worst = 0;
    for (double x = -0.25; x <= 0.05; x += 0.0031)
        for (double y = -0.35; y <= 0.35; y += 0.0137)
            for (double z = -0.07; z <= 0.07; z += 0.0071)
                worst = std::max(worst, std::abs(sample(a, Vec3(x, y, z)) - sample(b, Vec3(x, y, z))));
    EXPECT_LT(worst, 1e-6 * kRf);
    // A lone stopped marker sweeps nothing either.
    EXPECT_TRUE(strip_triangles(FrontMotion{{Vec3(0, 0, 0)}, {Vec3(0, 0, 0)}, false}).empty());
}

TEST(CrackGrid, ParallelRecordingAcrossCracksIsIndependentOfThreadCount) {
    auto run = [](int threads) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        CrackRecorder rec(kRf);
        std::vector<FrontMotion> motions;
        for (int c = 0; c < 4; ++c) {
            rec.add_crack();
            FrontMotion m = advance(-0.2, 0.1);
            for (auto* v : {&m.p0, &m.p1})
                for (Vec3& p : *v) p.z() += 0.2 * c;
            motions.push_back(m);
        }
        rec.record_substep(motions, nullptr);
        return rec.release();
    };
    const CrackLevelSets one = run(1), two = run(2);
    ASSERT_EQ(one.cracks.size(), 4u);
    for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(active_voxel_count(one.cracks[c]), active_voxel_count(two.cracks[c]));
        for (double x = -0.25; x <= 0.15; x += 0.017)
            EXPECT_EQ(sample(one.cracks[c], Vec3(x, 0.1, 0.2 * c + 0.01)), sample(two.cracks[c], Vec3(x, 0.1, 0.2 * c + 0.01)));
        EXPECT_NEAR(sample(one.cracks[c], Vec3(0, 0, 0.2 * c)), -kThick, 1e-6);
    }
}

TEST(CrackGrid, OneStripRecordedInParallelIsIndependentOfThreadCount) {
    // One crack, one wide curved strip: its leaf-sized blocks are rasterised in parallel and
    // merged by min, so 1 and 2 threads must give the same grid. The count is the number of
    // band voxels, each once: on an empty grid, exactly the voxels it activates.
    auto run = [](int threads, std::size_t* count) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        FrontMotion m;
        m.closed = true;
        for (int i = 0; i < 48; ++i) {
            const double a = 2 * M_PI * i / 48;
            m.p0.emplace_back(0.2 * std::cos(a), 0.2 * std::sin(a), 0.02 * std::sin(3 * a));
            m.p1.emplace_back(0.3 * std::cos(a), 0.3 * std::sin(a), 0.05 * std::sin(3 * a));
        }
        CrackRecorder rec(kRf);
        rec.add_crack();
        *count = rec.add_triangles(0, strip_triangles(m));
        return rec.release().cracks[0];
    };
    std::size_t n1 = 0, n2 = 0;
    const LevelSet one = run(1, &n1), two = run(2, &n2);
    EXPECT_EQ(n1, n2);
    EXPECT_EQ(n1, active_voxel_count(one));
    EXPECT_EQ(active_voxel_count(one), active_voxel_count(two));
    int compared = 0;
    for (double x = -0.33; x <= 0.33; x += 0.0123)
        for (double y = -0.33; y <= 0.33; y += 0.0131)
            for (double z = -0.09; z <= 0.09; z += 0.017) {
                const double a = sample(one, Vec3(x, y, z)), b = sample(two, Vec3(x, y, z));
                EXPECT_EQ(a, b) << x << " " << y << " " << z;
                compared += a < 3 * kRf;
            }
    EXPECT_GT(compared, 1000);  // many samples inside the band
}

TEST(MarkerTest, LeftTheObject) {
    const LevelSet object = level_set_from_mesh(testmesh::box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}), kRf);
    EXPECT_EQ(test_marker(&object, {}, -1, Vec3(0.4, 0, 0), Vec3(0.49, 0, 0)).hit, MarkerHit::none);
    EXPECT_EQ(test_marker(&object, {}, -1, Vec3(0.45, 0, 0), Vec3(0.52, 0, 0)).hit, MarkerHit::left_object);
}

TEST(MarkerTest, CrossingAnotherCrackIsFoundEvenWhenBothEndsAreOutsideIt) {
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_triangles(0, strip_triangles(advance(-0.2, 0.2)));  // sheet at z = 0
    const std::vector<LevelSet> cracks = rec.snapshot().cracks;
    // Grazing: endpoints 2.5 r_f above/below the sheet (outside its sqrt(3) r_f thin volume).
    const MarkerTest t = test_marker(nullptr, cracks, 1, Vec3(0.05, 0, 0.05), Vec3(0.05, 0, -0.05));
    EXPECT_EQ(t.hit, MarkerHit::crossed_crack);
    EXPECT_EQ(t.other_crack, 0);
    EXPECT_NEAR(t.alpha, 0.5, 0.2);
    // Oblique crossing, nearly parallel: 1 r_f drop over 20 r_f of travel.
    EXPECT_EQ(test_marker(nullptr, cracks, 1, Vec3(-0.18, 0.1, 0.5 * kRf + kThick), Vec3(0.18, 0.1, -0.5 * kRf - kThick)).hit,
              MarkerHit::crossed_crack);
    // Parallel at 1.5 thickness: no crossing. Beyond the sheet's edge: none.
    EXPECT_EQ(test_marker(nullptr, cracks, 1, Vec3(-0.1, 0, 1.5 * kThick), Vec3(0.1, 0, 1.5 * kThick)).hit, MarkerHit::none);
    EXPECT_EQ(test_marker(nullptr, cracks, 1, Vec3(0.3, 0, 0.05), Vec3(0.3, 0, -0.05)).hit, MarkerHit::none);
    // The marker's own crack is not "another" crack.
    EXPECT_NE(test_marker(nullptr, cracks, 0, Vec3(0.05, 0, 0.05), Vec3(0.05, 0, -0.05)).hit, MarkerHit::crossed_crack);
}

TEST(MarkerTest, SelfIntersectionByEquation62) {
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_triangles(0, strip_triangles(advance(-0.2, 0.2)));
    const std::vector<LevelSet> own = rec.snapshot().cracks;
    // A marker of the same crack, away from the sheet, heading back into it: hit.
    const MarkerTest back = test_marker(nullptr, own, 0, Vec3(0, 0, 0.2), Vec3(0, 0, -0.01));
    EXPECT_EQ(back.hit, MarkerHit::self_intersection);
    // Leaving the sheet perpendicular from on it: Phi_f(p0) < 0, moving away: no hit.
    EXPECT_EQ(test_marker(nullptr, own, 0, Vec3(0, 0, 0), Vec3(0, 0, 0.2)).hit, MarkerHit::none);
    // Propagating forward in the plane from the front edge: no hit.
    EXPECT_EQ(test_marker(nullptr, own, 0, Vec3(0.2, 0, 0), Vec3(0.26, 0, 0)).hit, MarkerHit::none);
    // Kinking by 30 degrees out of the plane at the front: no hit (within the 45-degree cone).
    EXPECT_EQ(test_marker(nullptr, own, 0, Vec3(0.2, 0, 0), Vec3(0.2 + 0.06 * std::cos(0.52), 0, 0.06 * std::sin(0.52))).hit,
              MarkerHit::none);
}

// Markers whose whole sub-step stays inside their recorded sheet (behind the recorded front:
// between neighbours that ran ahead, or on the chord of a curved initial crack) never left the
// crack, so they cannot run back into it. On an oblique sheet, trilinear Phi_f varies between
// about -0.87 r_f and -0.4 r_f along the sheet and its gradient points every way in the plane;
// eq. (6.2) on its own flagged such moves once phi = Phi_f(p0) + |x - p0| sin 45 turned
// positive. A marker starting just off the sheet (Phi_f(p0) >= 0) and heading into it is hit.
TEST(MarkerTest, PathsInsideTheRecordedSheetAreNotSelfIntersections) {
    // An oblique sheet through the origin: normal (-0.3, -0.17, 1) normalised.
    const Vec3 n = Vec3(-0.3, -0.17, 1).normalized();
    const Vec3 a = Vec3(1, 0, 0.3).normalized(), b = n.cross(a);
    std::vector<Vec3> f0, f1;
    for (int i = 0; i <= 20; ++i) {
        const double t = -0.2 + 0.4 * i / 20;
        f0.push_back(-0.2 * a + t * b);
        f1.push_back(0.2 * a + t * b);
    }
    CrackRecorder rec(kRf, 2);  // the fracture loop's default 2-voxel band
    rec.add_crack();
    rec.add_triangles(0, strip_triangles(FrontMotion{f0, f1, false}));
    const std::vector<LevelSet> own = rec.snapshot().cracks;
    int moves = 0, hits = 0;
    double phi_max = -1;
    for (int i = -6; i <= 6; ++i)
        for (int j = -6; j <= 6; ++j) {
            const Vec3 p0 = (0.011 * i) * a + (0.013 * j) * b;
            phi_max = std::max(phi_max, sample(own[0], p0) / kRf);
            for (int k = 0; k < 8; ++k) {  // in-plane directions, 0.85 r_f, slightly tilted
                const double phi = 2 * M_PI * k / 8;
                const Vec3 d = 0.85 * kRf * (std::cos(phi) * a + std::sin(phi) * b + 0.05 * (k % 2 ? 1 : -1) * n);
                hits += test_marker(nullptr, own, 0, p0, p0 + d).hit == MarkerHit::self_intersection;
                ++moves;
            }
        }
    EXPECT_GT(phi_max, -0.6) << "the sheet must give the trilinear plateau that made eq. (6.2) misfire";
    EXPECT_EQ(hits, 0) << "of " << moves << " in-sheet moves";
    // Just off the sheet (1.2 r_f above it, Phi_f(p0) = 0.33 r_f) and heading into it: hit.
    const Vec3 above = 1.2 * kRf * n;
    EXPECT_GE(sample(own[0], above), 0.0);
    EXPECT_EQ(test_marker(nullptr, own, 0, above, above - 2.0 * kRf * n).hit, MarkerHit::self_intersection);
}

TEST(MarkerTest, RecordSubstepReportsWhichCaseHitAndStillRecords) {
    const LevelSet object = level_set_from_mesh(testmesh::box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}), kRf);
    CrackRecorder rec(kRf);
    rec.add_crack();
    rec.add_crack();
    rec.add_triangles(0, strip_triangles(advance(-0.2, 0.2)));  // crack 0: sheet at z = 0
    // Crack 1: a front in the plane x = 0.1 moving down through crack 0; one marker also leaves
    // the object at the end; crack 0 grows in its plane.
    FrontMotion down{{Vec3(0.1, -0.1, 0.06), Vec3(0.1, 0.0, 0.06), Vec3(0.1, 0.45, 0.06)},
                     {Vec3(0.1, -0.1, 0.06), Vec3(0.1, 0.0, -0.04), Vec3(0.1, 0.55, 0.06)}, false};
    std::size_t written = 0;
    const auto tests = rec.record_substep({advance(0.2, 0.25), down}, &object, &written);
    ASSERT_EQ(tests.size(), 2u);
    for (const MarkerTest& t : tests[0]) EXPECT_EQ(t.hit, MarkerHit::none);
    EXPECT_EQ(tests[1][0].hit, MarkerHit::none);  // did not move
    EXPECT_EQ(tests[1][1].hit, MarkerHit::crossed_crack);
    EXPECT_EQ(tests[1][1].other_crack, 0);
    EXPECT_EQ(tests[1][2].hit, MarkerHit::left_object);
    EXPECT_STREQ(to_string(tests[1][2].hit), "left_object");
    EXPECT_GT(written, 0u);
    const CrackLevelSets s = rec.snapshot();
    EXPECT_LT(sample(s.cracks[0], Vec3(0.24, 0, 0)), 0);   // crack 0 grew to x = 0.25
    EXPECT_LT(sample(s.cracks[1], Vec3(0.1, 0.0, 0.0)), 0);  // crack 1 recorded its strip
}

// record_substep skips, in test (b), a crack whose recorded voxels lie farther than r_f from a
// marker's path (a box per crack); that must decide exactly as test_marker on the grids does. Three
// cracks (sheets at z = 0, x = 0.1 and y = 0.25, the last two also recorded in a recorder started
// from the grids, whose boxes come from the grids' leaves), and 400 random short paths around their
// edges, many ending just inside or just beyond a sheet's thickness.
TEST(MarkerTest, CrackBoxesDecideAsTheGridsDo) {
    CrackRecorder first(kRf);
    for (int c = 0; c < 3; ++c) first.add_crack();
    first.add_triangles(0, strip_triangles(advance(-0.2, 0.2)));
    first.add_triangles(1, strip_triangles(FrontMotion{{Vec3(0.1, -0.3, -0.3), Vec3(0.1, 0.3, -0.3)},
                                                         {Vec3(0.1, -0.3, -0.1), Vec3(0.1, 0.3, -0.1)}, false}));
    CrackRecorder rec(first.snapshot());  // boxes from the grids' leaves
    // Crack 2 recorded in this recorder (box from its triangles): y = 0.25, x in [0.3, 0.5].
    rec.add_triangles(2, strip_triangles(FrontMotion{{Vec3(0.3, 0.25, -0.2), Vec3(0.3, 0.25, 0.2)},
                                                       {Vec3(0.5, 0.25, -0.2), Vec3(0.5, 0.25, 0.2)}, false}));
    std::uint64_t state = 12345;
    auto uniform = [&](double lo, double hi) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return lo + (hi - lo) * double(state >> 11) / double(1ULL << 53);
    };
    // Crack 0's front does not move (one still marker); the paths are its markers' motions.
    FrontMotion probes;
    for (int i = 0; i < 400; ++i) {
        const Vec3 p0(uniform(-0.3, 0.6), uniform(-0.4, 0.4), uniform(-0.35, 0.1));
        const Vec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        probes.p0.push_back(p0);
        probes.p1.push_back(p0 + uniform(0.2, 1.0) * kRf * d.normalized());
    }
    const CrackLevelSets grids = rec.snapshot();
    int crossed = 0;
    std::vector<MarkerTest> expected(probes.p0.size());
    for (std::size_t i = 0; i < probes.p0.size(); ++i) {
        expected[i] = test_marker(nullptr, grids.cracks, 0, probes.p0[i], probes.p1[i]);
        crossed += expected[i].hit == MarkerHit::crossed_crack;
    }
    EXPECT_GT(crossed, 10) << "the paths must reach the other cracks";
    const auto tests = rec.record_substep({probes, FrontMotion{}, FrontMotion{}}, nullptr);
    for (std::size_t i = 0; i < probes.p0.size(); ++i) {
        EXPECT_EQ(tests[0][i].hit, expected[i].hit) << "path " << i;
        EXPECT_EQ(tests[0][i].other_crack, expected[i].other_crack) << "path " << i;
        EXPECT_EQ(tests[0][i].alpha, expected[i].alpha) << "path " << i;
    }
}

TEST(CrackGridErrors, PlanarCrackRejectsBadParameters) {
    EXPECT_THROW(planar_disk_crack(Vec3::Zero(), Vec3::UnitZ(), 0, kRf), std::invalid_argument);
    EXPECT_THROW(planar_disk_crack(Vec3::Zero(), Vec3::Zero(), 0.1, kRf), std::invalid_argument);
    CrackRecorder rec(kRf);
    EXPECT_THROW(rec.record_substep({advance(0, 0.1)}, nullptr), std::invalid_argument);  // no crack 0
}

TEST(CrackGrid, PlanarDiskMatchesTheDiskDistance) {
    const Vec3 n = Vec3(1, 1, 0.5).normalized();
    const LevelSet disk = planar_disk_crack(Vec3(0.1, 0, 0), n, 0.3, kRf);
    const Vec3 e = n.cross(Vec3::UnitZ()).normalized();  // in-plane direction
    EXPECT_NEAR(sample(disk, Vec3(0.1, 0, 0) + 0.02 * n), 0.02 - kThick, 0.02 * kRf);
    EXPECT_NEAR(sample(disk, Vec3(0.1, 0, 0) + 0.15 * e - 0.03 * n), 0.03 - kThick, 0.02 * kRf);
    // Beyond the rim: distance to the circle, r - R (sag below r_f / 10).
    EXPECT_NEAR(sample(disk, Vec3(0.1, 0, 0) + 0.34 * e), 0.04 - kThick, 0.12 * kRf);
}

}  // namespace
}  // namespace cf
