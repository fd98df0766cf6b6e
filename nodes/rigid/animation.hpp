#pragma once
// The animation a rigid-body scene records (thesis ch. 8, animation output): every piece that
// ever exists (original bodies and the fragments that replace broken ones), its high-resolution
// rest mesh in its body frame, and its pose at every frame it is alive. Writers turn it into a
// glTF 2.0 binary (Blender, any glTF viewer) and a points-as-transforms cache (Houdini's
// Transform Pieces, ParaView). Immutable once recorded; rest meshes are shared, not copied.
// SI units: m, s, kg, rad/s.
#include "nodes/domain/surface_mesh.hpp"

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace cf::rigid {

// How a piece collides and whether it can break again (thesis ch. 7.3).
enum class PieceClass {
    original,   // a body of the scene as authored
    hull,       // (a) small fragment: convex hull, not breakable
    mesh,       // (b) medium fragment: non-convex collision mesh, not breakable
    breakable,  // (c) large fragment: new BEM mesh, breakable
    large,      // (d) > 95 % of its parent: keeps the parent's BEM mesh and operators
};
const char* piece_class_name(PieceClass c);  // "original", "hull", "mesh", "breakable", "large"

struct AnimationPiece {
    std::string name;   // unique, stable across runs: "<body>" or "<parent name>.<k>" (k from 0)
    int parent = -1;    // index into Animation::pieces, -1 for an original body
    PieceClass piece_class = PieceClass::original;
    double volume = 0;  // [m^3]
    double mass = 0;    // [kg] (0 for static or kinematic bodies)
    bool dynamic = true;
    // Rest mesh in the body frame: x_world = position + rotation * x_rest.
    std::shared_ptr<const SurfaceMesh> rest_mesh;
    int first_frame = 0;   // first frame at which the piece is visible
    int last_frame = -1;   // last frame at which it is visible (inclusive); -1: until the end
};

struct PiecePose {
    Vec3 position = Vec3::Zero();                                   // centre of mass [m]
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();   // body to world, unit
    Vec3 velocity = Vec3::Zero();                                   // [m/s]
    Vec3 angular_velocity = Vec3::Zero();                           // [rad/s], world axes
};

struct AnimationFrame {
    double time = 0;  // [s] of the frame
    // (piece index, pose) for every piece alive at this frame, in increasing piece index.
    std::vector<std::pair<int, PiecePose>> poses;
};

struct Animation {
    double frame_rate = 25;             // [1/s]
    std::vector<AnimationPiece> pieces;
    std::vector<AnimationFrame> frames;  // frame 0 is the initial state
};

}  // namespace cf::rigid

CF_GRAPH_TYPE(cf::rigid::Animation, "Animation");
