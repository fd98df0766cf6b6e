// Node adapters of the fracture loop (thesis ch. 4.1, 4.5): fracture.start (the loop's initial
// state), propagate.fronts (one BEM time step of crack-front propagation with recording and
// BEM mesh growth) and fracture.geometry (the state's crack sheets and grids for other stages).
#include "graph/diagnostics.hpp"
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/domain/material.hpp"
#include "nodes/levelset/level_set.hpp"
#include "nodes/propagate/fracture_step.hpp"
#include "nodes/propagate/sif_export.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/registration.hpp"

#include <cmath>
#include <stdexcept>

namespace cf {
namespace {

graph::NodeType start_node() {
    graph::NodeType t("fracture.start",
                      "The initial state of a fracture simulation: no cracks yet, the coarse crack resolution r_c "
                      "(App. A item 15) and the fine resolution r_f of the object's level set (item 16). The state is "
                      "the variable a fracture loop carries from one BEM time step to the next.");
    t.input<SurfaceMesh>("mesh", "the ordinary BEM surface (its triangle count sizes the initiation bookkeeping)");
    t.input<LevelSet>("object", "the object's level set; its voxel size is r_f");
    t.param_real("r_c", 0, "m", "target edge length of new crack elements in the BEM mesh; must exceed r_f "
                                  "(the thesis uses r_c / r_f = 17-80)").required().above(0);
    t.param_real("crack_band", 2, "voxels",
                 "narrow-band half-width of the crack grids (the object keeps its own, 3). The marker tests of "
                 "fig. 27 read Phi_f near and below sqrt(3) r_f / 2, segmentation and meshing its zero crossing, "
                 "so 2 takes the same decisions (tested); the thesis used 3, which records ~1.35x slower")
        .range(2, 10);
    t.output<propagate::FractureState>("state", "empty fracture state");
    t.run([](graph::NodeContext& c) {
        const LevelSet& object = c.in<LevelSet>("object");
        propagate::FractureState s;
        try {
            s = propagate::start_fracture_state(c.real("r_c"), object.voxel_size, c.real("crack_band"),
                                                c.in<SurfaceMesh>("mesh").num_triangles());
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("parameter 'r_c' / input 'object': ") + e.what());
        }
        c.count("r_c_over_r_f", s.r_c / s.r_f);
        c.out("state", std::move(s));
    });
    return t;
}

// propagate.fronts' run, in steps.

// The step settings from the material and parameters; the object level set must be at r_f.
propagate::StepSettings step_settings(graph::NodeContext& c, const propagate::FractureState& s, const LevelSet* object) {
    const Material& mat = c.in<Material>("material");
    propagate::StepSettings set;
    set.law.E = mat.E;
    set.law.nu = mat.nu;
    set.law.rho = mat.rho;
    set.substeps = static_cast<int>(c.integer("substeps"));
    set.surface_margin = c.real("surface_margin") * s.r_f;
    set.crack_margin = c.real("crack_margin") * s.r_f;
    if (object && std::abs(object->voxel_size - s.r_f) > 1e-9 * s.r_f)
        c.fail("input 'object' has voxel size " + graph::format_number(object->voxel_size) + " m but the state was started with r_f = " +
               graph::format_number(s.r_f) + " m; use the same level set for fracture.start and propagate.fronts");
    return set;
}

// The grids as named level sets for a .vdb file: crack0, crack1, ...
std::vector<std::pair<std::string, LevelSet>> named_crack_grids(const std::vector<LevelSet>& cracks) {
    std::vector<std::pair<std::string, LevelSet>> grids;
    for (std::size_t i = 0; i < cracks.size(); ++i) grids.emplace_back("crack" + std::to_string(i), cracks[i]);
    return grids;
}

// Called after every sub-step: Ctrl-C is noticed there (each is short; a step may have
// thousands), and with write_substep_vdb the crack grids are written.
propagate::SubstepObserver substep_observer(graph::NodeContext& c, int step) {
    if (!c.boolean("write_substep_vdb")) return [&c](int, const CrackRecorder&) { c.check_cancelled(); };
    const auto dir = c.output_dir();
    return [dir, step, &c](int k, const CrackRecorder& rec) {
        c.check_cancelled();
        const CrackLevelSets g = rec.snapshot();
        write_vdb(dir / ("cracks_step" + std::to_string(step) + "_sub" + std::to_string(k) + ".vdb"), named_crack_grids(g.cracks));
    };
}

void count_step(graph::NodeContext& c, const propagate::FractureState& s, const propagate::StepReport& r) {
    c.count("step", s.step);
    c.count("fronts_propagated", r.fronts_propagated);
    c.count("fronts_waiting", r.fronts_waiting);
    c.count("fronts_stopped", r.fronts_stopped);
    c.count("markers", static_cast<double>(r.markers));
    c.count("active_markers", static_cast<double>(r.active_markers));
    c.count("hits_left_object", static_cast<double>(r.hits_left_object));
    c.count("hits_crossed_crack", static_cast<double>(r.hits_crossed_crack));
    c.count("hits_self_intersection", static_cast<double>(r.hits_self_intersection));
    c.count("elements_added", static_cast<double>(r.elements_added));
    c.count("openings_estimated", static_cast<double>(r.openings_estimated));
    c.count("crack_elements", static_cast<double>(s.cracks.num_triangles()));
    c.count("voxels_written", static_cast<double>(r.voxels_written));
    c.count("max_marker_travel_m", r.max_marker_travel);
    c.count("simulated_time_s", r.simulated_time);
    c.count("propagate_seconds", r.propagate_seconds);
    c.count("record_seconds", r.record_seconds);
    c.count("grow_seconds", r.grow_seconds);
}

void run_fronts(graph::NodeContext& c) {
    propagate::FractureState s = c.in<propagate::FractureState>("state");
    const ScalarField& toughness = c.in<ScalarField>("toughness");
    if (toughness.quantity != FieldQuantity::toughness)
        c.fail("input 'toughness' is a " + std::string(quantity_name(toughness.quantity)) +
               " field; connect a field with quantity: toughness");
    const LevelSet* object = c.has("object") ? &c.in<LevelSet>("object") : nullptr;
    propagate::StepSettings set = step_settings(c, s, object);
    if (c.has("surface")) set.bem_surface = &c.in<SurfaceMesh>("surface");
    const propagate::SubstepObserver observer = substep_observer(c, s.step);
    propagate::StepReport r;
    try {
        r = propagate::propagate_step(s, c.in<std::vector<bem::FrontEdgeSif>>("sifs"), toughness, object, set, observer);
    } catch (const std::invalid_argument& e) {
        c.fail(e.what());
    }
    if (c.boolean("write_vdb"))
        write_vdb(c.output_dir() / ("cracks_step" + std::to_string(s.step) + ".vdb"), named_crack_grids(s.grids.cracks));
    count_step(c, s, r);
    c.out("continue", r.should_continue());
    c.out("state", std::move(s));
}

graph::NodeType fronts_node() {
    graph::NodeType t("propagate.fronts",
                      "One BEM time step of crack propagation (ch. 4.5.2): SIFs averaged to the coarse front nodes and "
                      "interpolated to n = ceil(r_c/r_f) markers per edge; n forward-Euler sub-steps with speed eq. (4.8), "
                      "direction eq. (4.10)-(4.14) (compressive rule, blending, toughness steering; the first sub-step of a "
                      "new crack is planar); after each sub-step the fig. 27 tests deactivate markers that left the object "
                      "or met a crack, and the swept strips are recorded into the crack grids (ch. 6.2); finally the crack "
                      "sheets grow by the elements of fig. 16. 'continue' is false once a step adds no element and no marker moves.");
    t.input<propagate::FractureState>("state", "fracture state of the previous step (after initiation)");
    t.input<std::vector<bem::FrontEdgeSif>>("sifs", "per crack-front edge, from sif.displacement_correlation or an estimator");
    t.input<ScalarField>("toughness", "toughness field K_c [Pa*sqrt(m)] with its compressive factor f_c");
    t.input<Material>("material", "E, nu, rho (c_R = 0.9 sqrt(mu/rho) sets the simulated time)");
    t.optional_input<LevelSet>("object", "object level set: markers leaving it stop (fig. 27 a); without it they never do");
    t.optional_input<SurfaceMesh>("surface",
                                  "the ordinary BEM surface the next assembly solves on: new crack elements that touch or "
                                  "cross it wait (the assembly would refuse them; it can stand inside the object by up to "
                                  "half a voxel where a fragment is thin or concave)");
    t.param_int("substeps", 0, "sub-steps per BEM step; 0: n = ceil(r_c / r_f) as in the thesis").at_least(0);
    t.param_real("surface_margin", 1, "voxels", "new BEM crack nodes stay this many r_f inside the object").at_least(0);
    t.param_real("crack_margin", 0, "voxels", "new BEM crack nodes stay this many r_f outside other cracks' volumes")
        .at_least(0);
    t.param_bool("write_vdb", false, "write the crack grids after the step as cracks_step<s>.vdb (App. A item 18)");
    t.param_bool("write_substep_vdb", false,
                 "write the crack grids after every sub-step as cracks_step<s>_sub<k>.vdb (App. A item 19)");
    t.writes_fixed("cracks_step*.vdb", "write_vdb");
    t.writes_fixed("cracks_step*_sub*.vdb", "write_substep_vdb");
    t.output<propagate::FractureState>("state", "state after the step");
    t.output<bool>("continue", "true while the step added elements, markers still moved, or new cracks wait for their first SIFs");
    t.run(run_fronts);
    return t;
}

graph::NodeType geometry_node() {
    graph::NodeType t("fracture.geometry",
                      "The crack geometry of a fracture state: the coarse crack sheets (for assemble.sgbem and VTK export) "
                      "and the fine crack level sets (for segment.fragments and VDB export).");
    t.input<propagate::FractureState>("state", "a fracture state");
    t.output<SurfaceMesh>("cracks", "BEM crack sheets; region r is crack r");
    t.output<CrackLevelSets>("grids", "one thickened crack grid per crack [m]");
    t.output<bem::CrackOpeningEstimate>("openings",
                                        "openings [m] estimated for crack nodes the fronts left behind (eq. 5.5-5.6), for "
                                        "assemble.sgbem once crack growth is estimated (method estimator or hybrid)");
    t.run([](graph::NodeContext& c) {
        const propagate::FractureState& s = c.in<propagate::FractureState>("state");
        c.count("cracks", s.num_cracks());
        c.count("crack_elements", static_cast<double>(s.cracks.num_triangles()));
        c.count("steps", s.step);
        c.out("cracks", s.cracks);
        c.out("grids", s.grids);
        bem::CrackOpeningEstimate openings = s.openings;
        openings.opening.resize(s.cracks.num_vertices(), Vec3::Zero());
        openings.known.resize(s.cracks.num_vertices(), 0);
        openings.front_active = propagate::moving_front_nodes(s);
        c.out("openings", std::move(openings));
    });
    return t;
}

graph::NodeType sif_export_node() {
    graph::NodeType t("export.sifs",
                      "Writes the stress intensities along every crack front: one row per front node (the mean of its two "
                      "edges, as propagation uses them, ch. 4.5.2) or per front edge, in front order, with the node "
                      "position or edge midpoint [m], the tip frame (e1 forward, e2 crack normal, e3 = e1 x e2), K_I, K_II, K_III, "
                      "the effective K of eq. (4.7) and K_c there [Pa*sqrt(m)], as CSV and as VTK polylines (one per front, "
                      "for ParaView). Inside a fracture loop it writes every step ('{iteration}' in the path); files are "
                      "written atomically.");
    t.input<std::vector<bem::FrontEdgeSif>>("sifs", "from sif.fronts, sif.estimator or sif.displacement_correlation");
    t.input<bem::BemSolution>("solution", "the solution the SIFs were read from (its crack sheets place the edges)");
    t.optional_input<ScalarField>("toughness", "toughness field for the K_c column (-1 without)");
    t.param_string("path", "", "CSV file; relative to the run's output directory; '{iteration}' becomes the loop iteration")
        .required().writes_file();
    t.param_string("vtp_path", "", "VTK polylines (.vtp); empty: '<path stem>.vtp' beside 'path'; 'none': no VTK file").writes_file();
    t.param_choice("at", "nodes", {"nodes", "edges"},
                   "one row per front node (columns front,node,crack,vertex,...) or per front edge (front,edge,crack,v0,v1,...)");
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        const bool nodes = c.string("at") == "nodes";
        const SurfaceMesh* cracks = bem::current_crack_mesh(sol);
        const ScalarField* toughness = c.has("toughness") ? &c.in<ScalarField>("toughness") : nullptr;
        if (toughness && toughness->quantity != FieldQuantity::toughness)
            c.fail("input 'toughness' is a " + std::string(quantity_name(toughness->quantity)) +
                   " field; connect a field with quantity: toughness");
        const std::filesystem::path csv = c.output_path(c.string("path"));
        std::filesystem::path vtp = c.string("vtp_path");
        if (vtp.empty()) vtp = csv.parent_path() / (csv.stem().string() + ".vtp");
        else if (vtp != "none") vtp = c.output_path(c.string("vtp_path"));
        std::vector<propagate::FrontSifRow> rows;
        try {
            const auto& sifs = c.in<std::vector<bem::FrontEdgeSif>>("sifs");
            const double nu = sol.surface->elastic.nu;
            if (cracks)
                rows = nodes ? propagate::front_node_sif_rows(*cracks, sifs, nu, toughness)
                             : propagate::front_sif_rows(*cracks, sifs, nu, toughness);
            propagate::write_front_sifs_csv(csv, rows, nodes);
            if (vtp != "none") propagate::write_front_sifs_vtp(vtp, rows);
        } catch (const std::invalid_argument& e) {
            c.fail(std::string("inputs 'sifs' / 'solution': ") + e.what());
        } catch (const std::exception& e) {
            c.fail("parameter 'path' (" + csv.string() + ") / 'vtp_path': " + e.what());
        }
        c.count(nodes ? "front_nodes" : "front_edges", static_cast<double>(rows.size()));
    });
    return t;
}

}  // namespace

void register_propagate_nodes(graph::NodeRegistry& r) {
    r.add(start_node());
    r.add(fronts_node());
    r.add(geometry_node());
    r.add(sif_export_node());
}

}  // namespace cf
