// Node adapters for nodes/bem: assemble.sgbem (operators, append-only crack blocks) and
// solve.sgbem (boundary conditions, factorisation reuse, crack Schur extension).
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/bem/assembly_step.hpp"
#include "nodes/bem/bem_types.hpp"
#include "nodes/bem/bem_vtk_export.hpp"
#include "nodes/bem/displacement_correlation.hpp"
#include "nodes/registration.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cf {
namespace {

// assemble.sgbem's declaration and run, in steps.

void declare_assemble_params(graph::NodeType& t) {
    t.param_real("E", 3.1e9, "Pa", "Young's modulus").above(0);
    t.param_real("nu", 0.327, "", "Poisson's ratio").range(0, 0.4999);
    t.param_int("singular_order", 5, "Gauss points per direction of the Sauter-Schwab rules (5: ~1e-5 operator error)")
        .range(2, 10);
    t.param_real("fold_angle", 60, "degrees",
                 "touching triangles folded sharper than this (inner angle; 180 flat, 90 a box edge) take the fold "
                 "rules; 0: none")
        .range(0, 180);
    t.param_int("fold_order", 10, "Gauss points per direction of the Sauter-Schwab rules on sharp folds").range(2, 12);
    t.param_int("farfield_boost", 0, "extra far-field quadrature zones (0 = distance-based default)").range(0, 6);
    t.param_bool("single_layer", true, "assemble V (needed only when some region has a displacement condition)");
    t.param_real("memory_budget", 0, "GB",
                 "refuse dense blocks above this size; 0: half the machine's physical memory. Checked before every "
                 "assembly, the loop's appends included; may not exceed the physical memory")
        .at_least(0);
    t.param_choice("method", "inherit", {"inherit", "full", "estimator", "hybrid"},
                   "crack unknowns (ch. 5): full BEM, estimator, or hybrid; inherit = full on a first assembly, the previous "
                   "operators' method with 'previous'");
    t.param_int("switch_elements", 3000,
                "method hybrid: BEM elements (surface + crack triangles) above which growth is estimated; below the "
                "starting count the estimator runs from the first step (thesis fig. 40 used 3000)")
        .at_least(0);
    t.param_bool("opening_update", true,
                 "estimated growth: integrate the estimated openings into the surface's right-hand side (ch. 5.2); false "
                 "keeps the surface data of the switch, which underestimates K as the crack grows (thesis fig. 22a)");
    t.param_choice("front_elements", "inherit", {"inherit", "linear", "square_root"},
                   "crack elements along every front: square_root (elements whose front unknowns are the coefficients "
                   "of sqrt(distance); sif.fronts reads K from them: front-average K_I within 0.5 % on the penny crack; "
                   "docs/architecture.md) or linear (P1, zero opening at the front; sif.fronts correlates displacements "
                   "as the thesis does, K 15-18 % low at the thesis' crack resolution). Full BEM only (estimated growth "
                   "uses the estimator). inherit = square_root on a first assembly, the previous operators' choice with "
                   "'previous'; set it on the first assembly");
    t.param_string("boundary_regions", "",
                   "regions the boundary conditions of the solves using these operators name, as 'solve:region;...'; "
                   "filled in by the pipeline loader (leave it empty): a region the mesh lacks, or that has no "
                   "triangles, is an error before assembling");
}

// Parameter 'memory_budget' [GB] in bytes (0: the default, half of what this process may use); a
// budget above what the process may use fails the node. assemble.sgbem and solve.sgbem.
double memory_budget_param(graph::NodeContext& c) {
    const double available = available_memory_bytes();
    if (c.real("memory_budget") * 1e9 > available && available > 0) {
        std::ostringstream m;
        m.precision(3);
        m << "parameter 'memory_budget' is " << c.real("memory_budget") << " GB, more than the " << available / 1e9
          << " GB this process may use (physical memory, or a ulimit); dense blocks that large would swap or be "
             "killed. Use at most "
          << available / 1e9 << " (0: half of it)";
        c.fail(m.str());
    }
    return c.real("memory_budget") > 0 ? c.real("memory_budget") * 1e9 : default_memory_budget_bytes();
}

// The assembly request from the parameters and inputs.
bem::AssemblyRequest assembly_request(graph::NodeContext& c) {
    bem::AssemblyRequest rq;
    rq.opening_update = c.boolean("opening_update");
    if (c.string("front_elements") != "inherit") rq.tip_elements = c.string("front_elements") == "square_root";
    rq.options.quadrature.singular_order = static_cast<int>(c.integer("singular_order"));
    rq.options.quadrature.farfield_boost = static_cast<int>(c.integer("farfield_boost"));
    rq.options.quadrature.fold_angle = c.real("fold_angle");
    rq.options.quadrature.fold_order = static_cast<int>(c.integer("fold_order"));
    rq.options.single_layer = c.boolean("single_layer");
    rq.options.memory_budget_bytes = memory_budget_param(c);
    rq.material.E = c.real("E");
    rq.material.nu = c.real("nu");
    if (c.has("material")) rq.material = c.in<Material>("material");
    rq.mesh = &c.in<SurfaceMesh>("mesh");
    if (const std::string problem = bem::check_named_regions(c.string("boundary_regions"), *rq.mesh); !problem.empty())
        c.fail(problem);
    if (c.has("cracks")) rq.cracks = &c.in<SurfaceMesh>("cracks");
    if (c.has("previous")) rq.previous = &c.in<bem::BemOperators>("previous");
    if (c.has("reuse")) rq.surface_blocks = c.in<bem::BemOperators>("reuse").surface;
    if (c.has("openings")) rq.openings = &c.in<bem::CrackOpeningEstimate>("openings");
    if (c.string("method") != "inherit") rq.method = bem::parse_crack_method(c.string("method"));
    rq.switch_elements = c.integer("switch_elements");
    rq.step = c.iteration() + 1;
    return rq;
}

void count_assembly(graph::NodeContext& c, const bem::AssemblyRequest& rq, const bem::AssemblyReport& rep,
                    const bem::BemOperators& out) {
    c.count("surface_reused", rep.surface_reused ? 1 : 0);
    c.count("surface_pairs_computed", rep.surface_reused ? 0.0 : static_cast<double>(out.surface->pairs_computed));
    if (!rep.surface_reused) {
        // The quadrature's rigid-motion error before K's rows were corrected (rigid_motion_rows.hpp):
        // a few 1e-2 on remeshed scans, order 1 for a surface that is open or inside out.
        c.count("rigid_motion_residual", out.surface->rigid_motion.max_residual);
        c.count("rigid_motion_rows", out.surface->rigid_motion.applied ? 1 : 0);
    }
    c.count("crack_pairs_computed", static_cast<double>(rep.crack_pairs));
    c.count("tip_pairs_computed", static_cast<double>(rep.tip_pairs));
    c.count("tip_pairs_reused", static_cast<double>(rep.tip_pairs_reused));
    c.count("tip_pairs_in_append", static_cast<double>(rep.tip_pairs_in_append));
    if (rq.cracks) c.count("crack_triangles", static_cast<double>(rq.cracks->num_triangles()));
    c.count("elements", static_cast<double>(rep.elements));
    c.count("growth_estimated", rep.estimated ? 1 : 0);
    if (rep.switched) {
        c.count("switched_to_estimator", 1);
        c.count("switch_step", rq.step);  // BEM step: 0 for the assembly before the loop, k + 1 in iteration k
    }
    if (out.estimated) c.count("estimated_nodes_added", static_cast<double>(out.estimated->nodes_last));
    c.count("triangles", static_cast<double>(rq.mesh->num_triangles()));
}

void run_assemble(graph::NodeContext& c) {
    const bem::AssemblyRequest rq = assembly_request(c);
    bem::AssemblyReport rep;
    bem::BemOperators out;
    try {
        out = bem::assemble_step(rq, rep);
    } catch (const std::invalid_argument& e) {
        c.fail(e.what());
    }
    count_assembly(c, rq, rep, out);
    c.out("operators", std::move(out));
}

graph::NodeType assemble_node() {
    graph::NodeType t("assemble.sgbem",
                      "Dense SGBEM blocks V, K, D of a closed surface and W, X, Y of crack sheets (thesis eq. 2.26, 2.38). "
                      "With 'previous', the surface blocks are reused when the surface and settings are unchanged, and only "
                      "crack elements appended since then are integrated (each element pair exactly once). 'method' chooses "
                      "how crack growth enters (ch. 5): full (every opening a BEM unknown), estimator (the cracks given to the "
                      "first assembly are solved once; later growth carries openings estimated by eq. (5.5) whose influence "
                      "f <- f - B du is integrated element by element, B and Y never assembled), or hybrid (full until the "
                      "mesh exceeds 'switch_elements', then as estimator, fig. 40). Set it on the first assembly; the loop's "
                      "assembly inherits it through 'previous'.");
    t.input<SurfaceMesh>("mesh", "closed, outward-oriented ordinary surface (BEM resolution)");
    t.optional_input<SurfaceMesh>("cracks", "open crack sheets strictly inside the body; regions are the cracks");
    t.optional_input<bem::BemOperators>("previous", "operators of the previous step, extended append-only");
    t.optional_input<bem::BemOperators>("reuse", "operators assembled earlier on the same surface (e.g. rigid.impact's "
                                                 "'surface'): their surface blocks are used when surface, material and "
                                                 "quadrature match; unlike 'previous', nothing else carries over");
    t.optional_input<Material>("material", "when connected, E and nu come from it (material.brittle) instead of the parameters");
    t.optional_input<bem::CrackOpeningEstimate>("openings",
                                                "openings estimated for nodes the fronts left behind (fracture.geometry); used "
                                                "once growth is estimated, ignored by the full BEM");
    t.output<bem::BemOperators>("operators", "immutable; blocks shared with 'previous' where unchanged");
    declare_assemble_params(t);
    t.run(run_assemble);
    return t;
}

graph::NodeType solve_node() {
    graph::NodeType t("solve.sgbem",
                      "Solves the SGBEM system for the given boundary conditions (eq. 2.25; pure Neumann with the Tikhonov "
                      "regulariser of ch. 7.1; cracks through the Schur complement, eq. 4.3). With 'previous', the surface "
                      "factorisation is reused and the crack Schur factor extended when only crack unknowns were appended.");
    t.input<bem::BemOperators>("operators", "from assemble.sgbem");
    t.optional_input<bem::BemSolution>("previous", "solution of the previous step (factorisations to reuse)");
    t.optional_input<bem::BemSolution>("reuse", "a solution on the same surface operators (e.g. rigid.impact's 'factor'): "
                                                "its surface factorisation is used when the Dirichlet/Neumann partition "
                                                "matches and 'previous' gives none");
    t.optional_input<bem::BoundaryConditions>(
        "conditions", "boundary conditions as a value (e.g. per-element collision tractions from rigid.impact, ch. 7.2); "
                      "when connected they replace the parameter 'boundary_conditions'");
    t.output<bem::BemSolution>("solution", "nodal displacements [m], element tractions [Pa], crack opening [m]");
    t.param_string("boundary_conditions", "*: traction 0 0 0",
                   "per region 'name: displacement x y z' [m], 'name: traction x y z' [Pa] and/or 'name: pressure p' [Pa] "
                   "(traction -p n on each element, n its outward normal: p > 0 pushes into the body; adds to a traction "
                   "on the same region, an error on a displacement region), ';'-separated; '*' covers every region not "
                   "named, e.g. 'z_max: traction 0 0 1e6; z_min: displacement 0 0 0; *: traction 0 0 0'")
        .checked_by([](const std::string& text) -> std::string {
            try {
                bem::parse_boundary_conditions(text);
            } catch (const std::invalid_argument& e) {
                return e.what();
            }
            return "";
        });
    t.param_real("crack_pressure", 0, "Pa", "pressure on both faces of every crack (0: traction-free)");
    t.param_real("balance_tolerance", 1e-3, "", "pure Neumann: largest accepted relative net force/torque of the loads")
        .above(0);
    t.param_real("memory_budget", 0, "GB",
                 "refuse a surface factor or crack Schur complement (eq. 4.3) whose dense matrices exceed this, before "
                 "allocating them; 0: the budget of the assemble.sgbem that made the operators. May not exceed the "
                 "physical memory")
        .at_least(0);
    t.run([](graph::NodeContext& c) {
        const bem::BemOperators& ops = c.in<bem::BemOperators>("operators");
        const double budget = memory_budget_param(c);
        const bem::BemSolution* prev = c.has("previous") ? &c.in<bem::BemSolution>("previous") : nullptr;
        std::shared_ptr<const bem::BemSolution> sol;
        try {
            const bem::ResolvedConditions bc = bem::resolve(
                c.has("conditions") ? c.in<bem::BoundaryConditions>("conditions")
                                    : bem::parse_boundary_conditions(c.string("boundary_conditions")),
                ops.surface->mesh);
            bem::CrackLoads loads;
            if (ops.cracks) loads.pressure.assign(ops.cracks->cracks.num_regions(), c.real("crack_pressure"));
            bem::SolveOptions so;
            so.balance_tolerance = c.real("balance_tolerance");
            if (c.real("memory_budget") > 0) so.memory_budget_bytes = budget;
            sol = bem::solve_sgbem(ops.surface, ops.solve_cracks(), bc, loads, prev, so, ops.estimated,
                                   c.has("reuse") ? c.in<bem::BemSolution>("reuse").system : nullptr);
        } catch (const bem::MemoryBudgetExceeded& e) {
            c.fail(std::string(e.what()) + " ('memory_budget' of this node, or of the assemble.sgbem that made the operators)");
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("parameter boundary_conditions / inputs: ") + e.what());
        } catch (const std::runtime_error& e) {
            c.fail(e.what());
        }
        {
            // A solve that produced NaN or infinity is a failure, not a result (e.g. E = 1e300 overflows
            // the single layer, an inverted mesh makes a factor indefinite without tripping it).
            bool finite = true;
            for (const Vec3& u : sol->displacement) finite = finite && u.allFinite();
            for (const Vec3& t : sol->traction) finite = finite && t.allFinite();
            for (const Vec3& w : sol->crack_opening) finite = finite && w.allFinite();
            if (!finite) {
                std::ostringstream os;
                os.precision(6);
                os << "the solution has non-finite values (NaN or infinity): the material is out of a physical range "
                      "(E = " << 2 * ops.surface->elastic.mu * (1 + ops.surface->elastic.nu) << " Pa, nu = " << ops.surface->elastic.nu
                   << "; E of real solids lies between about 1e5 and 1e12 Pa) or the BEM mesh is degenerate; check "
                      "material.brittle (or assemble.sgbem's E, nu) and the mesh";
                c.fail(os.str());
            }
        }
        c.count("surface_factor_reused", sol->reused_surface_factor ? 1 : 0);
        c.count("schur_extended", sol->extended_schur ? 1 : 0);
        c.count("schur_rows_added", static_cast<double>(sol->schur_rows_added));
        c.count("residual_force", sol->residual_force.norm());
        c.count("residual_torque", sol->residual_torque.norm());
        c.count("growth_estimated", sol->estimated ? 1 : 0);
        c.out_shared("solution", sol);
    });
    return t;
}

graph::NodeType vtk_node() {
    graph::NodeType t("export.bem_vtk",
                      "Writes an SGBEM solution as VTK PolyData for ParaView: the surface with nodal displacement 'u' [m] and "
                      "element 'traction' [Pa], 'dirichlet' and 'region' cell arrays; crack sheets (if any) to a second file "
                      "with the opening 'du' = u+ - u- [m] and the average displacement 'u_average' (thesis ch. 6.4). "
                      "Files are written atomically.");
    t.input<bem::BemSolution>("solution", "from solve.sgbem");
    t.param_string("path", "", "surface .vtp file; relative paths are relative to the run's output directory; '{iteration}' "
                               "becomes the loop iteration (per-step files)").required().writes_file();
    t.param_string("crack_path", "",
                   "crack-sheet .vtp file (written only when there are cracks); empty: '<path stem>_cracks.vtp' beside 'path'").writes_file();
    t.param_bool("crack_average", true,
                 "add 'u_average' at crack vertices (representation formula over the surface, eq. 2.20; costs one surface "
                 "integral per crack vertex)");
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        const std::filesystem::path path = c.output_path(c.string("path"));
        std::filesystem::path crack_path = c.string("crack_path");
        if (crack_path.empty()) crack_path = path.parent_path() / (path.stem().string() + "_cracks.vtp");
        else crack_path = c.output_path(c.string("crack_path"));
        try {
            bem::write_bem_vtk(sol, path, crack_path, c.boolean("crack_average"));
        } catch (const std::exception& e) {
            c.fail("parameter 'path' (" + path.string() + ") / 'crack_path' (" + crack_path.string() + "): " + e.what());
        }
        c.count("surface_triangles", static_cast<double>(sol.surface->mesh.num_triangles()));
        c.count("crack_triangles", sol.cracks ? static_cast<double>(sol.cracks->cracks.num_triangles()) : 0.0);
    });
    return t;
}

graph::NodeType sif_node() {
    graph::NodeType t("sif.displacement_correlation",
                      "Stress-intensity factors K_I, K_II, K_III per crack-front edge by displacement correlation "
                      "(eq. 2.39 with the full-jump constant) at the interior node of the edge's triangle, with the tip "
                      "frame e1 (forward), e2 (crack normal), e3 (front tangent) (ch. 4.5.2). The fast estimator of ch. 5 "
                      "produces the same output, so a pipeline swaps one for the other by changing this node.");
    t.input<bem::BemSolution>("solution", "from solve.sgbem (with cracks)");
    t.output<std::vector<bem::FrontEdgeSif>>("sifs", "one record per crack-front edge [Pa*sqrt(m)]");
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        std::vector<bem::FrontEdgeSif> sifs;
        if (sol.cracks && sol.cracks->cracks.num_triangles() > 0) {
            const double mu = sol.surface->elastic.mu, nu = sol.surface->elastic.nu;
            try {
                sifs = bem::displacement_correlation_sifs(sol.cracks->cracks, sol.crack_opening, 2 * mu * (1 + nu), nu);
            } catch (const std::invalid_argument& e) {
                c.fail(std::string("input 'solution' crack sheets: ") + e.what());
            }
        }
        double kmax = 0;
        for (const auto& s : sifs) kmax = std::max(kmax, std::abs(s.KI));
        c.count("front_edges", static_cast<double>(sifs.size()));
        c.count("max_abs_KI", kmax);
        c.out("sifs", std::move(sifs));
    });
    return t;
}

}  // namespace

void register_bem_nodes(graph::NodeRegistry& r) {
    r.add(assemble_node());
    r.add(solve_node());
    r.add(vtk_node());
    r.add(sif_node());
}

}  // namespace cf
