#include "nodes/fields/periodic_voronoi.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace cf {

namespace {

// Uniform double in [0, 1) from the top 53 bits: unlike std::uniform_real_distribution this is
// the same on every standard library.
double unit_uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double periodic_distance(const Vec3& a, const Vec3& b, double T) {
    Vec3 d = a - b;
    for (int k = 0; k < 3; ++k) d[k] -= T * std::round(d[k] / T);
    return d.norm();
}

}  // namespace

PeriodicVoronoi::PeriodicVoronoi(double tile, int grains, std::uint64_t seed) : tile_(tile) {
    if (!(tile > 0) || !std::isfinite(tile)) throw std::invalid_argument("granular field: tile size must be > 0 [m]");
    if (grains < 8) throw std::invalid_argument("granular field: grains per tile must be >= 8 (got " + std::to_string(grains) + ")");
    std::mt19937_64 rng(seed);
    const double min_gap = 0.5 * std::cbrt(tile * tile * tile / grains);
    seeds_.reserve(grains);
    while (static_cast<int>(seeds_.size()) < grains) {
        Vec3 best = Vec3::Zero();
        // Dart throwing: up to 64 tries for a point far enough from all seeds; otherwise the
        // farthest candidate seen (keeps the loop bounded for any seed).
        double best_gap = -1;
        for (int attempt = 0; attempt < 64; ++attempt) {
            const Vec3 c(unit_uniform(rng) * tile, unit_uniform(rng) * tile, unit_uniform(rng) * tile);
            double gap = std::numeric_limits<double>::infinity();
            for (const Vec3& s : seeds_) gap = std::min(gap, periodic_distance(c, s, tile));
            if (gap > best_gap) {
                best_gap = gap;
                best = c;
            }
            if (gap >= min_gap) break;
        }
        seeds_.push_back(best);
    }
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k)
                for (std::size_t s = 0; s < seeds_.size(); ++s) {
                    images_.push_back(seeds_[s] + tile * Vec3(i, j, k));
                    image_seed_.push_back(static_cast<int>(s));
                }
}

double PeriodicVoronoi::mean_spacing() const { return std::cbrt(tile_ * tile_ * tile_ / seeds_.size()); }

Vec3 PeriodicVoronoi::wrap(const Vec3& p) const {
    Vec3 q;
    for (int k = 0; k < 3; ++k) {
        q[k] = p[k] - tile_ * std::floor(p[k] / tile_);
        if (q[k] >= tile_) q[k] -= tile_;  // rounding of values just below a multiple of the tile
    }
    return q;
}

int PeriodicVoronoi::grain_of(const Vec3& p) const {
    const Vec3 q = wrap(p);
    std::size_t best = 0;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < images_.size(); ++i) {
        const double d = (images_[i] - q).squaredNorm();
        if (d < bd) {
            bd = d;
            best = i;
        }
    }
    return image_seed_[best];
}

double PeriodicVoronoi::boundary_distance(const Vec3& p) const {
    const Vec3 q = wrap(p);
    std::size_t nearest = 0;
    double d0 = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < images_.size(); ++i) {
        const double d = (images_[i] - q).squaredNorm();
        if (d < d0) {
            d0 = d;
            nearest = i;
        }
    }
    const Vec3& s0 = images_[nearest];
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < images_.size(); ++i) {
        if (i == nearest) continue;
        // Distance from q to the bisector plane of s0 and s_i: (|q-s_i|^2 - |q-s0|^2) / (2 |s_i - s0|).
        const double plane = ((images_[i] - q).squaredNorm() - d0) / (2 * (images_[i] - s0).norm());
        best = std::min(best, plane);
    }
    return std::max(best, 0.0);
}

}  // namespace cf
