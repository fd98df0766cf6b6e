#pragma once
// A seeded, tileable (periodic) Voronoi grain structure: the cube tile [0, T)^3 repeats in all
// three directions, seeds are placed by dart throwing from a std::mt19937_64 stream (the
// generator's output is fixed by the C++ standard, so a seed gives the same grains everywhere).
#include "nodes/domain/surface_mesh.hpp"

#include <cstdint>
#include <vector>

namespace cf {

class PeriodicVoronoi {
public:
    // `grains` seeds in a cube tile of edge `tile` [m]. Seeds keep at least half the mean
    // spacing (tile^3/grains)^(1/3) apart where dart throwing allows (no tiny grains).
    // Throws std::invalid_argument for tile <= 0 or grains < 8 (fewer grains would need more than
    // the 27 nearest tile images to find every grain boundary).
    PeriodicVoronoi(double tile, int grains, std::uint64_t seed);

    double tile() const { return tile_; }
    const std::vector<Vec3>& seeds() const { return seeds_; }
    double mean_spacing() const;  // (tile^3 / grains)^(1/3) [m]

    Vec3 wrap(const Vec3& p) const;  // into [0, tile)^3
    // Index of the grain containing p (nearest seed over the periodic images).
    int grain_of(const Vec3& p) const;
    // Exact distance [m] from p to the nearest grain boundary: the smallest distance to a
    // bisector plane between the nearest seed and any other seed image (the cell is the
    // intersection of those half-spaces). Zero on grain boundaries.
    double boundary_distance(const Vec3& p) const;

private:
    // Calls f(i) for every image i in the buckets overlapping the ball of `radius` around c (a
    // superset of the images within it; each image once).
    template <class F>
    void images_near(const Vec3& c, double radius, F&& f) const;
    std::size_t nearest_image(const Vec3& q, double& d0) const;

    double tile_;
    std::vector<Vec3> seeds_;
    std::vector<Vec3> images_;      // all seeds shifted by {-1,0,1}^3 tiles
    std::vector<int> image_seed_;   // seed index of each image
    // The images bucketed by a uniform grid of `buckets_`^3 cells over [-tile, 2 tile)^3 (about one
    // image per cell): queries look at the images near a point instead of all 27 x grains.
    int buckets_ = 0;
    double bucket_size_ = 0;
    std::vector<std::uint32_t> bucket_start_, bucket_images_;
};

}  // namespace cf
