#pragma once
// Fields stored on voxel grids (thesis ch. 4.5.3): a granular material from a periodic Voronoi
// grain structure, and a field read from a user's .vdb file.
#include "nodes/fields/periodic_voronoi.hpp"
#include "nodes/fields/scalar_field.hpp"
#include "nodes/fields/voxel_grid.hpp"

#include <cstdint>
#include <filesystem>

namespace cf {

struct GranularSettings {
    double boundary_value = 1e6;   // field value on grain boundaries (the minimum) [field units]
    double rise = 0.1;             // fractional rise towards grain interiors: interior = (1 + rise) * boundary [-]
    double grain_size = 1e-2;      // mean grain spacing [m]
    int grains_per_tile = 64;      // grains in one periodic tile (>= 8); tile edge = grain_size * cbrt(grains)
    std::uint64_t seed = 1;        // grain placement
    int voxels_per_grain = 8;      // distance-grid resolution: voxels per grain_size
    double interior_depth = 0.25;  // distance from the boundary (in grain sizes) where the rise is complete [-]
};

// K(p) = K_b (1 + rise * min(d(p) / (interior_depth * grain_size), 1)), with d the distance to
// the nearest grain boundary, sampled once on a periodic OpenVDB grid and interpolated
// trilinearly: toughness is lowest on grain boundaries, so cracks prefer to run along them.
class GranularField final : public FieldSource {
public:
    // Throws std::invalid_argument for non-positive sizes, rise <= -1, or a grid too large.
    explicit GranularField(const GranularSettings& s);
    double value(const Vec3& p) const override;
    Vec3 gradient(const Vec3& p) const override;
    double lower_bound() const override;
    std::string description() const override;

    const PeriodicVoronoi& grains() const { return grains_; }
    const VoxelGrid& distance_grid() const { return distance_; }  // [m]
    double boundary_distance(const Vec3& p) const { return distance_.sample(p); }  // interpolated [m]

private:
    GranularSettings s_;
    PeriodicVoronoi grains_;
    VoxelGrid distance_;
    double saturation_;  // interior_depth * grain_size [m]
};

// value = scale * (trilinear sample of a float grid in a .vdb file).
class VdbFileField final : public FieldSource {
public:
    // Throws std::invalid_argument naming the file and grid (see VoxelGrid::read).
    VdbFileField(const std::filesystem::path& file, const std::string& grid_name, double scale);
    double value(const Vec3& p) const override { return scale_ * grid_.sample(p); }
    Vec3 gradient(const Vec3& p) const override { return scale_ * grid_.gradient(p); }
    double lower_bound() const override;
    std::string description() const override;

private:
    std::string file_, grid_name_;
    double scale_;
    VoxelGrid grid_;
};

}  // namespace cf
