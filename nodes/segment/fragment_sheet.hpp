#pragma once
// The fragments' preview (issue 14): a contact sheet of four orthographic views in one PNG, the
// user's oblique view (top left), front, side and top, every fragment in its own colour
// (fragment_palette.hpp, by fragment index) and its fracture faces (region "inside") in a pale
// shade of it, pieces moved apart by `explode`. A software z-buffer on the fragment meshes: the
// pixels do not depend on the thread count (each view is drawn by one task, nearest face wins,
// ties to the lower fragment and triangle index).
#include "nodes/domain/surface_mesh.hpp"

#include <filesystem>
#include <vector>

namespace cf {

struct SheetOptions {
    int width = 640, height = 480;  // [pixels] of the whole image; the sheet's views are half of each
    double explode = 1.0;           // fragment i moves by explode x (its centroid - the common centroid)
    Vec3 up = Vec3(0, 0, 1);        // the scene's vertical, drawn upwards
    Vec3 view = Vec3(0.5, -1.2, 0.7);  // oblique view: direction from the scene's centre to the camera
    bool contact_sheet = true;      // false: only the oblique view (width x height)
};

// The sheet's RGB bytes (row 0 at the top), for tests: width x height x 3; each of the four views
// is (width / 2) x (height / 2) pixels (the whole image without the contact sheet). `centroids` [m] one per mesh. Throws
// std::invalid_argument for no meshes, sizes that differ, a bad size or camera.
std::vector<unsigned char> render_fragment_sheet(const std::vector<SurfaceMesh>& meshes,
                                                 const std::vector<Vec3>& centroids, const SheetOptions& options,
                                                 int* sheet_width = nullptr, int* sheet_height = nullptr);

// Renders and writes the PNG atomically.
void write_fragment_sheet(const std::filesystem::path& png, const std::vector<SurfaceMesh>& meshes,
                          const std::vector<Vec3>& centroids, const SheetOptions& options);

// A fracture step at a glance (issue 14's per-step preview): the same four views of the object cut
// away — only its far walls drawn (faces turned away from the camera, pale grey), so what is inside
// shows — and the crack surfaces in front of them, crack i in fragment_colour(i). Framed on the
// object, so the images of a run's steps line up. `object`: any closed outward mesh of the object
// (the BEM surface); `cracks`: one closed mesh per crack (the shell of its recorded level set).
// Throws std::invalid_argument for an object without vertices or a bad size or camera.
std::vector<unsigned char> render_crack_sheet(const SurfaceMesh& object, const std::vector<SurfaceMesh>& cracks,
                                              const SheetOptions& options, int* sheet_width = nullptr,
                                              int* sheet_height = nullptr);
void write_crack_sheet(const std::filesystem::path& png, const SurfaceMesh& object, const std::vector<SurfaceMesh>& cracks,
                       const SheetOptions& options);

}  // namespace cf
