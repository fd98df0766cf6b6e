// Node adapters of the fast estimators (thesis ch. 5.1): sif.fronts, the SIF node of a fracture
// loop (displacement correlation while crack openings are BEM unknowns, the estimator once growth
// is estimated, so the hybrid switch needs no re-wiring), and sif.estimator (always the estimator).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/bem/tip_elements.hpp"
#include "nodes/domain/material.hpp"
#include "nodes/estimate/sif_estimator.hpp"
#include "nodes/registration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cf {
namespace {

void declare_estimator_params(graph::NodeType& t) {
    t.input<bem::BemSolution>("solution", "from solve.sgbem");
    t.optional_input<Material>("material", "its compressive_factor f_c weighs compressive principal stresses (default 1)");
    t.output<std::vector<bem::FrontEdgeSif>>("sifs", "one record per crack-front edge [Pa*sqrt(m)], as sif.displacement_correlation");
    t.param_choice("estimator", "aligned", {"aligned", "basic"},
                   "aligned: eq. (5.2)-(5.4), the kink turns the crack onto a principal direction; basic: eq. (5.1), the "
                   "traction on the crack plane (oscillating paths, fig. 22)");
    t.param_int("smoothing_passes", 4, "passes of the 1/3-1/3-1/3 stress smoothing along each front (ends renormalised)")
        .range(0, 100);
    t.param_real("near_surface", 0.1, "",
                 "surface stress (eq. 4.6) instead of eq. (2.23) closer to the surface than this fraction of the closest "
                 "triangle's longest edge")
        .range(0, 10);
    t.param_real("scale", 2 / M_PI, "",
                 "geometry factor of eq. (5.1): 2/pi (default) is the circular crack of area A the estimator assumes "
                 "(penny crack, K_I = (2/pi) sigma sqrt(pi a)); the thesis used 1.1215, a straight edge crack in a half-space, "
                 "which overestimated K 1.9-2.7x against the full BEM on the thesis' cubes (docs/verification.md)")
        .above(0);
}

estimate::SifEstimatorSettings settings_of(const graph::NodeContext& c) {
    estimate::SifEstimatorSettings s;
    s.kind = c.string("estimator") == "basic" ? estimate::EstimatorKind::basic : estimate::EstimatorKind::aligned;
    s.smoothing_passes = static_cast<int>(c.integer("smoothing_passes"));
    s.near_surface = c.real("near_surface");
    s.scale = c.real("scale");
    if (c.has("material")) s.compressive_factor = c.in<Material>("material").compressive_factor;
    return s;
}

void report(graph::NodeContext& c, const bem::BemSolution& sol, const SurfaceMesh* cracks,
            const std::vector<bem::FrontEdgeSif>& sifs, const estimate::SifEstimatorReport* rep) {
    if (cracks && !sifs.empty()) {
        const auto m = estimate::interior_front_means(*sol.surface, *cracks, sifs, c.real("near_surface"), sol.surface->elastic.nu);
        c.count("mean_KI_interior", m.KI);
        c.count("mean_kink_deg_interior", m.kink_deg);
    }
    double kmax = 0, ksum = 0;
    for (const auto& s : sifs) {
        kmax = std::max(kmax, std::abs(s.KI));
        ksum += s.KI;
    }
    c.count("front_edges", static_cast<double>(sifs.size()));
    c.count("max_abs_KI", kmax);
    c.count("mean_KI", sifs.empty() ? 0.0 : ksum / static_cast<double>(sifs.size()));
    if (rep) {
        c.count("somigliana_points", static_cast<double>(rep->interior_points));
        c.count("surface_stress_points", static_cast<double>(rep->surface_points));
        c.count("compressive_directions", static_cast<double>(rep->compressive_choices));
        c.count("edges_not_moving", static_cast<double>(rep->skipped_edges));
    }
}

graph::NodeType fronts_node() {
    graph::NodeType t("sif.fronts",
                      "Stress-intensity factors per crack-front edge for a fracture loop: while the solution's crack openings "
                      "are BEM unknowns, from the square-root front elements' coefficients when assemble.sgbem used them "
                      "(front_elements: square_root), else by displacement correlation (eq. 2.39); by the estimator of ch. 5.1 once "
                      "growth is estimated (assemble.sgbem method estimator, or hybrid past its threshold), so the hybrid "
                      "switch needs no re-wiring. Without cracks it gives no record (new fronts wait).");
    declare_estimator_params(t);
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        std::vector<bem::FrontEdgeSif> sifs;
        estimate::SifEstimatorReport rep;
        const SurfaceMesh* cracks = bem::current_crack_mesh(sol);
        try {
            if (sol.estimated) {
                if (cracks && cracks->num_triangles() > 0)
                    sifs = estimate::estimate_sifs(sol, *cracks, settings_of(c), &rep, &sol.estimated->front_active);
            } else if (cracks && cracks->num_triangles() > 0) {
                const double mu = sol.surface->elastic.mu, nu = sol.surface->elastic.nu;
                if (!sol.front_coefficient.empty())  // square-root front elements: K from their coefficients
                    sifs = bem::tip_element_sifs(*cracks, sol.front_coefficient, 2 * mu * (1 + nu), nu);
                else
                    sifs = bem::displacement_correlation_sifs(*cracks, sol.crack_opening, 2 * mu * (1 + nu), nu);
            }
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("input 'solution' crack sheets: ") + e.what());
        }
        c.count("estimated", sol.estimated ? 1 : 0);
        report(c, sol, cracks, sifs, sol.estimated ? &rep : nullptr);
        c.out("sifs", std::move(sifs));
    });
    return t;
}

graph::NodeType estimator_node() {
    graph::NodeType t("sif.estimator",
                      "Stress-intensity factors per crack-front edge by the estimator of ch. 5.1 from the ordinary surface "
                      "data alone (Somigliana stress without crack terms, eq. 2.23; surface stress near the surface, eq. 4.6; "
                      "aligned estimator eq. 5.2-5.4 or basic eq. 5.1), whatever the solution's cracks. On a full-BEM "
                      "solution this is the comparison of thesis fig. 21.");
    declare_estimator_params(t);
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        const SurfaceMesh* cracks = bem::current_crack_mesh(sol);
        if (!cracks || cracks->num_triangles() == 0)
            c.fail("input 'solution' has no crack sheet, so there is no crack front to estimate; connect a solution "
                   "assembled with cracks, or use sif.fronts in a loop where cracks appear later");
        std::vector<bem::FrontEdgeSif> sifs;
        estimate::SifEstimatorReport rep;
        try {
            sifs = estimate::estimate_sifs(sol, *cracks, settings_of(c), &rep);
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("input 'solution' crack sheets: ") + e.what());
        }
        report(c, sol, cracks, sifs, &rep);
        c.out("sifs", std::move(sifs));
    });
    return t;
}

}  // namespace

void register_estimate_nodes(graph::NodeRegistry& r) {
    r.add(fronts_node());
    r.add(estimator_node());
}

}  // namespace cf
