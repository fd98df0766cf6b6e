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
    double tile_;
    std::vector<Vec3> seeds_;
    std::vector<Vec3> images_;      // all seeds shifted by {-1,0,1}^3 tiles
    std::vector<int> image_seed_;   // seed index of each image
};

}  // namespace cf
