#pragma once
// Per-corner attributes (SurfaceMesh::corner_uv / corner_normal) as formats with per-vertex
// attributes need them (PLY, glTF): one output vertex per distinct (vertex, uv, normal), so a
// texture seam or a crease splits a vertex and nothing else does.
#include "nodes/domain/surface_mesh.hpp"

#include <vector>

namespace cf {

struct CornerVertices {
    std::vector<int> vertex;      // output vertex -> mesh vertex
    std::vector<Vec2> uv;         // per output vertex (empty when the mesh has none)
    std::vector<Vec3> normal;     // per output vertex (empty when the mesh has none)
    std::vector<Tri> triangles;   // the mesh's triangles in output vertices
};

CornerVertices split_corner_vertices(const SurfaceMesh& m);

}  // namespace cf
