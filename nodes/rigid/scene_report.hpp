#pragma once
// The fracture runs of a scene as a table (report of Table 3's quantities per run): frame, body,
// summed impulse [N s], contact force [N], contact duration [s], BEM step bound, BEM triangles,
// fragments kept and dropped, crack triangles and those carried on as incomplete cracks, seconds, whether it broke. Written atomically.
#include "nodes/rigid/scene_simulation.hpp"

#include <filesystem>
#include <vector>

namespace cf::rigid {

// Writes <stem>.csv and <stem>.json.
void write_fracture_runs(const std::filesystem::path& stem, const std::vector<FractureRunRecord>& runs);

}  // namespace cf::rigid
