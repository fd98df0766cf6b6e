#pragma once
// Verification case 4 of docs/verification.md (surface stress under uniaxial tension).
#include "nodes/domain/surface_mesh.hpp"
#include "nodes/domain/verification_case.hpp"

namespace cf::initiate {

// Cube [-L/2, L/2]^3, each face split into m x m squares of two triangles, outward CCW.
SurfaceMesh verification_cube(int m, double L);

// Max over elements of |sigma_e - sigma_exact|_F / sigma for the exact uniaxial field
// u = (sigma/E)(-nu x, -nu y, z), traction sigma_exact n, on verification_cube(m, L);
// side = true: only side faces (normal orthogonal to z), else only top and bottom faces.
double uniaxial_surface_stress_error(int m, double L, double sigma, double E, double nu, bool side);

}  // namespace cf::initiate
