// Node adapter for nodes/probes: export.probes.
#include "graph/node_context.hpp"
#include "graph/registry.hpp"
#include "nodes/probes/probe_export.hpp"
#include "nodes/registration.hpp"
#include "nodes/vec3_param.hpp"

#include <stdexcept>

namespace cf {

void register_probes_nodes(graph::NodeRegistry& r) {
    graph::NodeType t("export.probes",
                      "Writes displacement [m] and Cauchy stress [Pa] (tensor and principal values, largest first) of an "
                      "SGBEM solution at points inside the body (representation formula, thesis eq. 2.20 and 2.23; cracks "
                      "included): at the user's 'points', or on a grid slice (origin + s u + t v, s, t in [0, 1]; the grid "
                      "points outside the body are left out). CSV, and for a slice also VTK PolyData for ParaView. Inside a "
                      "fracture loop it writes every step ('{iteration}' in the path); files are written atomically. A user "
                      "point outside the body (or on its surface or a crack) is an error naming it.");
    t.input<bem::BemSolution>("solution", "from solve.sgbem");
    t.param_reals("points", {}, "m", "probe points as x y z triples, e.g. [0, 0, 0, 0.01, 0, 0]; empty: use the slice");
    t.param_reals("slice_origin", {0, 0, 0}, "m", "grid slice: corner point").size(3);
    t.param_reals("slice_u", {1, 0, 0}, "m", "grid slice: first edge vector (from the origin to the far corner along it)").size(3);
    t.param_reals("slice_v", {0, 1, 0}, "m", "grid slice: second edge vector").size(3);
    t.param_int("slice_u_points", 0, "grid slice: points along slice_u (0: no slice; otherwise at least 2)").range(0, 1000);
    t.param_int("slice_v_points", 0, "grid slice: points along slice_v (0: no slice; otherwise at least 2)").range(0, 1000);
    t.param_bool("include_cracks", true, "include the crack sheets' term (false: the surface data only)");
    t.param_string("path", "", "CSV file; relative to the run's output directory; '{iteration}' becomes the loop iteration")
        .required()
        .writes_file();
    t.param_string("vtp_path", "", "slice as VTK PolyData (.vtp); empty: '<path stem>.vtp' beside 'path'; 'none': no VTK file")
        .writes_file();
    t.run([](graph::NodeContext& c) {
        const bem::BemSolution& sol = c.in<bem::BemSolution>("solution");
        const std::vector<double>& flat = c.reals("points");
        const long long nu = c.integer("slice_u_points"), nv = c.integer("slice_v_points");
        const bool slice_given = nu > 0 || nv > 0;
        if (flat.empty() == !slice_given)
            c.fail(flat.empty() ? "give either 'points' or a grid slice ('slice_u_points' and 'slice_v_points' >= 2)"
                                : "give either 'points' or a grid slice, not both (set 'slice_u_points' and "
                                  "'slice_v_points' to 0, or 'points' to [])");
        if (flat.size() % 3 != 0)
            c.fail("parameter 'points' has " + std::to_string(flat.size()) + " numbers; it needs x y z triples [m]");
        if (slice_given && (nu < 2 || nv < 2)) c.fail("parameters 'slice_u_points' and 'slice_v_points' must both be at least 2");
        probes::GridSlice slice;
        slice.origin = vec3_param(c, "slice_origin");
        slice.u = vec3_param(c, "slice_u");
        slice.v = vec3_param(c, "slice_v");
        slice.nu = static_cast<int>(nu);
        slice.nv = static_cast<int>(nv);
        if (slice_given && slice.u.cross(slice.v).norm() <= 1e-12 * slice.u.norm() * slice.v.norm())
            c.fail("parameters 'slice_u' and 'slice_v' are parallel or zero; give two independent edge vectors [m]");
        std::vector<probes::ProbeSample> samples;
        try {
            if (slice_given) {
                samples = probes::probe_slice(sol, slice, c.boolean("include_cracks"));
            } else {
                std::vector<Vec3> pts;
                for (std::size_t k = 0; k < flat.size(); k += 3) pts.emplace_back(flat[k], flat[k + 1], flat[k + 2]);
                samples = probes::probe_points(sol, pts, c.boolean("include_cracks"));
            }
        } catch (const std::invalid_argument& e) {
            c.fail((slice_given ? "grid slice: " : "parameter 'points': ") + std::string(e.what()));
        }
        c.check_cancelled();
        const std::filesystem::path csv = c.output_path(c.string("path"));
        std::filesystem::path vtp = c.string("vtp_path");
        if (vtp.empty()) vtp = csv.parent_path() / (csv.stem().string() + ".vtp");
        else if (vtp != "none") vtp = c.output_path(c.string("vtp_path"));
        try {
            probes::write_probe_csv(csv, samples, slice_given ? &slice : nullptr);
            if (slice_given && vtp != "none") probes::write_probe_slice_vtp(vtp, samples, slice);
        } catch (const std::exception& e) {
            c.fail("parameter 'path' (" + csv.string() + ") / 'vtp_path': " + e.what());
        }
        double smax = -1e300, smin = 1e300;
        for (const auto& s : samples) {
            smax = std::max(smax, s.principal[0]);
            smin = std::min(smin, s.principal[2]);
        }
        c.count("points", static_cast<double>(samples.size()));
        if (slice_given) c.count("points_outside", static_cast<double>(nu * nv) - static_cast<double>(samples.size()));
        c.count("max_principal_stress", smax);
        c.count("min_principal_stress", smin);
    });
    r.add(std::move(t));
}

}  // namespace cf
