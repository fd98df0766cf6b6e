#pragma once
// Quadrature rules for Galerkin BEM on flat triangles (sgbem-math.md §3).
// Points are given in the unit right triangle {(s,t): s,t >= 0, s+t <= 1}; a physical point is
// A + s (B-A) + t (C-A). Single-triangle weights sum to 1/2, pair weights to 1/4, so a physical
// integral is sum_q w_q f(x_q) * 2|T| (single) or sum_q w_q f(x_q, y_q) * (2|T_x|)(2|T_y|) (pairs).
#include <vector>

namespace cf::bem {

// n-point Gauss-Legendre rule on [0, 1] (weights sum to 1).
void gauss_legendre_01(int n, std::vector<double>& points, std::vector<double>& weights);

struct TriangleRule {
    std::vector<double> s, t, w;
    std::size_t size() const { return w.size(); }
};

// Collapsed (Duffy) Gauss rule with n*n points; exact for polynomials of degree 2n-2.
TriangleRule collapsed_gauss_triangle_rule(int n);
// Symmetric rules: 3 points (degree 2) and 6 points (degree 4, Strang-Fix/Dunavant).
TriangleRule symmetric_triangle_rule_3();
TriangleRule symmetric_triangle_rule_6();

// How two triangles of the same mesh touch.
enum class PairKind { identical, common_edge, common_vertex, separated };

// Sauter-Schwab rule for a touching pair (6/5/2 regions of n^4 points each). For common_edge
// the shared edge is local vertices (0,1) of both triangles, in the same order; for
// common_vertex the shared vertex is local vertex 0 of both.
struct PairRule {
    std::vector<double> sx, tx, sy, ty, w;
    std::size_t size() const { return w.size(); }
};
PairRule sauter_schwab_rule(PairKind kind, int n);

// Far-field zoning by rho = distance(centroids) / max(diameters) (sgbem-math.md §3, measured
// errors for 1/r there). Zone rules, from cheapest: 3-point, 6-point, then collapsed Gauss with
// 3x3, 4x4, ..., 8x8 points. Base zone: rho >= 12 -> 3 points; [6,12) -> 6; [3,6) -> 3x3;
// [1.5,3) -> 4x4; [0.75,1.5) -> 5x5; < 0.75 (near, not touching) -> 6x6. `boost` moves every pair up that many
// zones (tests use boost 1 for about 10x smaller far-field error).
constexpr int num_regular_zones = 8;
int regular_zone(double rho, int boost);
// The triangle rule of a zone (0 .. num_regular_zones-1).
const TriangleRule& regular_zone_rule(int zone);

}  // namespace cf::bem
