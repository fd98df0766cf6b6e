#pragma once
// The colour of fragment i wherever fragments are drawn or written (the preview contact sheet, the
// fragment meshes' glTF and .mtl materials, the scenes' glTF pieces), so a piece has one colour
// everywhere. Hues a golden angle (137.508 degrees) apart starting at 30 degrees, value alternating
// 0.92 / 0.72 and saturation cycling 0.65 / 0.5 / 0.8, so consecutive indices differ in hue and
// brightness and the first 64 are pairwise distinct. Header-only: a few lines of arithmetic.
#include "nodes/domain/surface_mesh.hpp"

#include <cmath>
#include <cstddef>
#include <string>

namespace cf {

// HSV (hue in degrees, s and v in [0, 1]) to RGB in [0, 1].
inline Vec3 hsv_to_rgb(double h, double s, double v) {
    h = std::fmod(std::fmod(h, 360.0) + 360.0, 360.0) / 60.0;
    const int sector = int(h);
    const double f = h - sector, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (sector) {
        case 0: return Vec3(v, t, p);
        case 1: return Vec3(q, v, p);
        case 2: return Vec3(p, v, t);
        case 3: return Vec3(p, q, v);
        case 4: return Vec3(t, p, v);
        default: return Vec3(v, p, q);
    }
}

inline Vec3 fragment_colour(std::size_t i) {
    const double hue = 30.0 + 137.50776405003785 * double(i);
    const double sat[3] = {0.65, 0.5, 0.8};
    return hsv_to_rgb(hue, sat[i % 3], i % 2 ? 0.72 : 0.92);
}

// The fracture ("inside") faces of a piece of colour c: c mixed 35/65 with a pale stone grey, so
// they read as the same piece but clearly apart from its outer faces.
inline Vec3 inside_shade(const Vec3& c) { return 0.35 * c + 0.65 * Vec3(0.93, 0.9, 0.84); }
inline Vec3 fragment_inside_colour(std::size_t i) { return inside_shade(fragment_colour(i)); }

// The id of the region named `name` in m, or -1.
inline int region_id(const SurfaceMesh& m, const std::string& name) {
    for (int r = 0; r < int(m.region_names.size()); ++r)
        if (m.region_names[std::size_t(r)] == name) return r;
    return -1;
}

}  // namespace cf
