#pragma once
// Crack fronts of crack sheets (thesis ch. 4.5.2). Crack sheets are one cf::SurfaceMesh whose
// regions are the cracks, as the BEM stage stores them (bem::CrackOperators::cracks); a front is
// an ordered chain of that mesh's boundary vertices with per-node SIFs and local frames.
#include "nodes/propagate/propagation_law.hpp"

#include <vector>

namespace cf::propagate {

// Local crack-front frame: n1 crack-surface normal, n2 forward in-plane normal, n3 tangent
// (right-handed, n2 = n3 x n1).
struct FrontFrame {
    Vec3 n1 = Vec3::UnitZ(), n2 = Vec3::UnitX(), n3 = Vec3::UnitY();
};

// Re-orthonormalises a frame (ch. 4.5.2): normalise n1, make n3 orthogonal to n1 and normalise,
// n2 = n3 x n1. Throws std::invalid_argument when n1 or n3 vanish or are parallel.
FrontFrame orthonormalised(const Vec3& n1, const Vec3& n3);

struct CrackFront {
    std::vector<int> nodes;          // crack-mesh vertex ids, ordered along the front
    bool closed = true;              // a loop (the usual case) or an open polyline
    int region = 0;                  // the crack (region of the crack mesh)
    std::vector<Sifs> sifs;          // per node (empty until assigned)
    std::vector<FrontFrame> frames;  // per node (empty until assigned)
    std::size_t num_edges() const { return closed ? nodes.size() : (nodes.empty() ? 0 : nodes.size() - 1); }
};

// Fronts of the crack sheets: boundary edges chained into closed loops, each directed as in
// its triangle (a, b, c) -> a -> b, so n1 = triangle normal, n3 = (b - a)/|b - a| and
// n2 = n3 x n1 points away from the crack. Ordered by region, then smallest vertex id.
// Throws std::invalid_argument naming the vertex when the boundary is not a set of simple loops.
std::vector<CrackFront> extract_fronts(const SurfaceMesh& cracks);

// Per-edge SIFs and frame of a front edge (a -> b); e.g. from displacement correlation.
struct EdgeSifs {
    int v0 = -1, v1 = -1;
    Sifs K;
    FrontFrame frame;
};

// Averages edge SIFs and frames to the nodes of `front` (ch. 4.5.2): each node takes 50 % from
// each adjacent edge (open ends: 100 % of their edge), then frames are re-orthonormalised.
// Throws std::invalid_argument naming the edge when an edge of the front has no entry.
void assign_node_sifs(CrackFront& front, const std::vector<EdgeSifs>& edges);

}  // namespace cf::propagate
