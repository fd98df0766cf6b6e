#pragma once
// Writes small .vdb files for the field tests (the only test code that includes OpenVDB).
#include <filesystem>
#include <string>

namespace cf::testing {

// A vector-valued grid named `name` (for the wrong-type error).
void write_vec3_grid(const std::filesystem::path& file, const std::string& name);
// A float grid named `name` with voxel size h [m]: value(i,j,k) = c0 + c1 * (x + 2y - z) at
// world (x,y,z) = h (i,j,k), for 0 <= i,j,k < n.
void write_linear_float_grid(const std::filesystem::path& file, const std::string& name, double h, int n, double c0,
                             double c1);

}  // namespace cf::testing
