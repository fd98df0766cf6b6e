// The crack recorder (ch. 6.2) against a brute-force reference on procedural swept fronts: every
// voxel near the strips gets min over all recorded triangles of the exact squared distance (no
// pruning, no blocks, no bounds), thickened and rounded to float as the grid stores it. The
// recorder prunes triangles by lower bounds (bounding box, in-plane box, column ranges) and reads
// old values lazily; those only skip work, so the recorded grid must equal the reference bit for
// bit, sub-step after sub-step (tolerance 0), and hold exactly the voxels whose distance is within
// the band.
#include "nodes/domain/triangle_closest_point.hpp"
#include "nodes/levelset/crack_grids.hpp"
#include "nodes/levelset/level_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace cf {
namespace {

// A power of two, so voxel centres k r_f and their index coordinates are exact in double and the
// trilinear sample at a voxel centre is the stored value itself.
constexpr double kRf = 1.0 / 64;
constexpr double kHalfWidth = 2;  // the crack band the shipped pipelines use (fracture.start)

struct Sweep {
    std::vector<FrontMotion> steps;
};

// An open, wavy front tilted out of every coordinate plane, advancing with per-marker speeds and
// directions that turn; some markers stop (p1 == p0) part-way, as markers deactivated by fig. 27.
Sweep open_tilted_sweep(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3);
    const int n = 17, substeps = 9;
    std::vector<Vec3> front;
    for (int i = 0; i < n; ++i) {
        const double s = double(i) / (n - 1);
        front.emplace_back(0.11 + 0.05 * std::sin(3 * s), -0.2 + 0.4 * s, 0.07 * s + 0.02 * std::cos(5 * s));
    }
    const Vec3 ahead = Vec3(1, 0.3, 0.45).normalized();
    std::vector<char> stopped(n, 0);
    Sweep sw;
    for (int k = 0; k < substeps; ++k) {
        FrontMotion m;
        m.p0 = front;
        m.p1 = front;
        for (int i = 0; i < n; ++i) {
            if (!stopped[i] && k >= 3 && (i % 5 == 2) && rng() % 3 == 0) stopped[i] = 1;
            if (stopped[i]) continue;
            const Vec3 dir = (ahead + Vec3(jitter(rng), jitter(rng), 0.5 * jitter(rng))).normalized();
            m.p1[i] = front[i] + (0.4 + 0.7 * (0.5 + 0.5 * jitter(rng))) * kRf * dir;
        }
        front = m.p1;
        sw.steps.push_back(m);
    }
    return sw;
}

// A closed, tilted ring expanding unevenly (a penny crack growing out of its plane).
Sweep closed_ring_sweep(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 24, substeps = 7;
    const Vec3 c(0.02, -0.01, 0.03), e1 = Vec3(1, 0.2, 0.1).normalized();
    const Vec3 e2 = Vec3(-0.3, 1, 0.5).cross(e1).cross(e1).normalized() * -1.0;
    const Vec3 nrm = e1.cross(e2).normalized();
    std::vector<Vec3> front;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        front.push_back(c + 0.06 * (std::cos(a) * e1 + std::sin(a) * e2));
    }
    Sweep sw;
    for (int k = 0; k < substeps; ++k) {
        FrontMotion m;
        m.closed = true;
        m.p0 = front;
        m.p1 = front;
        for (int i = 0; i < n; ++i) {
            if (i == 5 && k >= 2) continue;  // one marker stopped
            const Vec3 out = (front[i] - c).normalized();
            m.p1[i] = front[i] + (0.3 + 0.8 * u(rng)) * kRf * (out + 0.4 * (u(rng) - 0.5) * nrm).normalized();
        }
        front = m.p1;
        sw.steps.push_back(m);
    }
    return sw;
}

// Brute force over the voxels around all triangles recorded so far: the grid must hold exactly
// float(sqrt(min_t d_t^2) - thick) where min_t d_t^2 < reach^2 and the background elsewhere.
void expect_grid_equals_reference(const LevelSet& grid, const std::vector<Triangle3>& tris, std::size_t& in_band) {
    const double thick = crack_half_thickness(kRf);
    const double reach = kHalfWidth * kRf + thick, reach2 = reach * reach;
    Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
    for (const Triangle3& t : tris)
        for (const Vec3& p : t) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    int k0[3], k1[3];
    for (int a = 0; a < 3; ++a) {
        k0[a] = int(std::floor((lo[a] - reach) / kRf)) - 1;
        k1[a] = int(std::ceil((hi[a] + reach) / kRf)) + 1;
    }
    const float background = float(kHalfWidth * kRf);
    std::size_t mismatches = 0;
    in_band = 0;
    for (int i = k0[0]; i <= k1[0]; ++i)
        for (int j = k0[1]; j <= k1[1]; ++j)
            for (int k = k0[2]; k <= k1[2]; ++k) {
                const Vec3 p(i * kRf, j * kRf, k * kRf);
                double best = reach2;
                for (const Triangle3& t : tris) best = std::min(best, closest_point_on_triangle(p, t[0], t[1], t[2]).distance2);
                const bool band = best < reach2;
                in_band += band;
                const float expected = band ? float(std::sqrt(best) - thick) : background;
                const double got = sample(grid, p);
                if (got != double(expected) && ++mismatches <= 5)
                    ADD_FAILURE() << "voxel (" << i << ", " << j << ", " << k << "): recorded " << got << ", reference "
                                  << expected << " [m]";
            }
    EXPECT_EQ(mismatches, 0u);
    EXPECT_EQ(active_voxel_count(grid), in_band);
}

void check_sweep(const Sweep& sw) {
    CrackRecorder rec(kRf, kHalfWidth);
    rec.add_crack();
    std::vector<Triangle3> all;
    std::size_t in_band = 0, last = 0;
    for (std::size_t s = 0; s < sw.steps.size(); ++s) {
        SCOPED_TRACE("after sub-step " + std::to_string(s));
        rec.record_substep({sw.steps[s]}, nullptr);
        const std::vector<Triangle3> t = strip_triangles(sw.steps[s]);
        all.insert(all.end(), t.begin(), t.end());
        if (s % 3 == 2 || s + 1 == sw.steps.size()) {  // the brute force is O(voxels x triangles)
            expect_grid_equals_reference(rec.snapshot().cracks[0], all, in_band);
            EXPECT_GT(in_band, last);  // the crack grew
            last = in_band;
        }
    }
    EXPECT_GT(in_band, 1500u);  // a test over many voxels, not a handful
}

TEST(CrackRecordingExactness, OpenTiltedFrontEqualsBruteForceBitForBit) {
    for (unsigned seed : {1u, 7u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        check_sweep(open_tilted_sweep(seed));
    }
}

TEST(CrackRecordingExactness, ClosedRingFrontEqualsBruteForceBitForBit) { check_sweep(closed_ring_sweep(3)); }

}  // namespace
}  // namespace cf
