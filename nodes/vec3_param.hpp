#pragma once
// A node parameter declared with param_reals(...).size(3) read as a point or direction.
#include "graph/node_context.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <string_view>

namespace cf {

inline Vec3 vec3_param(const graph::NodeContext& c, std::string_view name) {
    const std::vector<double>& r = c.reals(name);
    return Vec3(r[0], r[1], r[2]);
}

}  // namespace cf
