#pragma once
// Topology of a triangle surface: is it closed, 2-manifold, consistently oriented, free of
// degenerate triangles? Shapes assert these of their output; import reports them for a file.
// The BEM needs a closed, consistently outward-oriented boundary (thesis App. A (11): every
// boundary element in exactly one region; ch. 2: the boundary integral is over a closed surface).
#include "nodes/domain/surface_mesh.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace cf {

struct MeshTopologyReport {
    std::size_t vertices = 0;               // vertices referenced by at least one triangle
    std::size_t unreferenced_vertices = 0;  // vertices no triangle uses
    std::size_t edges = 0;                  // distinct undirected edges
    std::size_t triangles = 0;
    std::size_t boundary_edges = 0;         // edges with exactly one triangle (a hole's rim)
    std::size_t nonmanifold_edges = 0;      // edges with three or more triangles
    std::size_t misoriented_edges = 0;      // two-triangle edges traversed the same way by both
    std::size_t nonmanifold_vertices = 0;   // vertices whose triangles form more than one fan
    std::size_t degenerate_triangles = 0;   // repeated vertex, bad index, or (almost) zero area
    std::size_t components = 0;             // edge-connected pieces
    long long euler_characteristic = 0;     // V - E + F over referenced vertices

    bool closed() const { return boundary_edges == 0; }
    bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
    bool consistently_oriented() const { return misoriented_edges == 0; }
    // Closed, manifold, consistently oriented and without degenerate triangles.
    bool is_closed_manifold() const {
        return closed() && manifold() && consistently_oriented() && degenerate_triangles == 0 && triangles > 0;
    }
    // One line naming every problem found, or "closed 2-manifold, consistently oriented".
    std::string describe() const;
};

// A triangle counts as degenerate when twice its area is at most
// degenerate_ratio * (longest edge)^2, i.e. its height over the longest edge is that small a
// fraction of the edge: scale-free, so it works in millimetres and kilometres alike.
MeshTopologyReport check_topology(const SurfaceMesh& mesh, double degenerate_ratio = 1e-12);

// The edge-connected piece of every triangle, numbered 0, 1, ... in the order of each piece's first
// triangle (check_topology's `components` pieces); -1 for a triangle with an invalid index or a
// repeated corner.
std::vector<int> triangle_components(const SurfaceMesh& mesh);

}  // namespace cf
