// The only translation unit of the stage that includes CGAL (slow to compile).
#include "nodes/initiate/sheet_mesher.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <map>
#include <stdexcept>

namespace cf::initiate {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<K>;
using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<CDT>;
using Point = CDT::Point;
}  // namespace

SurfaceMesh mesh_planar_region(const std::vector<Vec2>& boundary, const Vec2& interior_point, double max_edge,
                               const Vec3& origin, const Vec3& t1, const Vec3& t2, const std::string& name) {
    if (boundary.size() < 3) throw std::invalid_argument("planar crack mesh: the boundary has fewer than 3 points");
    if (!(max_edge > 0)) throw std::invalid_argument("planar crack mesh: the target edge length must be > 0 m");
    CDT cdt;
    std::vector<CDT::Vertex_handle> rim;
    rim.reserve(boundary.size());
    for (const Vec2& p : boundary) rim.push_back(cdt.insert(Point(p.x(), p.y())));
    for (std::size_t i = 0; i < rim.size(); ++i) cdt.insert_constraint(rim[i], rim[(i + 1) % rim.size()]);
    cdt.insert(Point(interior_point.x(), interior_point.y()));
    // Shape bound 0.125 = the ~20.6 degree minimum angle Ruppert refinement guarantees.
    CGAL::refine_Delaunay_mesh_2(cdt, Criteria(0.125, max_edge));

    SurfaceMesh m;
    std::map<const void*, int> index;  // by vertex address; ids follow the face order (deterministic)
    auto id = [&](CDT::Vertex_handle v) {
        auto [it, added] = index.emplace(static_cast<const void*>(&*v), static_cast<int>(m.vertices.size()));
        if (added) m.vertices.push_back(origin + v->point().x() * t1 + v->point().y() * t2);
        return it->second;
    };
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (!f->is_in_domain()) continue;
        // CGAL faces are counter-clockwise in (x, y): normal t1 x t2.
        m.triangles.push_back({id(f->vertex(0)), id(f->vertex(1)), id(f->vertex(2))});
    }
    m.region.assign(m.triangles.size(), 0);
    m.region_names = {name};
    return m;
}

}  // namespace cf::initiate
