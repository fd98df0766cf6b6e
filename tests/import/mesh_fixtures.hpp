#pragma once
// Tiny meshes for the import/export tests, built inline, and hand-written file contents in
// every format (written byte by byte here, independently of nodes/export's writers).
#include "nodes/domain/surface_mesh.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace cf::testing {

// Unit cube [0,1]^3; faces listed as quads (outward, counter-clockwise seen from outside).
inline std::vector<Vec3> cube_vertices() {
    return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
}
inline std::vector<std::array<int, 4>> cube_quads() {
    return {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
}
// The 12-triangle cube: each quad (a, b, c, d) as (a, b, c), (a, c, d). Volume 1, area 6.
inline SurfaceMesh unit_cube() {
    SurfaceMesh m;
    m.vertices = cube_vertices();
    for (const auto& q : cube_quads()) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}
// Corner tetrahedron (0,0,0), e_x, e_y, e_z. Volume 1/6, area 3/2 + sqrt(3)/2.
inline SurfaceMesh tetrahedron() {
    SurfaceMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

inline std::string cube_obj() {
    return "# unit cube\n"
           "o cube\n"
           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "vn 0 0 1\n"
           "g all\n"
           "f 1 4 3 2\n"
           "f 5/1/1 6/1/1 7/1/1 8/1/1\n"
           "f 1//1 2//1 6//1 5//1\n"
           "f 3 4 8 7\n"
           "f -8 -4 -1 -5\n"  // relative indices: 1 5 8 4
           "f 2 3 7 6\n";
}

inline std::string cube_off() {
    std::string s = "OFF\n# unit cube\n8 12 0\n";
    for (const Vec3& p : cube_vertices()) s += std::to_string(int(p.x())) + " " + std::to_string(int(p.y())) + " " +
                                               std::to_string(int(p.z())) + "\n";
    for (const Tri& t : unit_cube().triangles)
        s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    return s;
}

inline std::string cube_ply_ascii() {
    std::string s =
        "ply\nformat ascii 1.0\ncomment unit cube\nelement vertex 8\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement face 6\nproperty list uchar int vertex_indices\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    for (const Vec3& p : cube_vertices())
        s += std::to_string(int(p.x())) + " " + std::to_string(int(p.y())) + " " + std::to_string(int(p.z())) + " 255\n";
    for (const auto& q : cube_quads())
        s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
             std::to_string(q[3]) + "\n";
    s += "0 1\n";
    return s;
}

// Byte-level builder for binary files.
struct Bytes {
    std::string data;
    bool big_endian = false;
    void raw(const void* p, std::size_t n) {
        std::string b(static_cast<const char*>(p), n);
        if (big_endian) std::reverse(b.begin(), b.end());
        data += b;
    }
    void f32(float v) { raw(&v, 4); }
    void f64(double v) { raw(&v, 8); }
    void i32(std::int32_t v) { raw(&v, 4); }
    void u32(std::uint32_t v) { raw(&v, 4); }
    void u16(std::uint16_t v) { raw(&v, 2); }
    void u8(std::uint8_t v) { raw(&v, 1); }
};

// Binary PLY of a mesh: float vertices, an int "flags" property, uchar/int face lists.
inline std::string mesh_ply_binary(const SurfaceMesh& m, bool big_endian) {
    Bytes b;
    b.big_endian = big_endian;
    b.data = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
             " 1.0\nelement vertex " + std::to_string(m.vertices.size()) +
             "\nproperty double x\nproperty double y\nproperty double z\nproperty int flags\nelement face " +
             std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : m.vertices) {
        b.f64(p.x());
        b.f64(p.y());
        b.f64(p.z());
        b.i32(7);
    }
    for (const Tri& t : m.triangles) {
        b.u8(3);
        for (int v : t) b.i32(v);
    }
    return b.data;
}

inline std::string mesh_stl_ascii(const SurfaceMesh& m) {
    std::string s = "solid test\n";
    for (const Tri& t : m.triangles) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (int v : t) {
            char line[128];
            std::snprintf(line, sizeof line, "      vertex %.17g %.17g %.17g\n", m.vertices[v].x(), m.vertices[v].y(),
                          m.vertices[v].z());
            s += line;
        }
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid test\n";
}

inline std::string mesh_stl_binary(const SurfaceMesh& m) {
    Bytes b;
    b.data = std::string(80, 'x');
    b.u32(static_cast<std::uint32_t>(m.triangles.size()));
    for (const Tri& t : m.triangles) {
        for (int k = 0; k < 3; ++k) b.f32(0);
        for (int v : t)
            for (int k = 0; k < 3; ++k) b.f32(static_cast<float>(m.vertices[v][k]));
        b.u16(0);
    }
    return b.data;
}

inline std::string mesh_obj(const SurfaceMesh& m) {
    std::string s;
    char line[128];
    for (const Vec3& p : m.vertices) {
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
        s += line;
    }
    for (const Tri& t : m.triangles)
        s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
    return s;
}

inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

// A mesh with its triangles in another order and orientation flips applied.
inline SurfaceMesh with_flipped(SurfaceMesh m, const std::vector<int>& flip) {
    for (int t : flip) std::swap(m.triangles[t][1], m.triangles[t][2]);
    return m;
}

// Appends `b` to `a` (vertices renumbered).
inline SurfaceMesh merged(SurfaceMesh a, const SurfaceMesh& b) {
    const int off = static_cast<int>(a.vertices.size());
    for (const Vec3& p : b.vertices) a.vertices.push_back(p);
    for (const Tri& t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    return a;
}

inline SurfaceMesh transformed(SurfaceMesh m, double scale, const Vec3& shift) {
    for (Vec3& p : m.vertices) p = p * scale + shift;
    return m;
}

}  // namespace cf::testing
