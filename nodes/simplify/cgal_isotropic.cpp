// CGAL translation unit: isotropic remeshing of the QEM mesh (issue 13: QEM alone leaves needles
// and caps with angles down to 0.04 degrees on flat faces and rounded edges, whose plane quadrics
// vanish or coincide; element shape is what the BEM's conditioning depends on).
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/cgal_surface_mesh.hpp"

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
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
                             double fold_dihedral_deg, bool bevels, const std::function<Vec3(const Vec3&)>& project,
                             const CancelToken& cancel) {
    namespace PMP = CGAL::Polygon_mesh_processing;
    using cgal_mesh::Mesh;
    Mesh mesh = cgal_mesh::to_cgal(in, "isotropic remeshing");
    auto feature = mesh.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
    // Features: edges sharper than `feature_dihedral_deg`, and with `bevels` edges of a narrow bevel (a rounded
    // box edge of radius ~r_f, which QEM leaves as a strip of two 135-degree edges): dihedral below
    // 150 degrees with a turning radius (mean height of the two triangles over the edge divided by
    // the turning angle) below a quarter of the target edge length. Smooth curvature (the bunny's
    // back at 4x the target count) turns as much only over a radius of elements.
    // An edge sharper than `fold_dihedral_deg` is a fold QEM left (a needle turned over its
    // neighbour), not a feature to keep: left free, it is remeshed and projected away.
    for (auto e : mesh.edges()) {
        const auto h = mesh.halfedge(e);
        if (mesh.is_border(e)) continue;
        const auto f1 = mesh.face(h), f2 = mesh.face(mesh.opposite(h));
        const auto n1 = PMP::compute_face_normal(f1, mesh);
        const auto n2 = PMP::compute_face_normal(f2, mesh);
        const double turn = std::atan2(std::sqrt(CGAL::cross_product(n1, n2).squared_length()), n1 * n2);
        const double dihedral = 180 - turn * 180 / CGAL_PI;
        if (dihedral < fold_dihedral_deg) continue;
        if (dihedral < feature_dihedral_deg) {
            feature[e] = true;
            continue;
        }
        if (!bevels || dihedral >= 150) continue;
        const double len = std::sqrt(CGAL::squared_distance(mesh.point(mesh.source(h)), mesh.point(mesh.target(h))));
        const double heights = (PMP::face_area(f1, mesh) + PMP::face_area(f2, mesh)) / len;  // mean height (h1 + h2) / 2
        feature[e] = len > 0 && heights / turn < 0.25 * edge_length;
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
