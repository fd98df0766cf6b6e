#include "nodes/register_all.hpp"

#include "nodes/registration.hpp"

#include <algorithm>

namespace cf {

const graph::NodeRegistry& node_registry() {
    static const graph::NodeRegistry registry = [] {
        graph::NodeRegistry r;
        register_core_nodes(r);
        register_shape_nodes(r);
        register_regions_nodes(r);
        register_import_nodes(r);
        register_export_nodes(r);
        register_levelset_nodes(r);
        register_simplify_nodes(r);
        register_segment_nodes(r);
        register_bem_nodes(r);
        register_fields_nodes(r);
        register_initiate_nodes(r);
        register_propagate_nodes(r);
        register_estimate_nodes(r);
        register_rigid_nodes(r);
        register_probes_nodes(r);
        add_plan_checks(r);
        return r;
    }();
    return registry;
}

const std::vector<VerificationCase>& verification_cases() {
    static const std::vector<VerificationCase> cases = [] {
        std::vector<VerificationCase> c;
        add_propagate_verification_cases(c);
        add_initiate_verification_cases(c);
        add_levelset_verification_cases(c);
        add_bem_verification_cases(c);
        add_fracture_verification_cases(c);
        add_estimate_verification_cases(c);
        add_estimator_pipeline_cases(c);
        add_rigid_verification_cases(c);
        add_scene_verification_cases(c);
        add_remesh_verification_cases(c);
        std::sort(c.begin(), c.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
        return c;
    }();
    return cases;
}

}  // namespace cf
