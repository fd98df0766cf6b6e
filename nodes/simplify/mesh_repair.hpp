#pragma once
// CGAL-backed mesh operations behind a plain cf::SurfaceMesh interface (CGAL is included only
// by qem_simplify.cpp and cgal_repair.cpp; CGAL adds -frounding-math and slow headers).
#include "graph/cancel_token.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <functional>
#include <utility>
#include <vector>

namespace cf {

// Quadric-error edge collapse (Garland-Heckbert plane quadrics, CGAL SMS) of a closed manifold
// mesh down to `target_triangles` (closed meshes: stops at 3 F / 2 edges). Keeps topology;
// stops early where the genus forbids further collapses. Throws std::invalid_argument if the
// input is not a closed manifold polygon mesh.
SurfaceMesh simplify_to_count(const SurfaceMesh& mesh, std::size_t target_triangles,
                              const CancelToken& cancel = CancelToken::current());

// Pairs of triangles that intersect other than in their shared vertices/edge (exact predicates).
// Polls `cancel` throughout the search (through the point map CGAL reads every candidate pair with).
std::vector<std::pair<int, int>> self_intersecting_pairs(const SurfaceMesh& mesh,
                                                         const CancelToken& cancel = CancelToken::current());

// Fills every hole (boundary loop) of a manifold mesh by minimum-weight triangulation without
// new vertices. Returns the number of holes filled. Throws std::runtime_error if a hole cannot
// be filled.
std::size_t fill_holes(SurfaceMesh& mesh, const CancelToken& cancel = CancelToken::current());

}  // namespace cf

namespace cf {

// Isotropic remeshing (Botsch-Kobbelt: split edges longer than 4/3 L, collapse those shorter than
// 4/5 L, flip towards valence 6, tangential relaxation, projection onto `mesh` as it was given)
// with target edge length `edge_length` [m], `iterations` rounds. Edges whose dihedral is below
// `feature_dihedral_deg` (180 = flat, see mesh_quality.hpp) are kept as polylines that vertices
// move along, so box edges stay straight, unless their dihedral is below `fold_dihedral_deg` (a fold,
// not a feature); with `bevels` also the edges of narrow bevels (dihedral below 150 degrees turning
// within a quarter of `edge_length`: a box edge rounded to a voxel). Vertices are projected by `project` (the closest point of
// the surface the mesh stands for), or, if it is empty, onto `mesh` as given. The input must be a
// closed manifold oriented mesh.
SurfaceMesh isotropic_remesh(const SurfaceMesh& mesh, double edge_length, int iterations, double feature_dihedral_deg,
                             double fold_dihedral_deg, bool bevels, const std::function<Vec3(const Vec3&)>& project = {},
                             const CancelToken& cancel = CancelToken::current());

}  // namespace cf
