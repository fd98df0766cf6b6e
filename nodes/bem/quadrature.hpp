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

// n-point Gauss-Legendre rule on [0, 1] composed with the endpoint-graded map v = w^2 (3 - 2 w)
// (weights times 6 w (1 - w)): integrands with v^(-1/2) or (1 - v)^(-1/2) endpoint singularities
// become smooth in w (square-root crack-front elements, tip_elements.hpp).
void graded_gauss_01(int n, std::vector<double>& points, std::vector<double>& weights);

// Collapsed (Duffy) Gauss rule with n*n points; exact for polynomials of degree 2n-2. graded: both
// directions use graded_gauss_01, so 1/sqrt singularities on the triangle's edges and corners are absorbed.
TriangleRule collapsed_gauss_triangle_rule(int n, bool graded = false);
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
// graded: every one of the four directions uses graded_gauss_01. The triangles' edges lie on faces,
// edges or corners of the unit 4-cube of these rules, so a factor 1/sqrt(distance to an edge) on either
// triangle (square-root front elements) is absorbed as well as the 1/r of the pair.
PairRule sauter_schwab_rule(PairKind kind, int n, bool graded = false);

// Far-field zoning by rho = distance(centroids) / max(diameters). Zone rules, from cheapest:
// 3-point (degree 2), 6-point (degree 4), then collapsed Gauss 4x4, 5x5, 6x6, 7x7, 8x8, 10x10 (the 3x3
// collapsed rule is left out: the 6-point rule was more accurate at every rho measured).
// Base zones, chosen for a worst per-pair error of 3e-6 (below the n = 5 Sauter-Schwab error of
// touching pairs), measured on 600 random pairs per rho (shape ratio diameter*perimeter/(2 area)
// < 12, gap >= 0.1 diameter) against 16x16 collapsed Gauss; the error of a pair is the largest of
// |dI1|/I1, |dIR_ij|/I1 and |dIK| h/I1 (the last is the relative error of the K-block entries):
//   rho >= 16: 3 points (1.3e-6 at rho 16);   [3, 16): 6 points (2.6e-6 at 3);
//   [2, 3): 4x4 (2.0e-6 at 2);   [1.5, 2): 5x5 (1.1e-6 at 1.5);   < 1.5: 6x6 (4.2e-7 at 1.25).
// Below rho = 1.25 no rule of this list reaches 3e-6 at a sensible cost (6x6: 2.1e-5 at rho 1,
// 2.6e-3 at 0.75; 8x8 still 4.4e-4 at 0.75): those near, non-touching pairs would need subdivision.
// They keep 6x6, which is at least as accurate as the previous table (25 points for [0.75, 1.5),
// 36 below). tests/bem/operators_test.cpp (FarFieldZoneErrors) re-measures the table.
// `boost` moves every pair up that many zones (tests use boost 1 for a smaller far-field error).
constexpr int num_regular_zones = 8;
int regular_zone(double rho, int boost);
// The triangle rule of a zone (0 .. num_regular_zones-1).
const TriangleRule& regular_zone_rule(int zone);

}  // namespace cf::bem
