#pragma once
// A closed (or, for cracks, open) triangle surface with per-triangle boundary-region ids.
// This is the mesh type every stage exchanges: import/shape produce it, simplify rebuilds it,
// assemble reads it, export writes it. Units: metres.
#include "graph/value.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross(): every user of Vec3 needs it
#include <array>
#include <string>
#include <vector>

namespace cf {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;
using Tri = std::array<int, 3>;

struct SurfaceMesh {
    std::vector<Vec3> vertices;
    std::vector<Tri> triangles;        // counter-clockwise seen from outside (outward normals)
    std::vector<int> region;           // one region id per triangle; empty means "all region 0"
    std::vector<std::string> region_names;  // region_names[id]; may be shorter than max id + 1
    // Optional per-corner attributes an artist's file brings (OBJ vt/vn, PLY u v / nx ny nz), carried
    // to the fragment meshes (nodes/segment/surface_fragments.hpp). Empty: none; otherwise one entry
    // per triangle, corners in the triangle's order. A stage that rebuilds the triangles leaves them
    // empty; has_uv()/has_normals() also treat a stale size as none.
    std::vector<std::array<Vec2, 3>> corner_uv;
    std::vector<std::array<Vec3, 3>> corner_normal;

    std::size_t num_vertices() const { return vertices.size(); }
    std::size_t num_triangles() const { return triangles.size(); }
    int region_of(std::size_t t) const { return region.empty() ? 0 : region[t]; }
    std::string region_name(int id) const;  // name or "region<id>"
    int num_regions() const;                // max(region ids, names) + 1; at least 1 if non-empty
    bool has_uv() const { return !triangles.empty() && corner_uv.size() == triangles.size(); }
    bool has_normals() const { return !triangles.empty() && corner_normal.size() == triangles.size(); }
};

// Geometry of one triangle.
Vec3 triangle_normal_unnormalised(const SurfaceMesh& m, std::size_t t);  // (b-a) x (c-a), |.| = 2 area
Vec3 triangle_normal(const SurfaceMesh& m, std::size_t t);               // unit; zero for degenerate
double triangle_area(const SurfaceMesh& m, std::size_t t);
Vec3 triangle_centroid(const SurfaceMesh& m, std::size_t t);

// Whole-surface measures.
double surface_area(const SurfaceMesh& m);
// Signed enclosed volume by the divergence theorem; positive for a closed outward-oriented mesh.
double signed_volume(const SurfaceMesh& m);
struct Box3 { Vec3 min, max; Vec3 extent() const { return max - min; } };
Box3 bounding_box(const SurfaceMesh& m);

}  // namespace cf

CF_GRAPH_TYPE(cf::SurfaceMesh, "SurfaceMesh");
