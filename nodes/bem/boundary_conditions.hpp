#pragma once
// Boundary conditions of the SGBEM: per region either a constant displacement (Dirichlet) or a
// constant traction (Neumann) and/or a pressure p (Neumann, traction -p n with each element's own
// outward normal, so it follows curved and non-planar regions), plus optional per-element tractions
// added on Neumann elements (rigid-body coupling, thesis ch. 7.2). Every triangle must be covered.
#include "graph/value.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cf::bem {

struct RegionCondition {
    enum class Kind { displacement, traction } kind = Kind::traction;
    Vec3 value = Vec3::Zero();  // [m] for displacement, [Pa] for traction
    double pressure = 0;        // [Pa], Neumann only: adds -pressure * n per element (n outward)
};

struct BoundaryConditions {
    std::map<std::string, RegionCondition> regions;  // by region name
    std::optional<RegionCondition> others;           // "*": every region not named
    std::vector<Vec3> element_tractions;             // empty, or one per triangle [Pa]
};

// Parses "z_max: traction 0 0 1e6; z_min: displacement 0 0 0; inner: pressure 2e5; *: traction 0 0 0".
// A region may carry a traction and a pressure (they add); a pressure on a region with a
// displacement is an error naming the region. Throws std::invalid_argument quoting the offending
// clause and the expected form.
BoundaryConditions parse_boundary_conditions(const std::string& text);

// Per-element resolution of the conditions on a mesh.
struct ResolvedConditions {
    std::vector<char> dirichlet;     // per element
    std::vector<Vec3> traction;      // per element (zero on Dirichlet elements) [Pa]
    std::vector<char> node_fixed;    // per node: in the closure of Gamma_D
    std::vector<Vec3> displacement;  // per node (zero where not fixed) [m]
    bool pure_neumann() const;
};

// Throws std::invalid_argument listing every uncovered region id/name, names that match no
// region, and nodes shared by Dirichlet regions with different displacements.
ResolvedConditions resolve(const BoundaryConditions& bc, const SurfaceMesh& mesh);

// `named` lists "node:region" entries separated by ';' (the regions the conditions of solve nodes
// name; nodes/region_names_check.cpp fills it in for assemble.sgbem). Returns "" when `mesh` has each
// region with at least one triangle, else a message naming the node, the region and the mesh's
// regions.
std::string check_named_regions(const std::string& named, const SurfaceMesh& mesh);

}  // namespace cf::bem

CF_GRAPH_TYPE(cf::bem::BoundaryConditions, "BoundaryConditions");
