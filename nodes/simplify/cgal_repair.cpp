// CGAL translation unit: exact self-intersection detection and hole filling (ch. 6.1;
// docs/libraries.md section 3). Rarely touched, so its ~40 s compile is paid once.
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/cgal_surface_mesh.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <memory>
#include <stdexcept>

namespace cf {

namespace {
using cgal_mesh::Kernel;
using cgal_mesh::Mesh;
namespace PMP = CGAL::Polygon_mesh_processing;

using cgal_mesh::from_cgal;
using cgal_mesh::to_cgal;

// The mesh's point map, polling a cancel token every 4096 reads. PMP::self_intersections takes no
// callback, but its exact test reads the corners of every candidate pair through this map, and
// every face's box meets at least its neighbours' boxes: the box sweep between two reads is short.
struct CancellablePointMap {
    using key_type = Mesh::Vertex_index;
    using value_type = Kernel::Point_3;
    using reference = const Kernel::Point_3&;
    using category = boost::readable_property_map_tag;
    const Mesh* mesh = nullptr;
    CancelToken cancel;
    std::shared_ptr<std::size_t> reads = std::make_shared<std::size_t>(0);  // sequential search: no race
    friend reference get(const CancellablePointMap& m, key_type v) {
        if ((++*m.reads & 4095u) == 0) m.cancel.poll();
        return m.mesh->point(v);
    }
};
}  // namespace

std::vector<std::pair<int, int>> self_intersecting_pairs(const SurfaceMesh& in, const CancelToken& cancel) {
    // Build directly (no soup check): face i of the CGAL mesh is triangle i.
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vs;
    vs.reserve(in.vertices.size());
    for (const Vec3& v : in.vertices) vs.push_back(mesh.add_vertex(Kernel::Point_3(v.x(), v.y(), v.z())));
    std::vector<int> face_to_tri;
    for (std::size_t t = 0; t < in.triangles.size(); ++t) {
        if ((t & 65535u) == 0) cancel.poll();
        const Tri& tri = in.triangles[t];
        if (mesh.add_face(vs[tri[0]], vs[tri[1]], vs[tri[2]]) == Mesh::null_face())
            throw std::invalid_argument("self-intersection test needs a manifold, oriented mesh (triangle " +
                                        std::to_string(t) + " cannot be added)");
        face_to_tri.push_back(int(t));
    }
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    PMP::self_intersections(mesh.faces(), mesh, std::back_inserter(pairs),
                            CGAL::parameters::vertex_point_map(CancellablePointMap{&mesh, cancel}));
    std::vector<std::pair<int, int>> out;
    out.reserve(pairs.size());
    for (auto& [a, b] : pairs) out.emplace_back(face_to_tri[a.idx()], face_to_tri[b.idx()]);
    return out;
}

std::size_t fill_holes(SurfaceMesh& in, const CancelToken& cancel) {
    Mesh mesh = to_cgal(in, "mesh repair");
    std::vector<Mesh::Halfedge_index> borders;
    for (auto h : mesh.halfedges())
        if (mesh.is_border(h)) borders.push_back(h);
    std::size_t filled = 0;
    std::vector<char> done(mesh.number_of_halfedges(), 0);
    for (auto h : borders) {
        if (done[h.idx()] || !mesh.is_border(h)) continue;
        cancel.poll();  // per hole: the repair's holes are one-rings of a few dozen edges
        for (auto g : CGAL::halfedges_around_face(h, mesh)) done[g.idx()] = 1;
        std::vector<Mesh::Face_index> patch;
        PMP::triangulate_hole(mesh, h, std::back_inserter(patch));
        if (patch.empty()) throw std::runtime_error("hole filling failed for a boundary loop");
        ++filled;
    }
    mesh.collect_garbage();
    in = from_cgal(mesh);
    return filled;
}

}  // namespace cf
