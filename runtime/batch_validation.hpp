#pragma once
// Checking a whole manifest before anything runs: every distinct pipeline as `crackflow validate`
// checks it, then every row's overrides applied to its pipeline, as `run --set` would apply them.
// All problems are collected, each with the manifest line and column of the cell at fault.
#include "graph/registry.hpp"
#include "runtime/batch_manifest.hpp"

#include <vector>

namespace cf::runtime::batch {

// `fast`: check the pipelines as `run --fast` runs them (their fast: sections applied).
void validate_manifest(const Manifest& manifest, const graph::NodeRegistry& registry, bool fast,
                       std::vector<Problem>& problems);

}  // namespace cf::runtime::batch
