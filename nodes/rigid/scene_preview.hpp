#pragma once
// Per-frame preview images of a rigid-body scene (nodes/rigid/animation.hpp): a software z-buffer
// rasteriser (no GPU, no extra dependency) with a perspective camera, flat Lambert + ambient
// shading, one colour per piece, an optional checkerboard ground plane and a sky gradient. Meant
// for looking at a recorded scene frame by frame without a glTF viewer, and for tests. Output does
// not depend on the thread count (oneTBB bands of rows, each pixel written by one task).
// SI units: m; angles in degrees where named so.
#include "nodes/rigid/animation.hpp"
#include "nodes/rigid/piece_colours.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace cf::rigid {

struct SceneCamera {
    Vec3 position = Vec3(2.5, -3.0, 1.8);  // [m]
    Vec3 target = Vec3(0, 0, 0.3);         // [m] looked at (the image centre)
    Vec3 up = Vec3(0, 0, 1);               // the scene's vertical (image up, sky gradient)
    double fov_degrees = 40;               // vertical field of view, in (0, 180)
    int width = 640, height = 480;         // [pixels], each in [16, 8192]
};

// Returns "" when usable, else what is wrong (parameter name first), e.g.
// "up: parallel to the view direction".
std::string scene_camera_problem(const SceneCamera& c);

// The image itself, for tests: 3 * width * height RGB bytes, row 0 at the top. Draws every piece
// that has a pose in frame `f`, at x_world = position + rotation * x_rest. The ground is the plane
// through `ground_point` with normal `ground_normal` (any length), drawn only if `ground`, as a
// light checkerboard of 1 m squares (from ground_point, along the world x axis projected on the
// plane) that fades into the horizon with distance and where squares get smaller than 4 pixels.
// Faces whose outward normal points away from the camera are not drawn (back-face culling: rest
// meshes are closed and counter-clockwise seen from outside, as SurfaceMesh has it; an inverted
// mesh shows its inside); geometry nearer to the camera than 1/1000 of its distance to the target
// is clipped. Throws std::invalid_argument naming what is wrong for a bad camera, `f`
// out of range, a bad ground plane (when drawn), or a pose/piece that cannot be drawn (piece index
// out of range, no rest mesh, a triangle index out of range, a non-finite vertex or pose, a
// rotation whose quaternion norm is off 1 by more than 1e-6, a bad parent).
std::vector<unsigned char> render_scene_image(const Animation& a, std::size_t f, const SceneCamera& c,
                                              const Vec3& ground_point, const Vec3& ground_normal, bool ground);

// Renders frame `f` of `a` as render_scene_image does and writes it as a PNG, atomically
// (std::runtime_error naming the path if it cannot be written).
void render_scene_preview(const Animation& a, std::size_t f, const SceneCamera& c, const std::filesystem::path& png,
                          const Vec3& ground_point, const Vec3& ground_normal, bool ground);

// ---- shading, public so tests can compute the expected pixel by hand ---------------------------


// Unit vector towards the light, fixed to the camera: normalise(-1 right + 1 up + 1.5 back), i.e.
// from the camera's upper left. A face with unit normal n (outward, facing the camera) is drawn in
// colour * (kSceneAmbient + kSceneDiffuse * max(0, n . light)), clamped to [0, 1], then rounded
// to bytes (255 * value). A 1-pixel outline: a piece's pixels next to (4-neighbourhood) a pixel of
// another piece, the ground or the sky are multiplied by kSceneOutline before rounding.
Vec3 scene_light_direction(const SceneCamera& c);
constexpr double kSceneAmbient = 0.3;
constexpr double kSceneDiffuse = 0.7;
constexpr double kSceneOutline = 0.7;

}  // namespace cf::rigid
