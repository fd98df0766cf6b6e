#pragma once
// Stress-intensity estimator of thesis ch. 5.1: K along every crack front from the ordinary
// surface data alone, so crack growth needs no crack unknowns in the BEM system.
//  1. Stress at the midpoint p of each front edge with every crack left out: the Somigliana
//     stress identity (eq. 2.23) over the ordinary surface's displacements and tractions
//     (bem::interior_stress with adaptive near-field quadrature); closer to the surface than
//     `near_surface` times the longest edge l of the closest surface triangle, that triangle's
//     surface stress (ch. 4.3, eq. 4.6) instead, where the kernels would be nearly singular.
//  2. The stress tensors smoothed along each front: passes of the 1/3 - 1/3 - 1/3 stencil whose
//     weights are renormalised where a front ends, so end values are not halved per pass.
//  3. Aligned estimator (eq. 5.2-5.4): the principal direction v the crack should open against
//     (largest principal stress; if cos(theta*) < 1/3 the second largest or, when larger in
//     magnitude after dividing by the compressive factor f_c, the most negative; else the last),
//     theta* = the kink that turns the crack normal onto v, eta = K_II / K_I,III from eq. (5.2),
//     K_I,III = s lambda with s = scale (pi A)^(1/4) / sqrt(1 + eta^2), K_II = eta K_I,III, and
//     K_I, K_III split by the angle alpha between v and the front tangent (eq. 5.4).
//     Basic estimator (eq. 5.1): K_i = scale (e_i^T sigma n) (pi A)^(1/4).
//     A is the coarse area of the crack (one face). The scale is 2/pi by default, the factor of the
//     circular crack of that area the estimator assumes (K_I = (2/pi) sigma sqrt(pi a), a = sqrt(A/pi));
//     the thesis used 1.1215, a straight edge crack in a half-space, which overestimated K by
//     1.9-2.7x against the full BEM on its own test cubes (docs/verification.md).
// Output: the FrontSifs of sif.displacement_correlation (same edges, frames and sign
// conventions: e1 forward, e2 crack normal, e3 = e1 x e2; K_III along e3), so propagation takes
// either. SI units: Pa, m, Pa sqrt(m).
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/bem/interior_evaluation.hpp"

#include <string>
#include <vector>

namespace cf::estimate {

using Mat3 = bem::Mat3;

enum class EstimatorKind { aligned, basic };

struct SifEstimatorSettings {
    EstimatorKind kind = EstimatorKind::aligned;
    double near_surface = 0.1;        // surface stress within this fraction of the closest triangle's longest edge
    int smoothing_passes = 4;         // along each front
    double scale = 2 / M_PI;          // geometry factor of eq. (5.1): a circular crack (the thesis: 1.1215, edge crack)
    double compressive_factor = 1;    // f_c: a compressive principal stress counts |lambda| / f_c (ch. 5.1)
    bem::InteriorQuadrature quadrature;
};

struct SifEstimatorReport {
    std::size_t interior_points = 0;  // Somigliana evaluations
    std::size_t surface_points = 0;   // surface-stress evaluations (near the surface)
    std::size_t skipped_edges = 0;    // edges of stopped fronts or without a moving end (not evaluated)
    std::size_t compressive_choices = 0, second_choices = 0, third_choices = 0;  // principal directions other than the largest
};

// Per front edge of `cracks` (v0 < v1, as displacement correlation orders them). `sol` provides
// the surface data. `moving` (per crack vertex, may be null or empty: every front moves) marks the
// front nodes whose markers still move: the stress is evaluated only at edges with a moving end
// (as the thesis' code evaluates it only at nodes with an active marker); the other edges of a
// front take the stress of the nearest evaluated edge along it, and a front with no moving node
// gets no records (propagation counts it as stopped). Throws std::invalid_argument naming the
// crack when a crack has zero area, when the sheets have no front, or when a front's boundary is
// not a set of loops.
std::vector<bem::FrontEdgeSif> estimate_sifs(const bem::BemSolution& sol, const SurfaceMesh& cracks,
                                             const SifEstimatorSettings& settings, SifEstimatorReport* report = nullptr,
                                             const std::vector<char>* moving = nullptr);

// Front average of K_I over the edges whose midpoint lies farther from the ordinary surface than
// `near_surface` times the longest edge of the closest surface triangle (where eq. 2.23 applies and
// fronts move; the edges along the surface of a surface-breaking crack are left out). 0 if none.
// Also the mean kink angle theta* of eq. (4.10) over the same edges [degrees].
struct InteriorFrontMeans {
    double KI = 0;         // [Pa sqrt(m)]
    double kink_deg = 0;   // [deg]
    std::size_t edges = 0;
};
InteriorFrontMeans interior_front_means(const bem::SurfaceOperators& surface, const SurfaceMesh& cracks,
                                        const std::vector<bem::FrontEdgeSif>& sifs, double near_surface, double nu);

// Eq. (5.2): K_II / K_I,III that kinks the crack by theta (|theta| < acos(1/3)).
double eta_for_kink(double theta);

// One edge's SIFs from its (smoothed) stress. `sqrt_pi_a` = (pi A)^(1/4); frame e1, e2, e3 as in
// bem::FrontEdgeSif. Returns {K_I, K_II, K_III}; `choice` (may be null) gets 0 (largest
// principal stress), 1 (second), 2 (most negative) or 3 (the remaining one).
Vec3 aligned_estimate(const Mat3& sigma, const Vec3& e1, const Vec3& e2, const Vec3& e3, double nu, double scale,
                      double sqrt_pi_a, double compressive_factor, int* choice = nullptr);
Vec3 basic_estimate(const Mat3& sigma, const Vec3& e1, const Vec3& e2, const Vec3& e3, double scale, double sqrt_pi_a);

}  // namespace cf::estimate
