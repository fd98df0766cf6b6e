#include "nodes/fields/periodic_voronoi.hpp"

#include <algorithm>
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
    buckets_ = std::clamp(static_cast<int>(std::ceil(3 * std::cbrt(static_cast<double>(grains)))), 3, 96);
    bucket_size_ = 3 * tile / buckets_;
    auto bucket_of = [&](const Vec3& p) {
        std::size_t b = 0;
        for (int k = 0; k < 3; ++k)
            b = b * buckets_ + std::size_t(std::clamp(static_cast<int>(std::floor((p[k] + tile) / bucket_size_)), 0, buckets_ - 1));
        return b;
    };
    bucket_start_.assign(std::size_t(buckets_) * buckets_ * buckets_ + 1, 0);
    for (const Vec3& p : images_) ++bucket_start_[bucket_of(p) + 1];
    for (std::size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
    bucket_images_.resize(images_.size());
    std::vector<std::uint32_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
    for (std::size_t i = 0; i < images_.size(); ++i) bucket_images_[fill[bucket_of(images_[i])]++] = std::uint32_t(i);
}

template <class F>
void PeriodicVoronoi::images_near(const Vec3& c, double radius, F&& f) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        // Clamped as doubles first (a huge radius must not overflow the conversion); a point outside
        // [-tile, 2 tile) belongs to the edge bucket, as in the constructor.
        const double a = (c[k] - radius + tile_) / bucket_size_, b = (c[k] + radius + tile_) / bucket_size_;
        lo[k] = static_cast<int>(std::floor(std::clamp(a, 0.0, double(buckets_ - 1))));
        hi[k] = static_cast<int>(std::floor(std::clamp(b, 0.0, double(buckets_ - 1))));
    }
    for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int z = lo[2]; z <= hi[2]; ++z) {
                const std::size_t b = (std::size_t(x) * buckets_ + y) * buckets_ + z;
                for (std::uint32_t e = bucket_start_[b]; e < bucket_start_[b + 1]; ++e) f(std::size_t(bucket_images_[e]));
            }
}

// The nearest image to q (the lowest index among equally near ones, as a scan in index order finds)
// and its squared distance d0. A first guess from the buckets around q bounds the search ball.
std::size_t PeriodicVoronoi::nearest_image(const Vec3& q, double& d0) const {
    double guess = std::numeric_limits<double>::infinity();
    images_near(q, bucket_size_, [&](std::size_t i) { guess = std::min(guess, (images_[i] - q).squaredNorm()); });
    std::size_t nearest = images_.size();
    d0 = std::numeric_limits<double>::infinity();
    auto consider = [&](std::size_t i) {
        const double d = (images_[i] - q).squaredNorm();
        if (d < d0 || (d == d0 && i < nearest)) {
            d0 = d;
            nearest = i;
        }
    };
    if (std::isfinite(guess)) {
        // Every image as near as the guess lies within sqrt(guess) (a relative 1e-6 above the rounding).
        images_near(q, std::sqrt(guess) * (1 + 1e-6), consider);
    } else {
        for (std::size_t i = 0; i < images_.size(); ++i) consider(i);
    }
    return nearest;
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
    double d0;
    return image_seed_[nearest_image(wrap(p), d0)];
}

double PeriodicVoronoi::boundary_distance(const Vec3& p) const {
    const Vec3 q = wrap(p);
    double d0;
    const std::size_t nearest = nearest_image(q, d0);
    const Vec3& s0 = images_[nearest];
    // Distance from q to the bisector plane of s0 and s_i: (|q-s_i|^2 - |q-s0|^2) / (2 |s_i - s0|),
    // >= +0 for every i (d0 is the smallest squared distance), so their minimum does not depend
    // on the order they are taken in.
    auto plane = [&](std::size_t i) { return ((images_[i] - q).squaredNorm() - d0) / (2 * (images_[i] - s0).norm()); };
    // By the triangle inequality an image's plane is at least |s_i - s0| / 2 - |q - s0|: where
    // |s_i - s0|^2 > 4 (best + |q - s0|)^2 (1 + 1e-6) it lies beyond `best` by a relative 5e-7, far
    // above the rounding of either value, so it is not the minimum. Starting from the plane of an
    // image near s0, only the images within 2 (best + |q - s0|) of s0 are looked at: the result is
    // the plain minimum over all 27 x grains images to the bit.
    const double r0 = std::sqrt(d0);
    double best = std::numeric_limits<double>::infinity();
    images_near(s0, bucket_size_, [&](std::size_t i) {
        if (i != nearest) best = std::min(best, plane(i));
    });
    auto take = [&](std::size_t i) {
        if (i == nearest) return;
        const double reach = best + r0;
        if ((images_[i] - s0).squaredNorm() > 4 * reach * reach * (1 + 1e-6)) return;
        best = std::min(best, plane(i));
    };
    if (std::isfinite(best)) {
        images_near(s0, 2 * (best + r0) * (1 + 1e-6), take);
    } else {
        for (std::size_t i = 0; i < images_.size(); ++i) take(i);
    }
    return std::max(best, 0.0);
}

}  // namespace cf
