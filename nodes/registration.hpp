#pragma once
// One registration function per stage folder; nodes/register_all.cpp calls each.
#include "graph/registry.hpp"
#include "nodes/domain/verification_case.hpp"

#include <vector>

namespace cf {

void register_core_nodes(graph::NodeRegistry& r);    // nodes/core: generic value and test nodes
void register_shape_nodes(graph::NodeRegistry& r);   // nodes/shape
void register_import_nodes(graph::NodeRegistry& r);  // nodes/import
void register_export_nodes(graph::NodeRegistry& r);  // nodes/export

// Verification cases per stage (crackflow verify).
// (stages add: void add_<stage>_verification_cases(std::vector<VerificationCase>& cases);)

}  // namespace cf
