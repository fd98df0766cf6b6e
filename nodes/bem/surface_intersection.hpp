#pragma once
// Crack sheets must stay strictly inside the body: a crack triangle that touches or crosses the
// ordinary surface would make the Sigma-Gamma integrals singular (sgbem-math.md §2, thesis ch. 2.5).
#include "nodes/bem/element_geometry.hpp"

#include <vector>

namespace cf::bem {

// True when the closed segment [p, q] meets the closed triangle (robust to a relative tolerance).
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const ElementGeometry& t);
bool triangles_intersect(const ElementGeometry& a, const ElementGeometry& b);

// Throws std::invalid_argument naming the crack and triangle when any crack triangle with index
// >= first intersects a surface triangle.
void check_crack_clear_of_surface(const std::vector<ElementGeometry>& surface, const std::vector<ElementGeometry>& crack,
                                  std::size_t first, const SurfaceMesh& cracks);

}  // namespace cf::bem
