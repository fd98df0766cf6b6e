#pragma once
// A box written as an OBJ with affine texture coordinates per face (so the exact UV of any point on
// a face is known in closed form) and two materials ("cap" on the faces normal to z, "wall" on the
// others), and two tilted crack planes that cut it into four fragments. Shared by the surface
// mesher's tests (surface_fragments_test.cpp, fragment_files_test.cpp).
#include "nodes/domain/surface_mesh.hpp"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace cf::textured_box {

inline const Vec3 kLo(-0.3, -0.2, -0.15), kHi(0.3, 0.2, 0.15);  // the box [m]
inline constexpr double kRf = 0.01;                              // voxel size [m]
inline constexpr int kSplit = 4;                                 // each box face as a 4 x 4 grid of quads

// The face of the box a point on it lies on: axis and side (+1 / -1).
struct BoxFace {
    int axis;
    int side;
};

// Exact texture coordinates of a point on face f: an affine map with a scale and offset of its
// own per face (non-trivial: no two faces alike, seams between them).
inline Vec2 exact_uv(const Vec3& p, BoxFace f) {
    const int a = (f.axis + 1) % 3, b = (f.axis + 2) % 3;
    const double k = 1.0 + f.axis + 0.5 * (f.side > 0);
    return Vec2(0.1 * (f.axis + 1) + k * (p[a] - kLo[a]), 0.05 * f.side + 0.7 * k * (p[b] - kLo[b]));
}

// Material by face: the two faces normal to z are "cap", the other four "wall".
inline std::string exact_material(BoxFace f) { return f.axis == 2 ? "cap" : "wall"; }

// The OBJ text: per face a kSplit x kSplit grid of quads, vt per corner, usemtl per face.
inline std::string box_obj() {
    std::ostringstream os;
    os.precision(17);
    std::vector<Vec3> verts;
    int vt = 0;
    std::ostringstream faces;
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;
            faces << "usemtl " << exact_material({axis, side}) << "\n";
            auto point = [&](int i, int j) {
                Vec3 p;
                p[axis] = side > 0 ? kHi[axis] : kLo[axis];
                p[a] = kLo[a] + (kHi[a] - kLo[a]) * i / kSplit;
                p[b] = kLo[b] + (kHi[b] - kLo[b]) * j / kSplit;
                return p;
            };
            const int base = int(verts.size());
            for (int i = 0; i <= kSplit; ++i)
                for (int j = 0; j <= kSplit; ++j) verts.push_back(point(i, j));
            for (int i = 0; i < kSplit; ++i)
                for (int j = 0; j < kSplit; ++j) {
                    int c[4] = {base + i * (kSplit + 1) + j, base + (i + 1) * (kSplit + 1) + j,
                                base + (i + 1) * (kSplit + 1) + j + 1, base + i * (kSplit + 1) + j + 1};
                    // Outward: (a, b, axis) is right-handed, so a then b is counter-clockwise seen
                    // from +axis; the -axis side is reversed.
                    if (side < 0) std::swap(c[1], c[3]);
                    faces << "f";
                    for (int k = 0; k < 4; ++k) {
                        const Vec2 uv = exact_uv(verts[std::size_t(c[k])], {axis, side});
                        os << "vt " << uv.x() << ' ' << uv.y() << "\n";
                        faces << ' ' << c[k] + 1 << '/' << ++vt;
                    }
                    faces << "\n";
                }
        }
    std::ostringstream all;
    all.precision(17);
    for (const Vec3& p : verts) all << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << "\n";
    // Welding: the grid vertices of neighbouring faces coincide; the OBJ lists them per face.
    return all.str() + os.str() + faces.str();
}

// Distance from p to the box's surface, and the face it is closest to.
inline double box_distance(const Vec3& p, BoxFace* face = nullptr) {
    double best = 1e300;
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
            Vec3 q = p.cwiseMax(kLo).cwiseMin(kHi);
            q[axis] = side > 0 ? kHi[axis] : kLo[axis];
            const double d = (p - q).norm();
            if (d < best) {
                best = d;
                if (face) *face = {axis, side};
            }
        }
    return best;
}

// Two crack planes through the box, tilted against the grid.
inline const Vec3 kN1 = Vec3(1, 0.25, 0.1).normalized(), kP1(0.04, 0, 0);
inline const Vec3 kN2 = Vec3(0.15, 1, -0.2).normalized(), kP2(0, -0.03, 0.01);

}  // namespace cf::textured_box
