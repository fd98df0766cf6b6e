#pragma once
// Element-pair integrals from which every Galerkin block is built (sgbem-math.md §2):
//   I1 = int_a int_b 1/r,  IR = int_a int_b d d^T / r^3  (d = x - y, x in a, y in b),
//   IKb[beta]  = int_a int_b (x-y).n_b / r^3 lambda_beta(y)   (Laplace double layer, trial b),
//   IKa[alpha] = int_a int_b (y-x).n_a / r^3 lambda_alpha(x)  (the same with the roles swapped).
// They depend on geometry only, not on the material. Touching pairs use Sauter-Schwab rules,
// separated pairs a regular rule chosen by distance/size (quadrature.hpp). All three families
// are summed in one pass over the same points (pair_kernel.hpp).
#include "nodes/bem/element_geometry.hpp"
#include "nodes/bem/quadrature.hpp"

#include <array>

namespace cf::bem {

struct PairIntegrals {
    double I1 = 0;
    double IR[6] = {0, 0, 0, 0, 0, 0};  // xx, yy, zz, xy, xz, yz
    double IKb[3] = {0, 0, 0};         // local vertex order of b
    double IKa[3] = {0, 0, 0};         // local vertex order of a
};

struct QuadratureSettings {
    int singular_order = 5;  // Gauss points per direction of the Sauter-Schwab rules (5 = production)
    int farfield_boost = 0;  // zones added to the distance-based far-field choice
    int fixed_regular = 0;   // > 0: n x n collapsed Gauss for every separated pair (oracle comparisons)
    // Touching pairs (common edge or vertex) folded sharper than fold_angle take Sauter-Schwab rules
    // of fold_order points per direction. fold_angle is the inner angle between the two triangles
    // [degrees]: 180 flat, 90 a box edge, 0 folded back; 0 turns the fold rules off. Why: across a sharp
    // fold the order-5 rules converge slowly (a V notch's 19-degree tip: K's rigid-motion rows off by
    // 14 %, a patch test's displacement by 1.8e-3; order 10 there: 1.8 % and 1.1e-4; graded rules were
    // worse), while up to a box's 90 degrees order 5 holds ~1e-5 (docs/verification.md).
    double fold_angle = 60;
    int fold_order = 10;
};

// The pair rules for one setting, built once and shared. Pair rules are stored flattened (tensor
// products of the regular zones expanded) and padded with zero-weight copies of their last point
// to a multiple of pair_rule_padding, which the kernel's vector loop needs.
constexpr std::size_t pair_rule_padding = 8;
class PairQuadrature {
public:
    explicit PairQuadrature(const QuadratureSettings& s);
    const QuadratureSettings& settings() const { return settings_; }
    const PairRule& singular(PairKind k) const { return k == PairKind::identical ? id_ : k == PairKind::common_edge ? edge_ : vert_; }
    // The rule of a touching pair whose normals' cosine is `normal_cos` (sharp folds: the fold rules).
    const PairRule& touching(PairKind k, double normal_cos) const {
        if (k != PairKind::identical && normal_cos < fold_cos_) return k == PairKind::common_edge ? edge_fold_ : vert_fold_;
        return singular(k);
    }
    // Flattened pair rule for a separated pair at separation ratio rho.
    const PairRule& regular_pairs(double rho) const {
        return fixed_.size() ? fixed_ : zones_[regular_zone(rho, settings_.farfield_boost)];
    }

private:
    QuadratureSettings settings_;
    PairRule fixed_;
    PairRule id_, edge_, vert_;
    double fold_cos_ = -2;  // normals' cosine below which a touching pair is a sharp fold (-cos of fold_angle)
    PairRule edge_fold_, vert_fold_;
    std::array<PairRule, num_regular_zones> zones_;
};

// The rules for `s`, built on its first use and kept for the life of the process (immutable, so any
// thread may read them). Every assembly call of every BEM step needs them, and building them (the
// fold rules alone are 70 000 points) cost ~3 ms of serial time per call, about 5 % of a short run.
const PairQuadrature& shared_pair_quadrature(const QuadratureSettings& s);

// Integrals of the pair (a, b). `same_mesh` says whether a and b index the same vertex array
// (only then can they touch). Pairs with a shared vertex id use Sauter-Schwab.
PairIntegrals pair_integrals(const ElementGeometry& a, const ElementGeometry& b, bool same_mesh, const PairQuadrature& q);

// Tensor product of a triangle rule with itself as a padded pair rule (index i * m + j, i on a).
PairRule tensor_pair_rule(const TriangleRule& t);
// Integrals of a pair treated as separated, with a given pair rule (accuracy studies and tests).
PairIntegrals separated_pair_integrals(const ElementGeometry& a, const ElementGeometry& b, const PairRule& r);

// rho = |c_a - c_b| / max(diameters), the far-field zoning ratio.
double separation_ratio(const ElementGeometry& a, const ElementGeometry& b);

}  // namespace cf::bem
