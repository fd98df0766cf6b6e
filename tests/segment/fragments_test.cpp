// Fragments (ch. 6.3): verification cases 9-11 as tests, plus the over-segmentation threshold
// range, the tile-aware search against the plain one, listings and bad inputs.
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/segment/fragments.hpp"
#include "nodes/segment/fracture_faces.hpp"
#include "nodes/segment/fragment_mesher.hpp"
#include "nodes/segment/levelset_verification.hpp"
#include "tests/harness/expect_error.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace cf {
namespace {

constexpr double kRf = 0.02;

LevelSet cube() { return level_set_from_mesh(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), kRf); }

std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

TEST(VerificationCase, planar_cut_two_fragments) {
    const VerificationResult r = verify_planar_cut_two_fragments();
    EXPECT_TRUE(r.passed) << r.details << " error " << r.error << " tol " << r.tolerance;
    std::cout << "[case 9] " << r.details << "; rel. error " << r.error << " (bar " << r.tolerance << ")\n";
}

TEST(VerificationCase, interior_crack_one_fragment) {
    const VerificationResult r = verify_interior_crack_one_fragment();
    EXPECT_TRUE(r.passed) << r.details << " error " << r.error << " tol " << r.tolerance;
    std::cout << "[case 10] " << r.details << "; error " << r.error << " (bar " << r.tolerance << ")\n";
}

TEST(VerificationCase, spindle_removed) {
    const VerificationResult r = verify_spindle_removed();
    EXPECT_TRUE(r.passed) << r.details << " error " << r.error << " tol " << r.tolerance;
    std::cout << "[case 11] " << r.details << "; error " << r.error << " (bar " << r.tolerance << ")\n";
}

// The level-set mesher's fracture faces: a unit cube cut at z = 0.031 by a plane crack. Each half's
// dual-contoured mesh has the 1 m^2 section as its fracture face (region "inside") and its part of
// the cube's surface as the rest: bottom or top (1 m^2) plus four side strips of heights
// 0.5 +- z - t (t = sqrt(3) r_f / 2, the thickened crack's half gap). Bounds: the crack faces within
// half a voxel of the cube's sides read as outside (a strip 0.5 r_f wide along the 4 m of the
// section's rim), and dual contouring rounds the rims by about a voxel: 4 m x 1.5 r_f.
TEST(Fragments, LevelSetMeshesTellFractureFacesFromTheObjectsSurface) {
    const double z = 0.031, t = std::sqrt(3.0) * kRf / 2;
    const LevelSet obj = cube();
    Fragments f = find_fragments(broken_object(obj, {kRf, 3, {planar_disk_crack(Vec3(0, 0, z), Vec3::UnitZ(), 1, kRf)}}));
    ASSERT_EQ(f.fragments.size(), 2u);
    f.object = obj;
    const FragmentMesher mesher(f, FragmentMesherOptions{});
    const double rim = 4 * 1.5 * kRf;
    const double side_heights[2] = {0.5 + z - t, 0.5 - z - t};  // lower (largest) then upper half
    for (std::size_t i = 0; i < 2; ++i) {
        const SurfaceMesh m = mesher.mesh(i);
        ASSERT_EQ(m.region_names, (std::vector<std::string>{"outside", "inside"}));
        EXPECT_TRUE(std::is_sorted(m.region.begin(), m.region.end())) << "outside faces first, then inside ones";
        EXPECT_NEAR(region_area(m, "inside"), 1.0, rim) << "fragment " << i;
        EXPECT_NEAR(region_area(m, "outside"), 1.0 + 4 * side_heights[i], rim) << "fragment " << i;
        // Every inside face lies in the crack's gap, every outside face on the cube's surface.
        for (std::size_t k = 0; k < m.num_triangles(); ++k) {
            const Vec3 c = triangle_centroid(m, k);
            if (m.region_of(k) == 1) EXPECT_NEAR(std::abs(c.z() - z), t, 0.5 * kRf) << "face " << k;
            else EXPECT_LT(0.5 - c.cwiseAbs().maxCoeff(), 0.75 * kRf) << "face " << k;
        }
    }
    // Without cracks the object is one fragment with no fracture faces.
    Fragments whole = find_fragments(obj);
    whole.object = obj;
    ASSERT_EQ(whole.fragments.size(), 1u);
    EXPECT_EQ(region_area(FragmentMesher(whole, FragmentMesherOptions{}).mesh(0), "inside"), 0.0);
    SurfaceMesh m = FragmentMesher(whole, FragmentMesherOptions{}).mesh(0);
    EXPECT_THROW(tag_fracture_faces(m, obj, 0), std::invalid_argument);
    EXPECT_THROW(tag_fracture_faces(m, obj, std::nan("")), std::invalid_argument);
}

// tag_fracture_faces reorders in chunks on parallel tasks: the result is one serial pass's order
// (outside faces first, then inside ones, each in its old order, with their UVs and normals), here
// for 200 000 faces (7 chunks) whose depth changes in runs of random length across chunk borders.
TEST(Fragments, FractureFacesReorderedAsOneSerialPass) {
    const LevelSet obj = cube();
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-0.45, 0.45);
    SurfaceMesh m;
    const std::size_t n = 200000;
    bool deep = false;
    std::size_t run = 0;
    for (std::size_t t = 0; t < n; ++t) {
        if (run == 0) {
            deep = !deep;
            run = 1 + std::size_t(rng() % 50000);
        }
        --run;
        // A small triangle around a point deep inside (|x| < 0.3) or on the surface (x = 0.5).
        const Vec3 c(deep ? 0.6 * u(rng) : 0.5, u(rng), u(rng));
        const int v = int(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {c + Vec3(1e-3, 0, 0), c + Vec3(0, 1e-3, 0), c + Vec3(0, 0, 1e-3)});
        m.triangles.push_back({v, v + 1, v + 2});
        m.corner_uv.push_back({Vec2(double(t), 0), Vec2(0, double(t)), Vec2(1, 1)});
        m.corner_normal.push_back({Vec3(double(t), 0, 0), Vec3::UnitY(), Vec3::UnitZ()});
    }
    std::vector<Vec3> centroids;
    for (std::size_t t = 0; t < n; ++t) centroids.push_back(triangle_centroid(m, t));
    const std::vector<double> phi = sample_points(obj, centroids);
    SurfaceMesh expected = m;
    expected.triangles.clear();
    expected.corner_uv.clear();
    expected.corner_normal.clear();
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t t = 0; t < n; ++t)
            if ((phi[t] < -kRf) == (pass == 1)) {
                expected.triangles.push_back(m.triangles[t]);
                expected.corner_uv.push_back(m.corner_uv[t]);
                expected.corner_normal.push_back(m.corner_normal[t]);
            }
    const std::size_t outside = std::size_t(std::count_if(phi.begin(), phi.end(), [](double p) { return !(p < -kRf); }));
    ASSERT_GT(outside, n / 4);
    ASSERT_LT(outside, 3 * n / 4);
    for (int threads : {1, 2}) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        SurfaceMesh got = m;
        tag_fracture_faces(got, obj, kRf);
        EXPECT_TRUE(got.triangles == expected.triangles) << threads << " threads";
        EXPECT_TRUE(got.corner_uv == expected.corner_uv) << threads << " threads";
        EXPECT_TRUE(got.corner_normal == expected.corner_normal) << threads << " threads";
        ASSERT_EQ(got.region.size(), n);
        EXPECT_EQ(std::size_t(std::count(got.region.begin(), got.region.end(), 0)), outside);
        EXPECT_TRUE(std::is_sorted(got.region.begin(), got.region.end()));
    }
}

TEST(Fragments, PlanarCutVolumesCentroidsAndBoxesMatchTheHalves) {
    const double z = 0.031, t = std::sqrt(3.0) * kRf / 2;
    const LevelSet obj = cube();
    const Fragments f = find_fragments(broken_object(obj, {kRf, 3, {planar_disk_crack(Vec3(0, 0, z), Vec3::UnitZ(), 1, kRf)}}));
    ASSERT_EQ(f.fragments.size(), 2u);
    // Largest first: the lower part z in [-0.5, z - t], then the upper part [z + t, 0.5].
    const double v_low = (z - t + 0.5), v_up = (0.5 - z - t);
    const double layer = 1.0 * kRf;  // one voxel layer over the 1 m^2 section
    EXPECT_NEAR(f.fragments[0].volume, v_low, layer);
    EXPECT_NEAR(f.fragments[1].volume, v_up, layer);
    EXPECT_NEAR(f.fragments[0].centroid.z(), (-0.5 + z - t) / 2, 0.5 * kRf);
    EXPECT_NEAR(f.fragments[1].centroid.z(), (0.5 + z + t) / 2, 0.5 * kRf);
    EXPECT_NEAR(f.fragments[0].centroid.x(), 0, 0.1 * kRf);
    EXPECT_NEAR(f.fragments[0].bbox.max.z(), z - t, kRf);
    EXPECT_NEAR(f.fragments[1].bbox.min.z(), z + t, kRf);
    EXPECT_NEAR(f.fragments[1].bbox.max.x(), 0.5, kRf);
    // Each fragment's grid is a proper level set of its part alone.
    EXPECT_LT(sample(f.fragments[1].grid, Vec3(0, 0, 0.3)), 0);
    EXPECT_GT(sample(f.fragments[1].grid, Vec3(0, 0, -0.3)), 0);
}

// Degenerate cracks, one scope each: none at all, one that stays inside, one of zero area, and a
// threshold of zero.
TEST(Fragments, EdgeCases) {
    const LevelSet obj = cube();
    const double t = crack_half_thickness(kRf);
    {
        SCOPED_TRACE("no cracks: one fragment, the whole 1 m^3 cube");
        const Fragments f = find_fragments(broken_object(obj, {kRf, 3, {}}));
        ASSERT_EQ(f.fragments.size(), 1u);
        EXPECT_NEAR(f.fragments[0].volume, 1.0, kRf);
    }
    {
        SCOPED_TRACE("a crack that stays inside the object splits nothing; its slab is not part of the fragment");
        const Fragments f = find_fragments(broken_object(obj, {kRf, 3, {planar_disk_crack(Vec3::Zero(), Vec3::UnitZ(), 0.2, kRf)}}));
        ASSERT_EQ(f.fragments.size(), 1u);
        const double slab = M_PI * 0.2 * 0.2 * 2 * t;  // the disk's recorded thickness
        EXPECT_NEAR(f.fragments[0].volume, 1.0 - slab, 0.5 * slab);
    }
    {
        SCOPED_TRACE("a crack of zero area (one point) splits nothing");
        CrackRecorder rec(kRf);
        rec.add_crack();
        const Vec3 p = kRf * Vec3(3, 1, -2);
        rec.add_triangles(0, {Triangle3{p, p, p}});
        const Fragments f = find_fragments(broken_object(obj, rec.release()));
        ASSERT_EQ(f.fragments.size(), 1u);
        EXPECT_NEAR(f.fragments[0].volume, 1.0, kRf);
    }
    {
        SCOPED_TRACE("threshold s = 0 still separates the two halves of a through cut");
        const Fragments f = find_fragments(broken_object(obj, {kRf, 3, {planar_disk_crack(Vec3(0, 0, 0.031), Vec3::UnitZ(), 1, kRf)}}),
                                           SegmentOptions{0.0, true});
        EXPECT_EQ(f.fragments.size(), 2u);
    }
}

TEST(Fragments, SpecksBelowTheMinimumVolumeAreDropped) {
    const double z = 0.031;
    const LevelSet obj = cube();
    Fragments f = find_fragments(broken_object(obj, {kRf, 3, {planar_disk_crack(Vec3(0, 0, z), Vec3::UnitZ(), 1, kRf)}}));
    ASSERT_EQ(f.fragments.size(), 2u);
    const double big = f.fragments[0].volume, small = f.fragments[1].volume;
    ASSERT_LT(small, big);
    Fragments keep = f;
    EXPECT_EQ(drop_small_fragments(keep, 0.0), 0u);  // 0 keeps everything
    EXPECT_EQ(keep.fragments.size(), 2u);
    double removed = 0;
    EXPECT_EQ(drop_small_fragments(f, 0.5 * (small + big), &removed), 1u);
    ASSERT_EQ(f.fragments.size(), 1u);
    EXPECT_EQ(f.fragments[0].volume, big);
    EXPECT_EQ(removed, small);  // the volume accounted for exactly
    EXPECT_THROW(drop_small_fragments(f, -1.0), std::invalid_argument);
}

TEST(Fragments, WithoutTilesTheInteriorCrackIsLost) {
    // r_f = 0.01 m: the crack's leaves (radius 0.1 m) are separated from the surface's leaves by
    // interior tiles, so only the tile-aware search can connect them.
    const double r_f = 0.01;
    const LevelSet obj = level_set_from_mesh(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), r_f);
    const LevelSet broken = broken_object(obj, {r_f, 3, {planar_disk_crack(Vec3::Zero(), Vec3::UnitZ(), 0.1, r_f)}});
    const Fragments tiles = find_fragments(broken, SegmentOptions{-1, true});
    const Fragments plain = find_fragments(broken, SegmentOptions{-1, false});
    EXPECT_EQ(tiles.fragments.size(), 1u);
    // The plain voxel search cannot cross the interior tiles: the shell and the crack's
    // surroundings come out as separate components (ch. 6.3).
    EXPECT_GE(plain.fragments.size(), 2u);
}

TEST(Fragments, ResultIndependentOfThreadCount) {
    auto run = [](int threads) {
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
        return find_fragments(broken_object(cube(), {kRf, 3, {planar_disk_crack(Vec3(0, 0.1, 0), Vec3(0.2, 1, 0.1), 1, kRf)}}));
    };
    const Fragments a = run(1), b = run(2);
    ASSERT_EQ(a.fragments.size(), b.fragments.size());
    for (std::size_t i = 0; i < a.fragments.size(); ++i) {
        EXPECT_EQ(a.fragments[i].volume, b.fragments[i].volume);
        EXPECT_EQ(a.fragments[i].active_voxels, b.fragments[i].active_voxels);
    }
}

TEST(Fragments, ThresholdOutOfRangeIsRejectedWithTheReason) {
    const LevelSet broken = broken_object(cube(), {kRf, 3, {planar_disk_crack(Vec3::Zero(), Vec3::UnitZ(), 1, kRf)}});
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { find_fragments(broken, SegmentOptions{1.5 * kRf, true}); },
                                                           {"[0, r_f]", "0.02"}));
    EXPECT_EQ(over_segmentation_ring(0, kRf), 1);
    EXPECT_EQ(over_segmentation_ring(kRf, kRf), 2);
    EXPECT_EQ(over_segmentation_ring(0.4 * kRf, kRf), 1);
}

TEST(Fragments, EmptyOrOutsideCracksAreRejected) {
    CrackRecorder rec(kRf);
    rec.add_crack();
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { broken_object(cube(), rec.release()); },
        {"crack 0 is empty"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { broken_object(cube(), {kRf, 3, {planar_disk_crack(Vec3(3, 0, 0), Vec3::UnitZ(), 0.2, kRf)}}); },
        {"outside the object"}));
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { broken_object(cube(), {0.01, 3, {planar_disk_crack(Vec3::Zero(), Vec3::UnitZ(), 0.2, 0.01)}}); },
        {"same r_f"}));
}

TEST(Fragments, ListingsHoldOneRowPerFragment) {
    const Fragments f = find_fragments(broken_object(cube(), {kRf, 3, {planar_disk_crack(Vec3::Zero(), Vec3::UnitX(), 1, kRf)}}));
    const auto dir = std::filesystem::temp_directory_path() / "cf_fragments_listing";
    std::filesystem::remove_all(dir);
    write_fragments_csv(dir / "fragments.csv", f);
    write_fragments_json(dir / "fragments.json", f);
    const std::string csv = slurp(dir / "fragments.csv"), json = slurp(dir / "fragments.json");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);  // header + 2 rows
    EXPECT_EQ(csv.rfind("index,volume_m3", 0), 0u);
    EXPECT_NE(json.find("\"index\": 1"), std::string::npos);
    EXPECT_NE(json.find("\"tile_aware\": true"), std::string::npos);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cf

// A partial crack cut into a box leaves one fragment with a thin slit (eq. 6.1); filling the slits
// of the cracks a fragment keeps (ch. 7.3, incomplete cracks) gives the box back: inside on the
// crack plane, the volume of the uncut box within one voxel layer of the crack area, and nothing
// added outside the box where the crack's grid reaches past its surface.
TEST(FillCrackSlits, AnIncompleteCracksSlitIsFilledWhereTheFragmentSurroundsIt) {
    const double r_f = 0.02;
    const cf::LevelSet object = cf::level_set_from_mesh(cf::testmesh::box(cf::Vec3(-0.5, -0.5, -0.5), cf::Vec3(0.5, 0.5, 0.5)), r_f);
    cf::CrackLevelSets cracks;
    cracks.voxel_size = r_f;
    cracks.cracks.push_back(cf::planar_disk_crack(cf::Vec3(-0.5, 0, 0), cf::Vec3(0, 0, 1), 0.6, r_f));  // from the x_min face inward
    const cf::Fragments f = cf::find_fragments(cf::broken_object(object, cracks));
    ASSERT_EQ(f.fragments.size(), 1u);
    const cf::LevelSet& cut = f.fragments[0].grid;
    const cf::Vec3 on_crack(-0.2, 0.0, 0.0);
    EXPECT_GT(cf::sample(cut, on_crack), 0) << "segmentation cut the slit";
    const cf::LevelSet filled = cf::fill_crack_slits(cut, object, cracks.cracks);
    EXPECT_LT(cf::sample(filled, on_crack), -0.5 * r_f);
    EXPECT_GT(cf::sample(filled, cf::Vec3(-0.5 - 1.5 * r_f, 0, 0)), 0) << "nothing added outside the box";
    const double crack_area_inside = 0.6 * 0.6 * 3.14159265358979 / 2;  // half disk inside the box (x > -0.5)
    // Volumes of the zero surfaces (OpenVDB's LevelSetMeasure misreads grids whose inactive values came
    // from segmentation: 1.07 m^3 for the cut box).
    const double v_object = cf::signed_volume(cf::level_set_to_mesh(object));
    const double v_cut = cf::signed_volume(cf::level_set_to_mesh(cut));
    const double v_filled = cf::signed_volume(cf::level_set_to_mesh(filled));
    EXPECT_NEAR(v_filled, v_object, crack_area_inside * r_f);
    EXPECT_LT(v_cut, v_filled - 0.5 * crack_area_inside * r_f) << "the slit (sqrt(3) r_f thick) is gone";
}
