#pragma once
// A user-given initial crack (thesis App. A item 12: location and orientation of an initial
// crack): a disk, or a half-disk for an edge crack, turned into a BEM crack sheet that stays
// strictly inside the ordinary surface (ch. 6: sheets are not connected to the surface) and a
// fine recorded surface that may reach through the object's boundary. SI units (metres).
#include "nodes/levelset/crack_grids.hpp"

#include <functional>
#include <vector>

namespace cf::initiate {

struct UserCrackSpec {
    Vec3 centre = Vec3::Zero();           // [m]
    Vec3 normal = Vec3::UnitZ();          // crack plane normal (any length > 0)
    Vec3 front_direction = Vec3::Zero();  // zero: full disk; else the half-disk on the +d side
    double radius = 0;                    // [m]
};

struct UserCrack {
    SurfaceMesh sheet;               // BEM sheet: edges ~r_c, normal +normal, >= margin inside the surface
    std::vector<Triangle3> recorded; // the whole (half-)disk, unclipped
    double margin = 0;               // max(r_f, 0.05 r_c) [m]
    Vec3 inner_point;                // the point the clipping rays start from (a sheet vertex)
    Vec3 plane_normal, t1, t2;       // unit frame: t1 = projected front direction (or any), t2 = n x t1
    bool half = false;
};

// Signed distance of the object (negative inside) [m], e.g. a sampled level set.
using ObjectDistance = std::function<double(const Vec3&)>;

// The crack region R = {x in the plane: |x - centre| <= radius, and (x - centre).d >= 0 for an
// edge crack}, d the front direction projected into the plane. The BEM sheet is the part of R
// that rays in the plane from an inner point (centre if it is at least the margin inside the
// surface, else centre + radius/2 d, else the deepest sampled point of R) reach while staying at
// least `margin` from every triangle of `surface` (sphere tracing, so no point of a ray comes
// closer), resampled at spacing ~r_c/2 and meshed with edges ~r_c, at most 1.4 r_c
// (mesh_planar_region).
// Throws std::invalid_argument naming the parameter and the fix when: normal is zero,
// front_direction is parallel to normal, no part of R is inside the object (`object_distance`
// >= 0 at every sample), or the sheet would be too small for an interior node at r_c (the
// message gives the minimum radius).
UserCrack build_user_crack(const UserCrackSpec& spec, const SurfaceMesh& surface, const ObjectDistance& object_distance,
                           double r_c, double r_f, const std::string& name = "user_crack");

// Longest BEM sheet edge of a user crack, in units of r_c.
constexpr double max_sheet_edge_factor = 1.4;

// Margin between a user crack sheet and the ordinary surface: max(r_f, 0.05 r_c) [m].
inline double user_crack_margin(double r_c, double r_f) { return std::max(r_f, 0.05 * r_c); }

}  // namespace cf::initiate
