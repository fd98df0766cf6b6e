#pragma once
// Conversion between cf::SurfaceMesh and CGAL::Surface_mesh, shared by the two CGAL
// translation units (qem_simplify.cpp, cgal_repair.cpp). Include it only there: CGAL headers
// are slow to compile and add -frounding-math.
#include "nodes/domain/surface_mesh.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace cf::cgal_mesh {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

// Throws std::invalid_argument "<purpose> needs a manifold, consistently oriented mesh" when the
// triangles do not form a polygon mesh.
inline Mesh to_cgal(const SurfaceMesh& in, const std::string& purpose) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    std::vector<Kernel::Point_3> points;
    points.reserve(in.vertices.size());
    for (const Vec3& v : in.vertices) points.emplace_back(v.x(), v.y(), v.z());
    std::vector<std::vector<std::size_t>> polys;
    polys.reserve(in.triangles.size());
    for (const Tri& t : in.triangles) polys.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
    if (!PMP::is_polygon_soup_a_polygon_mesh(polys))
        throw std::invalid_argument(purpose + " needs a manifold, consistently oriented mesh");
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polys, mesh);
    return mesh;
}

// Vertices and faces in CGAL index order; call mesh.collect_garbage() first after removals.
inline SurfaceMesh from_cgal(const Mesh& mesh) {
    SurfaceMesh out;
    out.vertices.reserve(mesh.number_of_vertices());
    for (auto v : mesh.vertices()) {
        const auto& p = mesh.point(v);
        out.vertices.emplace_back(p.x(), p.y(), p.z());
    }
    out.triangles.reserve(mesh.number_of_faces());
    for (auto f : mesh.faces()) {
        Tri t{};
        int k = 0;
        for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) t[k++] = int(v.idx());
        out.triangles.push_back(t);
    }
    return out;
}

}  // namespace cf::cgal_mesh
