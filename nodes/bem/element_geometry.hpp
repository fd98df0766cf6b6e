#pragma once
// Per-triangle data every BEM integral needs, computed once per mesh (sgbem-math.md §2):
// unit normal, area, surface gradients and curls of the three P1 hats, and the Guenter
// matrices M_beta[i][j] = g_i n_j - n_i g_j of the basis functions lambda_beta e_j.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace cf::bem {

using Mat3 = Eigen::Matrix3d;

struct ElementGeometry {
    Tri nodes{};                     // vertex ids in the mesh the element belongs to
    std::array<Vec3, 3> p;           // vertex positions, local order = nodes order
    Vec3 normal = Vec3::Zero();      // unit, (p1-p0) x (p2-p0) direction
    double area = 0;
    Vec3 centroid = Vec3::Zero();
    double diameter = 0;             // longest edge
    std::array<Vec3, 3> grad;        // surface gradient of lambda_beta
    std::array<Vec3, 3> curl;        // n x grad
    std::array<Mat3, 3> M;           // Guenter matrix of lambda_beta (constant per element)
};

// Throws std::invalid_argument naming the triangle when it is degenerate (area below
// 1e-12 * longest edge^2) or references a missing vertex.
ElementGeometry element_geometry(const SurfaceMesh& mesh, std::size_t t);
std::vector<ElementGeometry> element_geometries(const SurfaceMesh& mesh, const char* what);

}  // namespace cf::bem
