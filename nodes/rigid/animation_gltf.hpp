#pragma once
// A rigid-body Animation as one glTF 2.0 binary (.glb) for Blender and any glTF viewer.
//
// Conventions of the file:
//  - Units: metres and seconds (glTF's own). glTF is +Y up and right-handed; the scene keeps its
//    own axes under a root node "crackflow_scene" whose rotation maps GltfOptions::up onto +Y
//    (no rotation when up is +Y). Everything below the root is in scene axes.
//  - Nodes: node 0 is the root; node 1 + i is piece i (Animation::pieces order), named
//    piece.name, a child of the root (not of its parent piece: a fragment moves on its own).
//    Its local transform is the pose: translation = centre of mass, rotation = body-to-world
//    quaternion, so x = position + rotation * x_rest as in animation.hpp. Its static transform
//    is the first pose, with scale 0 if it is not yet alive at frame 0 (what a viewer without
//    animation shows is the initial state).
//  - Meshes: mesh i is piece i's rest mesh (body frame), one primitive of triangles with float32
//    POSITION (with min/max), float32 NORMAL and uint32 indices. Normals are area-weighted over the
//    triangles around a vertex whose normals lie within 30 degrees of the corner's own triangle,
//    so crack faces and box edges stay sharp while curved surfaces shade smoothly; a vertex is
//    split once per distinct normal. Each piece has its own material, named after
//    it, in its colour of the scene previews (scene_piece_colours); a piece whose rest mesh has
//    fracture faces (region "inside") draws them as a second primitive with material
//    "<name>.inside" in the inside shade of that colour (fragment_palette.hpp). Rough, not metallic.
//  - Animation 0, "simulation": per piece a translation and a rotation sampler (LINEAR, float32)
//    keyed at every frame time at which the piece is alive, plus a key at the first and the last
//    frame's time holding the first / last pose when the piece is born later or dies earlier, so
//    every piece's keys span [frames.front().time, frames.back().time]. Rotations are made
//    sign-continuous (q and -q are the same rotation, but slerp between them would spin the long
//    way). A scale sampler (STEP) is 0 before first_frame, 1 from first_frame through last_frame
//    and 0 from the frame after last_frame on: fragments appear at the frame they are created and
//    broken parents vanish.
//  - Node extras: {"id": piece index, "parent": parent index or -1, "volume": [m^3],
//    "mass": [kg], "class": piece_class_name}.
//  - The file is a function of its input: identical animations give byte-identical files (no
//    time stamps; generator "crackflow").
#include "nodes/rigid/animation.hpp"

#include <filesystem>

namespace cf::rigid {

struct GltfOptions {
    Vec3 up = Vec3(0, 0, 1);  // the scene's up axis (any non-zero length), mapped onto glTF's +Y
};

// Checks the animation (check_animation) and writes it atomically to `path`. Throws
// std::invalid_argument for a bad animation or a zero / non-finite `up`, std::runtime_error
// naming the path when the file cannot be written.
void write_animation_glb(const Animation& a, const std::filesystem::path& path, const GltfOptions& o = {});

}  // namespace cf::rigid
