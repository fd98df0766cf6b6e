// Material fields (thesis ch. 4.5.3) against closed forms and hand-computed values.
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/fields/grid_fields.hpp"
#include "vdb_fixture.hpp"
#include "tests/harness/expect_error.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <fstream>
#include <random>

namespace cf {
namespace {

// A scratch directory of the test's own (the process id in its name: ctest runs the tests of this
// file concurrently, and two test runs may share the machine), removed when the test ends (every run
// left three directories behind in /tmp before).
class ScratchDir {
public:
    explicit ScratchDir(const std::string& tag)
        : path_(std::filesystem::temp_directory_path() / ("cf_fields_" + tag + "_" + std::to_string(::getpid()))) {
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

TEST(HomogeneousField, ValueAndZeroGradient) {
    const ScalarField f = make_field(std::make_shared<HomogeneousField>(5e5), FieldQuantity::toughness, 2);
    EXPECT_EQ(f.value(Vec3(1, -2, 3)), 5e5);
    EXPECT_EQ(f.gradient(Vec3(1, -2, 3)), Vec3::Zero());
    EXPECT_EQ(f.compressive_value(Vec3::Zero()), 1e6);
}

TEST(LayeredField, GradientMatchesCentralDifferences) {
    const LayeredField f(1e6, 3e5, 40.0, Vec3(1, 2, -2));  // l = (1,2,-2)/3
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    for (int n = 0; n < 50; ++n) {
        const Vec3 p(u(rng), u(rng), u(rng));
        const double h = 1e-6;
        Vec3 fd;
        for (int k = 0; k < 3; ++k) {
            Vec3 e = Vec3::Zero();
            e[k] = h;
            fd[k] = (f.value(p + e) - f.value(p - e)) / (2 * h);
        }
        // |grad| <= b f = 1.2e7; central differences err O(h^2 b f^3) ~ 1e-5 plus rounding ~1e6*1e-16/1e-6.
        EXPECT_LT((fd - f.gradient(p)).norm(), 1e-6 * 1.2e7) << "at " << p.transpose();
    }
}

TEST(LayeredField, ExtremaAreAPlusMinusB) {
    const double a = 1e6, b = 3e5, freq = 40;
    const Vec3 l = Vec3(0, 3, 4) / 5;
    const LayeredField f(a, b, freq, Vec3(0, 3, 4));
    EXPECT_DOUBLE_EQ(f.value(Vec3::Zero()), a - b);                    // cos 0 = 1: minimum
    EXPECT_NEAR(f.value(M_PI / freq * l), a + b, 1e-9 * a);            // cos pi = -1: maximum
    EXPECT_NEAR(f.value(2 * M_PI / freq * l + Vec3(1, 0, 0)), a - b, 1e-9 * a);  // periodic, constant across layers
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i <= 4000; ++i) {
        const double v = f.value(l * (i * 1e-4 - 0.2));
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    EXPECT_GE(lo, a - b - 1e-9 * a);
    EXPECT_LE(hi, a + b + 1e-9 * a);
    EXPECT_LT(lo, a - b + 1e-3 * b);
    EXPECT_GT(hi, a + b - 1e-3 * b);
    EXPECT_DOUBLE_EQ(f.lower_bound(), a - b);
}

TEST(ScalarField, NegativeToughnessIsAClearError) {
    EXPECT_TRUE(cf::testing::throws<std::invalid_argument>(
        [&] { make_field(std::make_shared<LayeredField>(1e5, 3e5, 10, Vec3(0, 0, 1)), FieldQuantity::toughness, 2); },
        {"toughness", "-200000", ">= 0"}));
    EXPECT_THROW(make_field(std::make_shared<HomogeneousField>(-1), FieldQuantity::strength, 2), std::invalid_argument);
    EXPECT_THROW(make_field(std::make_shared<HomogeneousField>(1), FieldQuantity::strength, 0), std::invalid_argument);
    EXPECT_THROW(LayeredField(1, 0.5, 1, Vec3::Zero()), std::invalid_argument);
}

TEST(PeriodicVoronoi, SameSeedSameGrainsOtherSeedOtherGrains) {
    const PeriodicVoronoi a(0.1, 27, 42), b(0.1, 27, 42), c(0.1, 27, 43);
    ASSERT_EQ(a.seeds().size(), 27u);
    EXPECT_EQ(a.seeds(), b.seeds());
    EXPECT_NE(a.seeds(), c.seeds());
    for (const Vec3& s : a.seeds())
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(s[k], 0);
            EXPECT_LT(s[k], 0.1);
        }
}

TEST(PeriodicVoronoi, DistanceIsPeriodic) {
    const double T = 0.1;
    const PeriodicVoronoi v(T, 20, 3);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    for (int n = 0; n < 200; ++n) {
        const Vec3 p(u(rng), u(rng), u(rng));
        for (const Vec3& shift : {Vec3(T, 0, 0), Vec3(0, -2 * T, 0), Vec3(T, T, 3 * T)}) {
            EXPECT_NEAR(v.boundary_distance(p), v.boundary_distance(p + shift), 1e-12) << p.transpose();
        }
    }
}

TEST(PeriodicVoronoi, DistanceIsZeroOnBisectorsAndHalfTheNeighbourGapAtSeeds) {
    const double T = 0.1;
    const PeriodicVoronoi v(T, 20, 5);
    const auto& s = v.seeds();
    for (std::size_t i = 0; i < s.size(); ++i) {
        // Nearest periodic image of any other seed: the midpoint lies on the shared face
        // (|m - s_k| >= |s_k - s_i| - |m - s_i| >= |s_j - s_i| / 2 for every other seed k).
        double best = 1e300;
        Vec3 nearest;
        for (std::size_t j = 0; j < s.size(); ++j)
            for (int a = -1; a <= 1; ++a)
                for (int b = -1; b <= 1; ++b)
                    for (int c = -1; c <= 1; ++c) {
                        if (j == i && a == 0 && b == 0 && c == 0) continue;
                        const Vec3 q = s[j] + T * Vec3(a, b, c);
                        if ((q - s[i]).norm() < best) {
                            best = (q - s[i]).norm();
                            nearest = q;
                        }
                    }
        EXPECT_NEAR(v.boundary_distance(0.5 * (s[i] + nearest)), 0.0, 1e-14);
        EXPECT_NEAR(v.boundary_distance(s[i]), 0.5 * best, 1e-14);
        EXPECT_EQ(v.grain_of(s[i] + Vec3(T, 0, -T)), static_cast<int>(i));
    }
}

TEST(PeriodicVoronoi, TwentySevenImagesAgreeWithBruteForce) {
    const double T = 0.1;
    const PeriodicVoronoi v(T, 8, 11);  // the fewest grains allowed: the hardest case
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(0, T);
    std::vector<Vec3> img;
    for (const Vec3& s : v.seeds())
        for (int a = -2; a <= 2; ++a)
            for (int b = -2; b <= 2; ++b)
                for (int c = -2; c <= 2; ++c) img.push_back(s + T * Vec3(a, b, c));
    for (int n = 0; n < 300; ++n) {
        const Vec3 p(u(rng), u(rng), u(rng));
        std::size_t k0 = 0;
        for (std::size_t k = 1; k < img.size(); ++k)
            if ((img[k] - p).norm() < (img[k0] - p).norm()) k0 = k;
        double d = 1e300;
        for (std::size_t k = 0; k < img.size(); ++k)
            if (k != k0)
                d = std::min(d, ((img[k] - p).squaredNorm() - (img[k0] - p).squaredNorm()) / (2 * (img[k] - img[k0]).norm()));
        EXPECT_NEAR(v.boundary_distance(p), d, 1e-14);
    }
}

// boundary_distance and grain_of look only at the images bucketed near the point and skip images
// whose bisector is provably beyond the best so far; the results must be the plain loop's over all
// 27 x grains images to the bit (the plain loop as it was written: the images in the same order,
// the nearest the first of equals, every plane evaluated in order).
TEST(PeriodicVoronoi, BucketedQueriesAreThePlainLoopsToTheBit) {
    for (const int grains : {8, 64, 300}) {
        const double T = 0.037;
        const PeriodicVoronoi v(T, grains, 5 + grains);
        std::vector<Vec3> img;
        for (int i = -1; i <= 1; ++i)
            for (int j = -1; j <= 1; ++j)
                for (int k = -1; k <= 1; ++k)
                    for (const Vec3& s : v.seeds()) img.push_back(s + T * Vec3(i, j, k));
        auto plain = [&](const Vec3& p) {
            const Vec3 q = v.wrap(p);
            std::size_t nearest = 0;
            double d0 = 1e300;
            for (std::size_t i = 0; i < img.size(); ++i)
                if ((img[i] - q).squaredNorm() < d0) {
                    d0 = (img[i] - q).squaredNorm();
                    nearest = i;
                }
            double best = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < img.size(); ++i)
                if (i != nearest)
                    best = std::min(best, ((img[i] - q).squaredNorm() - d0) / (2 * (img[i] - img[nearest]).norm()));
            return std::make_pair(std::max(best, 0.0), int(nearest % v.seeds().size()));
        };
        std::mt19937 rng(grains);
        std::uniform_real_distribution<double> u(-0.5 * T, 1.5 * T);
        std::vector<Vec3> points;
        for (int n = 0; n < 3000; ++n) points.emplace_back(u(rng), u(rng), u(rng));
        const std::vector<Vec3>& s = v.seeds();
        for (std::size_t i = 0; i < s.size(); ++i) {
            points.push_back(s[i]);                                      // at a seed: |q - s0| = 0
            points.push_back(0.5 * (s[i] + s[(i + 1) % s.size()]));     // on or near a bisector
            points.push_back(s[i] + Vec3(T, 0, -T));                     // another image of it
        }
        for (int n = 0; n < 200; ++n) points.push_back(Vec3(0, u(rng), T * (n % 2)));  // on the tile's faces
        int differ = 0;
        for (const Vec3& p : points) {
            const double a = v.boundary_distance(p);
            const auto [b, grain] = plain(p);
            if ((std::memcmp(&a, &b, sizeof a) != 0 || v.grain_of(p) != grain) && ++differ <= 5)
                ADD_FAILURE() << grains << " grains, p = " << p.transpose() << ": " << a << " vs " << b << ", grain "
                              << v.grain_of(p) << " vs " << grain;
        }
        EXPECT_EQ(differ, 0) << grains << " grains";
    }
}

GranularSettings small_granular() {
    GranularSettings s;
    s.boundary_value = 1e6;
    s.rise = 0.1;
    s.grain_size = 0.01;
    s.grains_per_tile = 27;  // tile 0.03 m
    s.seed = 9;
    s.voxels_per_grain = 10;  // 30^3 voxels, h = 1 mm
    return s;
}

TEST(GranularField, GridDistanceMatchesExactDistanceWithinAVoxel) {
    const GranularField g(small_granular());
    const double h = g.distance_grid().voxel_size();
    EXPECT_NEAR(h, 1e-3, 1e-15);
    EXPECT_TRUE(g.distance_grid().is_periodic());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (int n = 0; n < 300; ++n) {
        const Vec3 p(u(rng), u(rng), u(rng));
        // The distance is 1-Lipschitz, so trilinear interpolation is off by at most the
        // distance to the farthest cell corner, sqrt(3) h.
        EXPECT_NEAR(g.boundary_distance(p), g.grains().boundary_distance(p), std::sqrt(3.0) * h);
    }
}

TEST(GranularField, PeriodicAndDeterministic) {
    const GranularField a(small_granular()), b(small_granular());
    GranularSettings other = small_granular();
    other.seed = 10;
    const GranularField c(other);
    const double T = a.grains().tile();
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    double diff_other = 0;
    for (int n = 0; n < 200; ++n) {
        const Vec3 p(u(rng), u(rng), u(rng));
        EXPECT_EQ(a.value(p), b.value(p));
        EXPECT_NEAR(a.value(p), a.value(p + Vec3(T, -T, 2 * T)), 1e-9 * 1e6);
        diff_other = std::max(diff_other, std::abs(a.value(p) - c.value(p)));
    }
    EXPECT_GT(diff_other, 1e4);  // another seed gives another structure
}

TEST(GranularField, LowOnBoundariesHighInsideGrains) {
    const GranularSettings s = small_granular();
    const GranularField g(s);
    const double h = g.distance_grid().voxel_size();
    const double sat = s.interior_depth * s.grain_size;
    const auto& seeds = g.grains().seeds();
    for (const Vec3& x : seeds) {
        const double d = g.grains().boundary_distance(x);
        const double expected = s.boundary_value * (1 + s.rise * std::min(d / sat, 1.0));
        EXPECT_NEAR(g.value(x), expected, s.boundary_value * s.rise * std::sqrt(3.0) * h / sat);
    }
    // Midpoint between seeds 0 and its nearest neighbour: on a boundary, value ~ boundary_value.
    double best = 1e300;
    Vec3 mid;
    const double T = g.grains().tile();
    for (std::size_t j = 1; j < seeds.size(); ++j)
        for (int a = -1; a <= 1; ++a)
            for (int b = -1; b <= 1; ++b)
                for (int c = -1; c <= 1; ++c) {
                    const Vec3 q = seeds[j] + T * Vec3(a, b, c);
                    if ((q - seeds[0]).norm() < best) {
                        best = (q - seeds[0]).norm();
                        mid = 0.5 * (q + seeds[0]);
                    }
                }
    EXPECT_NEAR(g.value(mid), s.boundary_value, s.boundary_value * s.rise * std::sqrt(3.0) * h / sat);
    EXPECT_DOUBLE_EQ(g.lower_bound(), s.boundary_value);
}

TEST(GranularField, GradientIsTheDerivativeOfTheInterpolant) {
    const GranularField g(small_granular());
    const double h = g.distance_grid().voxel_size();
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> cell(-40, 40);
    std::uniform_real_distribution<double> frac(0.2, 0.8);  // stay inside one voxel cell
    for (int n = 0; n < 100; ++n) {
        const Vec3 p = h * Vec3(cell(rng) + frac(rng), cell(rng) + frac(rng), cell(rng) + frac(rng));
        const double e = 1e-4 * h;
        Vec3 fd;
        for (int k = 0; k < 3; ++k) {
            Vec3 d = Vec3::Zero();
            d[k] = e;
            fd[k] = (g.value(p + d) - g.value(p - d)) / (2 * e);
        }
        // Trilinear: central differences exact up to rounding (values ~1e6, step 1e-7 m).
        EXPECT_LT((fd - g.gradient(p)).norm(), 1e-3 * (1e5 / 2.5e-3)) << p.transpose();
    }
}

TEST(VdbFileField, ReadsAFloatGridAndInterpolatesLinearFieldsExactly) {
    const ScratchDir dir("read");
    const auto file = dir / "k.vdb";
    testing::write_linear_float_grid(file, "toughness", 0.01, 10, 1e6, 1e6);
    const VdbFileField f(file, "toughness", 2.0);
    const Vec3 p(0.0234, 0.0411, 0.0377);
    EXPECT_NEAR(f.value(p), 2 * (1e6 + 1e6 * (p.x() + 2 * p.y() - p.z())), 1.0);
    const Vec3 g = f.gradient(p);
    EXPECT_NEAR(g.x(), 2e6, 1.0);
    EXPECT_NEAR(g.y(), 4e6, 1.0);
    EXPECT_NEAR(g.z(), -2e6, 1.0);
    // Values span 1e6 * (1 + 0.01 * [-9, 27]) times 2, background 1e6 times 2: all positive.
    EXPECT_NEAR(f.lower_bound(), 2 * (1e6 - 0.09e6), 1.0);
    EXPECT_NO_THROW(make_field(std::make_shared<VdbFileField>(file, "toughness", 1.0), FieldQuantity::toughness, 2));
    // Scaled by -1 the field is negative: refused.
    EXPECT_THROW(make_field(std::make_shared<VdbFileField>(file, "toughness", -1.0), FieldQuantity::toughness, 2),
                 std::invalid_argument);
}

TEST(VdbFileField, WritesAndReadsBackAGranularDistanceGrid) {
    const ScratchDir dir("roundtrip");
    const GranularField g(small_granular());
    g.distance_grid().write(dir / "grains.vdb", "distance");
    const VdbFileField back(dir / "grains.vdb", "distance", 1.0);
    const Vec3 p(0.0123, 0.0171, 0.0049);  // inside the tile: the stored voxels cover it
    EXPECT_NEAR(back.value(p), g.boundary_distance(p), 1e-7);
}

std::string error_of(const std::filesystem::path& file, const std::string& grid) {
    try {
        VdbFileField f(file, grid, 1.0);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(VdbFileField, ClearErrorsNamingFileAndGrid) {
    const ScratchDir dir("errors");
    std::string m = error_of(dir / "missing.vdb", "toughness");
    EXPECT_NE(m.find("missing.vdb"), std::string::npos) << m;
    EXPECT_NE(m.find("does not exist"), std::string::npos) << m;

    testing::write_linear_float_grid(dir / "k.vdb", "toughness", 0.01, 2, 1, 0);
    m = error_of(dir / "k.vdb", "strength");
    EXPECT_NE(m.find("'strength'"), std::string::npos) << m;
    EXPECT_NE(m.find("k.vdb"), std::string::npos) << m;
    EXPECT_NE(m.find("grids: toughness"), std::string::npos) << m;

    testing::write_vec3_grid(dir / "v.vdb", "toughness");
    m = error_of(dir / "v.vdb", "toughness");
    EXPECT_NE(m.find("vec3s"), std::string::npos) << m;
    EXPECT_NE(m.find("float grid"), std::string::npos) << m;

    {
        std::ofstream(dir / "junk.vdb") << "not a vdb file";
    }
    m = error_of(dir / "junk.vdb", "toughness");
    EXPECT_NE(m.find("junk.vdb"), std::string::npos) << m;
}

}  // namespace
}  // namespace cf
