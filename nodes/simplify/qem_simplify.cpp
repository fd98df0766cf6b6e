// CGAL translation unit: QEM simplification with Garland-Heckbert plane policies (ch. 6.1;
// docs/libraries.md section 2: 0 self-intersections on armadillo -> 1000 F, unlike Lindstrom-Turk).
#include "nodes/simplify/mesh_repair.hpp"
#include "nodes/simplify/cgal_surface_mesh.hpp"

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
using cgal_mesh::Kernel;
using cgal_mesh::Mesh;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

// A stop predicate that also polls the cancel token every 1024 collapses (a collapse takes
// microseconds; a million-triangle simplification takes seconds).
template <class Stop>
struct CancellableStop {
    Stop stop;
    CancelToken cancel;
    mutable std::size_t calls = 0;
    template <class FT, class Profile>
    bool operator()(const FT& cost, const Profile& profile, std::size_t initial, std::size_t current) const {
        if ((++calls & 1023u) == 0) cancel.poll();
        return stop(cost, profile, initial, current);
    }
};
}  // namespace

SurfaceMesh simplify_to_count(const SurfaceMesh& in, std::size_t target_triangles, const CancelToken& cancel) {
    Mesh mesh = cgal_mesh::to_cgal(in, "QEM simplification");
    if (!CGAL::is_closed(mesh)) throw std::invalid_argument("QEM simplification needs a closed mesh");
    if (target_triangles < in.triangles.size()) {
        // Closed triangle mesh: E = 3 F / 2.
        const CancellableStop<SMS::Count_stop_predicate<Mesh>> stop{SMS::Count_stop_predicate<Mesh>(3 * target_triangles / 2),
                                                                    cancel};
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
    return cgal_mesh::from_cgal(mesh);
}

}  // namespace cf
