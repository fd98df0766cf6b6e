#pragma once
// The colour of every piece of a rigid-body scene, shared by the scene previews
// (scene_preview.hpp) and the scene's glTF materials (animation_gltf.hpp), so a piece looks the
// same in both.
#include "nodes/rigid/animation.hpp"

#include <vector>

namespace cf::rigid {

// Base colour of every piece (RGB in [0, 1]), a function of the pieces' names, parents and order
// (the same in every frame and run; adding or renaming a body may change the others'). Original
// bodies, ordered by an FNV-1a hash of their names, take hues a golden angle (137.5 degrees)
// apart, at saturation 0.7 and value 0.9. A fragment takes its original ancestor's hue shifted by
// at most 6 degrees and its own saturation in [0.45, 0.85] and value in [0.55, 1] (the k-th
// fragment of a body, in piece order, from the k-th point of a low-discrepancy sequence: no two
// alike), so fragments read as shades of their body. Throws std::invalid_argument naming a piece
// whose parent is out of range or part of a cycle.
std::vector<Vec3> scene_piece_colours(const Animation& a);

}  // namespace cf::rigid
