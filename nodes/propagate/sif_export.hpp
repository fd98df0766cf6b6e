#pragma once
// The stress intensities along every crack front, written out (so a run's mechanics can be checked
// without C++): one row per front node (the values propagation uses, ch. 4.5.2: each node the mean
// of its two edges) or per front edge (the edge midpoint), in front order, with the position, the tip
// frame (e1 forward, e2 crack normal, e3 = e1 x e2), K_I, K_II, K_III [Pa sqrt(m)], the effective
// K of eq. (4.7) and the toughness K_c there. As CSV and as VTK polylines (one per front).
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/fields/scalar_field.hpp"

#include <filesystem>
#include <vector>

namespace cf::propagate {

struct FrontSifRow {
    int front = 0, edge = 0;       // front index (extract_fronts order), edge (or node) index along it
    int front_edges = 0;           // edges (or nodes) of that (closed) front
    int region = 0;                // the crack
    int v0 = -1, v1 = -1;          // crack-mesh vertex ids (v0 < v1); a node row: v0 the node, v1 = -1
    Vec3 midpoint = Vec3::Zero();  // edge midpoint or node position [m]
    Vec3 e1, e2, e3;
    double KI = 0, KII = 0, KIII = 0, K_eff = 0;
    double K_c = -1;               // [Pa sqrt(m)]; -1 without a toughness field
};

// Rows for the edges of `cracks`' fronts that have a record in `sifs` (fronts that were not
// evaluated, e.g. stopped ones under the estimator, are left out). Throws std::invalid_argument
// when a record names a vertex the mesh does not have.
std::vector<FrontSifRow> front_sif_rows(const SurfaceMesh& cracks, const std::vector<bem::FrontEdgeSif>& sifs, double nu,
                                        const ScalarField* toughness);

// One row per front node: K and frame the mean of the node's front edges that have a record
// (both on a closed front; ch. 4.5.2, as propagate.fronts assigns them), the frame
// re-orthonormalised, K_eff and K_c at the node. Nodes with no evaluated edge are left out.
std::vector<FrontSifRow> front_node_sif_rows(const SurfaceMesh& cracks, const std::vector<bem::FrontEdgeSif>& sifs, double nu,
                                             const ScalarField* toughness);

// Atomic writes; throw std::runtime_error naming the path. Node rows (node_rows) get the header
// front,node,crack,vertex,... instead of front,edge,crack,v0,v1,... (the same columns otherwise).
void write_front_sifs_csv(const std::filesystem::path& path, const std::vector<FrontSifRow>& rows, bool node_rows = false);
void write_front_sifs_vtp(const std::filesystem::path& path, const std::vector<FrontSifRow>& rows);

}  // namespace cf::propagate
