#pragma once
// Square-root crack-front elements (issue 13; Li, Mear & Xiao 1998 style, adapted to P1 triangles).
//
// The crack opening is the P1 field of all crack nodes, front nodes included, times sqrt(rho):
//   [u](x) = sqrt(rho(x)) * sum_i u_i lambda_i(x),   rho(x) = sum over NON-front nodes i of lambda_i(x).
// rho is 0 on the front, 1 at every node off it, so the field is plain P1 on elements without a front
// node. On a front triangle (front edge j-k, third node m) rho = lambda_m = d / H (d the distance
// behind the edge, H the triangle's height over it), and with xi along the edge
//   [u] = sqrt(rho) (1 - rho) [(1 - xi) u_j + xi u_k] + rho^(3/2) u_m,
// the element of the issue with a_j = u_j / sqrt(H): the nodal part of m carries rho^(3/2) (no
// linear term beside the square root, the blending problem of a plain sqrt(rho)-times-hat
// enrichment), and the front nodes' values u_j are square-root coefficients. The field is
// continuous (rho and the hats are), vanishes on the front, so the regularised hypersingular form
// (sgbem-math.md §2) stays valid. Near the front [u] = u(xi) sqrt(d / H), hence (sgbem-math §5)
//   K_I = E / (8 (1 - nu^2)) sqrt(2 pi / H) u(xi).e2, K_II with e1, K_III = E / (8 (1 + nu)) sqrt(2 pi / H) u(xi).e3.
//
// Curls are no longer constant on elements with a front node:
//   curl(sqrt(rho) lambda_a) = sqrt(rho) c_a + lambda_a / (2 sqrt(rho)) c_rho,
// with an integrable 1/sqrt(rho) singularity on the front edge (or at the front node). Quadrature
// composes every 1D Gauss rule with the endpoint-graded map v = w^2 (3 - 2w) (graded_gauss_01, the
// issue's rho = s^2 substitution applied in every direction): the Sauter-Schwab rules of touching
// pairs and the collapsed Gauss rules of separated ones place the triangles' edges on faces of their
// parameter cubes, so the square-root factors become smooth there, while the 1/r of the pair is
// handled by the Sauter-Schwab maps as for P1.
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/bem/operators.hpp"

#include <array>
#include <memory>
#include <vector>

namespace cf::bem {

// How rho behaves on a crack element. A node is a front node when it lies on the sheet's boundary,
// an edge is a front edge when it has one triangle, and a chord when it has two but both its nodes
// are front nodes (a triangle in the corner of a sheet, or one spanning a narrow strip, has all
// three nodes on the boundary without all its edges being fronts).
//   plain: no front node, rho = 1.
//   edge: one front edge (local nodes other than `local`), the third node off the front: rho = lambda_local.
//   vertex: one front node (`local`): rho = 1 - lambda_local.
//   general: any element with a chord: rho = sum over nodes off the front of lambda_i
//     + 4 sum over chords (p, q) of c_pq lambda_p lambda_q, the P2 interpolant of 0 at front nodes, 1 at
//     the others, c_pq at the midpoints of chords and the linear values elsewhere. c_pq = h_f / (h_f + h_i)
//     from the heights over the chord of its two triangles' third nodes when one is on the front (h_f)
//     and the other is not (h_i), so that rho ~ distance to the front / distance of the first node row
//     as on edge elements (a sliver in a corner gets a small c); 1/2 otherwise. rho is continuous
//     across every edge (its trace on an edge depends only on that edge), 0 exactly on front edges and
//     positive on chords, so no interior edge carries a zero opening and every front node keeps its
//     coefficient unknown. (rho = the sum of the hats off the front, used before, vanished on every
//     chord and on the whole of a corner triangle: edge_crack_mode1 had a front node without unknown.)
//   zero: all three edges are front edges (an isolated triangle): rho = 0, every basis function vanishes.
struct TipElementKind {
    enum Type { plain, edge, vertex, zero, general } type = plain;
    int local = -1;
    unsigned char front = 0;  // bit i: local node i is a front node
    unsigned char chord = 0;  // bit e: the edge opposite local node e is a chord
    double chord_value[3] = {0, 0, 0};  // c of each chord (rho at its midpoint)
};

// Whether two elements' rho is the same function of their barycentric coordinates.
bool same_tip_kind(const TipElementKind& x, const TipElementKind& y);

struct TipBasis {
    std::vector<char> front;             // per crack node: on the sheet's boundary
    std::vector<TipElementKind> kind;    // per crack element
};
TipBasis tip_basis(const SurfaceMesh& cracks);

// d rho / d lambda_m at the midpoint of the front edge opposite local node m, moving towards m (rho
// = slope * d / H near the edge, H the height over it): 1 on edge elements, r_m + 2 (c of the chords
// at m) on general ones.
double front_edge_rho_slope(const TipElementKind& k, int m);

// Values at one reference point (s, t) of an element (local order of the element's nodes): the
// barycentric coordinates, the physical point, sqrt(rho), lambda_a / (2 sqrt(rho)) (0 on plain
// elements), the basis values sqrt(rho) lambda_a and d rho / d lambda_i (general elements: the curl
// of rho is sum_i g_i curl(lambda_i)).
struct TipPoint {
    std::array<double, 3> lambda{};
    Vec3 x;
    double sq = 1;
    std::array<double, 3> q{};
    std::array<double, 3> psi{};
    std::array<double, 3> g{};
};
TipPoint tip_point(const ElementGeometry& g, const TipElementKind& k, double s, double t);

// Curl of rho on an element where it is constant (edge, vertex; 0 for plain and zero elements).
Vec3 rho_curl(const ElementGeometry& g, const TipElementKind& k);

// Blocks of one element pair with the square-root basis on both (plain elements are plain P1):
// H[alpha][beta] = <D psi_beta e_j, psi_alpha e_i> (test a, trial b), and Kb[beta] = K[a, (b, beta)]
// (a is then a P0 test element of another mesh). `same_mesh`: a and b index the same vertices (touching
// pairs use Sauter-Schwab). n: Gauss points per direction of the singular rules.
struct TipPairBlocks {
    std::array<std::array<Mat3, 3>, 3> H;
    std::array<Mat3, 3> Kb;
};
void tip_pair_blocks(const ElementGeometry& a, const TipElementKind& ka, const ElementGeometry& b, const TipElementKind& kb,
                     bool same_mesh, int n, const ElasticConstants& c, bool want_k, TipPairBlocks& out);

// Scalar test integral int_a int_b f(x) g(y) / r with f, g chosen among {sqrt(rho), lambda_a / (2 sqrt rho)}
// (index 0: sqrt(rho), 1 + a: lambda_a / (2 sqrt(rho)); general elements: 1 + 3a + i:
// lambda_a g_i / (2 sqrt(rho))), for the quadrature unit tests.
double tip_pair_scalar(const ElementGeometry& a, const TipElementKind& ka, int fa, const ElementGeometry& b,
                       const TipElementKind& kb, int fb, bool same_mesh, int n);

// n x n rule on an edge or vertex element that makes its weights polynomial: rho = u^2 with u a
// Gauss coordinate (edge: lambda_local = u^2, the rest split along the edge; vertex: lambda_local =
// 1 - u^2, collapsed onto the front node), so sqrt(rho) = u and the Jacobian 2u(1 - u^2) or 2u^3
// cancels 1 / sqrt(rho). Separated pairs then converge as fast as the kernel allows (the issue's
// rho = s^2 substitution). Other kinds: the graded collapsed rule.
TriangleRule tip_triangle_rule(const TipElementKind& k, int n);

// The same for a pair integrated as separated with the given rules on a and on b (zone studies).
double tip_separated_scalar(const ElementGeometry& a, const TipElementKind& ka, int fa, const TriangleRule& ra,
                            const ElementGeometry& b, const TipElementKind& kb, int fb, const TriangleRule& rb);

// The crack blocks with square-root front elements: a copy of the P1 blocks of `p1` in which every
// pair with an element touching the front is corrected (P1 contribution subtracted, square-root one
// added). Every crack node that carries a basis function is an unknown (front nodes included).
// `basis_integral` holds int psi_a per element for face loads. `previous`: the square-root operators
// of the step before (may be null); corrections of elements and pairs whose geometry and kinds did
// not change are taken from it instead of integrated again (same numbers, same order of addition).
// `appended`: the corrections made during the append that made `p1` (TipCorrectionsOfAppend); the
// ones it holds are taken instead of integrated (the same numbers).
class TipCorrectionsOfAppend;
std::shared_ptr<const CrackOperators> tip_crack_operators(const SurfaceOperators& surface, const CrackOperators& p1,
                                                          const CrackOperators* previous = nullptr,
                                                          const TipCorrectionsOfAppend* appended = nullptr);

// The square-root corrections of the pairs with a new element, made inside the append (as its
// observer, append_crack_elements) while it hands over their P1 blocks, so tip_crack_operators need
// not integrate those P1 blocks a second time (the correction is square-root minus P1 blocks) nor
// keep them meanwhile: the corrections made here are the ones the step keeps. `cracks`: the mesh
// being appended to. One append per object; its element tasks call it concurrently, each for its own
// element's pairs.
class TipCorrectionsOfAppend : public AppendedPairs {
public:
    TipCorrectionsOfAppend(const SurfaceOperators& surface, const SurfaceMesh& cracks);
    ~TipCorrectionsOfAppend() override;
    void begin(const std::vector<ElementGeometry>& crack_geometry, std::size_t first_new) override;
    void surface_pair(int b, int a, const PairBlocks& p1) override;
    void crack_pair(int a, int b, const PairBlocks& p1) override;

    struct Impl;
    const Impl& impl() const { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

// SIFs per front edge at the edge's midpoint from the front nodes' square-root coefficients (the
// solution's front_coefficient), with the same tip frame as displacement correlation.
std::vector<FrontEdgeSif> tip_element_sifs(const SurfaceMesh& cracks, const std::vector<Vec3>& front_coefficient, double E,
                                           double nu);

}  // namespace cf::bem
