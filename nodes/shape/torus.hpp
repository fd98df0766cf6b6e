#pragma once
// A torus around the z axis, the "chain link" of thesis fig. 36: pulled apart along x by
// Dirichlet displacements of its left and right outer faces along their normals
// (thesis ch. 8, fig. 36; thesis-cases.yaml chain_link_*).
#include "nodes/domain/surface_mesh.hpp"

namespace cf {

struct TorusSpec {
    double major_radius = 0.04;   // centre of the tube to the z axis [m], > minor_radius
    double minor_radius = 0.012;  // tube radius [m], > 0
    Vec3 centre{0, 0, 0};         // [m]
    int major_segments = 24;      // around the z axis, even (so left and right are mirror images), >= 4
    int minor_segments = 12;      // around the tube, >= 3
    double pull_angle = 0.5;      // half-angle [rad] of each pulled patch, in both tube angles
};

// Vertex (i, j) sits at tube angle phi_i = 2 pi i / major_segments around z and
// theta_j = 2 pi j / minor_segments around the tube (theta = 0 on the outer equator).
// Regions, in id order: rest, pull_left, pull_right. pull_left holds the quads whose centre
// angles are within pull_angle of phi = pi and of theta = 0 (outward normal near -x);
// pull_right likewise around phi = 0 (normal near +x). Each quad of the grid is a planar
// trapezoid split into two triangles, so the polyhedron's volume is exactly
// major_segments * sin(2 pi / major_segments) * major_radius * (minor_segments / 2) *
// minor_radius^2 * sin(2 pi / minor_segments).
// Throws std::invalid_argument on bad specs (including a pull_angle that selects no quad).
SurfaceMesh make_torus(const TorusSpec& spec);

}  // namespace cf
