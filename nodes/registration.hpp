#pragma once
// One registration function per stage folder; nodes/register_all.cpp calls each.
#include "graph/registry.hpp"
#include "nodes/domain/verification_case.hpp"

#include <vector>

namespace cf {

void register_core_nodes(graph::NodeRegistry& r);    // nodes/core: generic value and test nodes
void register_shape_nodes(graph::NodeRegistry& r);   // nodes/shape
void register_regions_nodes(graph::NodeRegistry& r); // nodes/regions
void register_import_nodes(graph::NodeRegistry& r);  // nodes/import
void register_export_nodes(graph::NodeRegistry& r);  // nodes/export
void register_levelset_nodes(graph::NodeRegistry& r);  // nodes/levelset (levelset.*, record.*)
void register_simplify_nodes(graph::NodeRegistry& r);  // nodes/simplify
void register_segment_nodes(graph::NodeRegistry& r);   // nodes/segment (segment.*, export.fragments)
void register_bem_nodes(graph::NodeRegistry& r);       // nodes/bem (assemble.sgbem, solve.sgbem)
void register_fields_nodes(graph::NodeRegistry& r);    // nodes/fields (fields.*, material.brittle)
void register_initiate_nodes(graph::NodeRegistry& r);  // nodes/initiate (initiate.cracks, initiate.user_crack)
void register_propagate_nodes(graph::NodeRegistry& r); // nodes/propagate (fracture.*, propagate.fronts)
void register_estimate_nodes(graph::NodeRegistry& r);  // nodes/estimate (sif.fronts, sif.estimator)
void register_rigid_nodes(graph::NodeRegistry& r);     // nodes/rigid (rigid.*, export.animation)
void register_probes_nodes(graph::NodeRegistry& r);    // nodes/probes (export.probes)

// Checks across nodes run by the pipeline loader (nodes/region_names_check.cpp: boundary
// conditions naming regions an upstream mesh will not have).
void add_plan_checks(graph::NodeRegistry& r);

// Verification cases per stage (crackflow verify).
// (stages add: void add_<stage>_verification_cases(std::vector<VerificationCase>& cases);)
void add_propagate_verification_cases(std::vector<VerificationCase>& cases);  // nodes/propagate: cases 6, 7
void add_initiate_verification_cases(std::vector<VerificationCase>& cases);   // nodes/initiate: case 4
void add_bem_verification_cases(std::vector<VerificationCase>& cases);  // nodes/bem: operator identities, cases 1-3, 5
void add_levelset_verification_cases(std::vector<VerificationCase>& cases);  // nodes/segment: cases 9-12
void add_estimate_verification_cases(std::vector<VerificationCase>& cases);  // nodes/estimate: cases 18-22 (ch. 5)
void add_estimator_pipeline_cases(std::vector<VerificationCase>& cases);  // nodes/estimator_verification.cpp: 19-21
void add_rigid_verification_cases(std::vector<VerificationCase>& cases);  // nodes/rigid: cases 23-25 (ch. 7)
void add_scene_verification_cases(std::vector<VerificationCase>& cases);  // nodes/scene_verification.cpp: 26-28
void add_remesh_verification_cases(std::vector<VerificationCase>& cases);  // nodes/remesh_verification.cpp: rigid_translation_remeshed
void add_fracture_verification_cases(std::vector<VerificationCase>& cases);  // nodes/fracture_verification.cpp: case 8

}  // namespace cf
