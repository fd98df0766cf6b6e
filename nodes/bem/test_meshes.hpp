#pragma once
// Small procedural meshes for the BEM verification cases and tests (the shape stage has the
// production builders; these keep the BEM cases independent of it).
#include "nodes/domain/surface_mesh.hpp"

namespace cf::bem {

// Cube [c - L/2, c + L/2]^3, each face split into m x m squares of 2 triangles, outward CCW.
// Regions 0..5: x_min, x_max, y_min, y_max, z_min, z_max.
SurfaceMesh bem_cube_mesh(int m, double L, const Vec3& centre = Vec3::Zero());
// Icosphere of radius R (20 * 4^level triangles), one region "surface".
SurfaceMesh bem_icosphere_mesh(int level, double R);
// Flat disk of radius a in the plane z = centre.z, normal +z, built from `rings` concentric
// rings (6 i points on ring i). grade > 1 packs rings towards the rim: radius of ring i is
// a (1 - (1 - i/rings)^grade). One region "crack".
SurfaceMesh bem_disk_mesh(int rings, double a, const Vec3& centre = Vec3::Zero(), double grade = 1.0);

}  // namespace cf::bem
