#pragma once
// Consistency of a recorded Animation (nodes/rigid/animation.hpp). Both animation writers call
// check_animation before they write a byte, so a broken recording is reported with the piece or
// frame at fault instead of producing a file that a viewer misplays.
#include "nodes/rigid/animation.hpp"

namespace cf::rigid {

// Throws std::invalid_argument whose message names the piece (index and name) or the frame
// (index and time) at fault, for:
//  - frame_rate not finite and > 0 [1/s]; no frames; frame times not finite and strictly increasing;
//  - a piece with an empty name or a name another piece has; a parent other than -1 or another
//    piece's index; a missing or empty rest mesh, or one with a non-finite vertex or a triangle
//    index out of range; a non-finite or negative volume or mass;
//  - first_frame outside the frames, last_frame neither -1 nor in [first_frame, last frame];
//  - a frame whose poses are not in strictly increasing piece index, name a piece that does not
//    exist or is not alive at that frame, or miss a piece that is alive;
//  - a non-finite pose, or a rotation quaternion with | |q| - 1 | > 1e-9.
void check_animation(const Animation& a);

// The last frame at which piece p is visible: p.last_frame, or the last frame for -1.
int last_visible_frame(const Animation& a, const AnimationPiece& p);

// The pose of piece `piece` at frame `frame`; nullptr if the frame has none for it.
// (Poses are sorted by piece index, so this is a binary search.)
const PiecePose* find_pose(const AnimationFrame& frame, int piece);

}  // namespace cf::rigid
