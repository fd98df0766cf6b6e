#pragma once
// Shared pieces of the estimator verification cases (nodes/estimate/estimate_verification*.cpp).
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/domain/verification_case.hpp"

#include <vector>

namespace cf {
namespace estimate {
// Flat sheet origin + s u + t v, (s, t) in [0,1]^2, nu x nv squares of two triangles, one region "crack".
SurfaceMesh rectangle_sheet(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv);
}  // namespace estimate

}  // namespace cf
