// CGAL translation unit: isotropic remeshing of the QEM mesh (issue 13: QEM alone leaves needles
// and caps with angles down to 0.04 degrees on flat faces and rounded edges, whose plane quadrics
// vanish or coincide; element shape is what the BEM's conditioning depends on).
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/cgal_surface_mesh.hpp"

#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <cmath>
#include <functional>

namespace cf {

namespace {
// CGAL's projection_functor: the new position of a vertex, from its current one.
struct ProjectVertex {
    const cgal_mesh::Mesh* mesh;
    const std::function<Vec3(const Vec3&)>* project;
    cgal_mesh::Kernel::Point_3 operator()(cgal_mesh::Mesh::Vertex_index v) const {
        const auto& p = mesh->point(v);
        const Vec3 q = (*project)(Vec3(p.x(), p.y(), p.z()));
        return {q.x(), q.y(), q.z()};
    }
};
}  // namespace

SurfaceMesh isotropic_remesh(const SurfaceMesh& in, double edge_length, int iterations, double feature_dihedral_deg,
                             double fold_dihedral_deg, const std::function<Vec3(const Vec3&)>& project, const CancelToken& cancel) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    using cgal_mesh::Mesh;
    Mesh mesh = cgal_mesh::to_cgal(in, "isotropic remeshing");
    // detect_sharp_edges takes the angle between the face normals: 180 - dihedral.
    auto feature = mesh.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
    if (feature_dihedral_deg > 0) PMP::detect_sharp_edges(mesh, 180.0 - feature_dihedral_deg, feature);
    // An edge sharper than `fold_dihedral_deg` is a fold QEM left (a needle turned over its
    // neighbour), not a feature to keep: left free, it is remeshed and projected away.
    for (auto e : mesh.edges()) {
        if (!feature[e]) continue;
        const auto h = mesh.halfedge(e);
        const auto n1 = PMP::compute_face_normal(mesh.face(h), mesh);
        const auto n2 = PMP::compute_face_normal(mesh.face(mesh.opposite(h)), mesh);
        const double angle = std::atan2(std::sqrt(CGAL::cross_product(n1, n2).squared_length()), n1 * n2) * 180 / CGAL_PI;
        if (180 - angle < fold_dihedral_deg) feature[e] = false;
    }
    cancel.poll();  // a few rounds on a few thousand triangles take milliseconds
    auto np = CGAL::parameters::number_of_iterations(unsigned(iterations))
                  .edge_is_constrained_map(feature)
                  .protect_constraints(false)
                  .relax_constraints(true);
    if (project)
        PMP::isotropic_remeshing(faces(mesh), edge_length, mesh, np.projection_functor(ProjectVertex{&mesh, &project}));
    else
        PMP::isotropic_remeshing(faces(mesh), edge_length, mesh, np);
    mesh.collect_garbage();
    return cgal_mesh::from_cgal(mesh);
}

}  // namespace cf
