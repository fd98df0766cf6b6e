#pragma once
// Test reference for the fragment search (ch. 6.3): the voxel-by-voxel algorithm of crackflow
// before issue 17, with the same contract as cf::find_fragments.
#include "nodes/segment/fragments.hpp"

namespace cf::reference {

Fragments find_fragments_voxelwise(const LevelSet& broken, const SegmentOptions& options = {});

}  // namespace cf::reference
