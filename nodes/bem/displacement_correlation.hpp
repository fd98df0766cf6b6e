#pragma once
// Stress intensity factors by displacement correlation (thesis eq. 2.39 with the full-jump
// constant of sgbem-math.md §5/§9): with the full jump [u] = u+ - u- at distance d behind the
// front, K_I = mu sqrt(2 pi) [u].e2 / (4 (1-nu) sqrt d), K_II likewise with e1,
// K_III = mu sqrt(2 pi) [u].e3 / (4 sqrt d). (Eq. 2.39's mu sqrt(pi) du / (c sqrt(2d)) holds for the
// one-face displacement, half the jump.)
#include "graph/value.hpp"
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Geometry>

#include <vector>

namespace cf::bem {

struct FrontEdgeSif {
    int v0 = -1, v1 = -1;  // front edge (crack mesh vertex ids)
    int interior = -1;     // where [u] is read: the third node of the front triangle, or (when that node is
                           // itself on the front) the nearest interior neighbour behind the edge
    double d = 0;          // its distance behind the front edge [m]
    Vec3 e1, e2, e3;       // tip frame: propagation direction, crack normal, front tangent
    double KI = 0, KII = 0, KIII = 0;  // [Pa sqrt(m)]
};

// Tip frame of front edge (v0, v1) of crack triangle `tri`: e2 the triangle's unit normal, e1 in its
// plane across the edge and away from the triangle's third vertex, e3 = e1 x e2 (the frame every
// FrontEdgeSif uses, whichever method fills it). Returns the third vertex.
int front_edge_frame(const SurfaceMesh& cracks, int tri, int v0, int v1, Vec3& e1, Vec3& e2, Vec3& e3);

// One entry per boundary edge of the crack sheets. Throws std::invalid_argument when a front
// crack has no interior node behind it.
std::vector<FrontEdgeSif> displacement_correlation_sifs(const SurfaceMesh& cracks, const std::vector<Vec3>& opening,
                                                        double E, double nu);

}  // namespace cf::bem

CF_GRAPH_TYPE(std::vector<cf::bem::FrontEdgeSif>, "FrontSifs");  // one per crack-front edge
