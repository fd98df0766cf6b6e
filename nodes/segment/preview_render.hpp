#pragma once
// A preview PNG of the fragments (ch. 6.4), exploded away from their common centroid, ray
// traced on the level sets (OpenVDB LevelSetRayTracer) with a clamped two-light Lambert shader.
#include "nodes/segment/fragments.hpp"

#include <filesystem>
#include <string>

namespace cf {

struct PreviewOptions {
    int width = 640, height = 480;  // [pixels]
    double explode = 0.3;           // each fragment moves by explode x (its centroid - common centroid)
    int samples_per_pixel = 1;
    // Camera: `up` is the scene's vertical (the built-in shapes and the thesis cases are z-up,
    // most imported meshes y-up); the eye looks at the scene's centre from the direction `view`
    // (any length, not parallel to `up`).
    Vec3 up = Vec3(0, 0, 1);
    Vec3 view = Vec3(0.5, -1.2, 0.7);
};

// What is wrong with the camera of `options` ('up' or 'view' zero or not finite, 'view' parallel
// to 'up'), or "" if it is usable.
std::string preview_camera_problem(const PreviewOptions& options);

// Writes the PNG atomically. Throws std::invalid_argument for an empty fragment list, a bad
// size or a camera whose view is zero or parallel to up, std::runtime_error if the PNG cannot be written.
void render_fragments_preview(const std::filesystem::path& png, const Fragments& fragments,
                              const PreviewOptions& options = {});

// Writes an 8-bit RGB image (row 0 at the top) as PNG, atomically.
void write_png_rgb(const std::filesystem::path& png, int width, int height, const unsigned char* rgb);

}  // namespace cf
