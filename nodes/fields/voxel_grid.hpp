#pragma once
// A scalar voxel grid behind an opaque handle: only voxel_grid.cpp includes OpenVDB (slow to
// compile). Voxel (i,j,k) of a grid built here sits at world position (i,j,k) * voxel_size;
// grids read from files keep their own (linear) transform.
#include "nodes/domain/surface_mesh.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace cf {

struct VoxelGridData;  // an openvdb::FloatGrid and its sampling settings (voxel_grid.cpp)

class VoxelGrid {
public:
    // Samples f at the nodes (i,j,k) * tile/res, 0 <= i,j,k < res, of a periodic cube tile of edge
    // `tile` [m]: queries wrap into the tile, so the grid repeats seamlessly. f is evaluated in
    // parallel (oneTBB); it must be thread-safe. Throws std::invalid_argument for res < 2 or
    // res^3 above 1.3e8 voxels.
    static VoxelGrid periodic(double tile, int res, const std::function<double(const Vec3&)>& f);

    // Reads the float grid `grid_name` from a .vdb file. Throws std::invalid_argument naming the
    // file and grid when the file cannot be read, has no grid of that name (listing the grids it
    // has), the grid is not a float grid (naming its type), or its transform is not linear.
    static VoxelGrid read(const std::filesystem::path& file, const std::string& grid_name);

    // Writes the grid as `grid_name` into a .vdb file, atomically.
    void write(const std::filesystem::path& file, const std::string& grid_name) const;

    // Trilinear interpolation of the voxel values, and its exact gradient [units / m].
    double sample(const Vec3& p) const;
    Vec3 gradient(const Vec3& p) const;

    double min_value() const;  // over all stored values, background included
    double max_value() const;
    double voxel_size() const;  // [m] (x axis of the transform)
    bool is_periodic() const;
    std::size_t active_voxel_count() const;

private:
    std::shared_ptr<const VoxelGridData> data_;
};

}  // namespace cf
