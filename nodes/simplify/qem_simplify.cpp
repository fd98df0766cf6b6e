// CGAL translation unit: QEM simplification with Garland-Heckbert plane policies (ch. 6.1;
// docs/libraries.md section 2: 0 self-intersections on armadillo -> 1000 F, unlike Lindstrom-Turk).
#include "nodes/simplify/mesh_repair.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <stdexcept>

namespace cf {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;
}  // namespace

SurfaceMesh simplify_to_count(const SurfaceMesh& in, std::size_t target_triangles) {
    std::vector<Kernel::Point_3> points;
    points.reserve(in.vertices.size());
    for (const Vec3& v : in.vertices) points.emplace_back(v.x(), v.y(), v.z());
    std::vector<std::vector<std::size_t>> polys;
    polys.reserve(in.triangles.size());
    for (const Tri& t : in.triangles) polys.push_back({std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2])});
    if (!PMP::is_polygon_soup_a_polygon_mesh(polys))
        throw std::invalid_argument("QEM simplification needs a manifold, consistently oriented mesh");
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polys, mesh);
    if (!CGAL::is_closed(mesh)) throw std::invalid_argument("QEM simplification needs a closed mesh");
    if (target_triangles < in.triangles.size()) {
        // Closed triangle mesh: E = 3 F / 2.
        SMS::Count_stop_predicate<Mesh> stop(3 * target_triangles / 2);
        SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> gh(mesh);
        // On flat faces every plane quadric vanishes, so a collapse that folds a triangle over
        // its neighbour or flattens it to zero area costs nothing; the filter rejects any
        // collapse that turns a surviving triangle's normal by 90 degrees or more (or zeroes it).
        SMS::edge_collapse(mesh, stop,
                           CGAL::parameters::get_cost(gh.get_cost())
                               .get_placement(gh.get_placement())
                               .filter(SMS::Bounded_normal_change_filter<>()));
        mesh.collect_garbage();
    }
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

}  // namespace cf
