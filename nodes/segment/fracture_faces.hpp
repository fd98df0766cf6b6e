#pragma once
// Which faces of a level-set fragment mesh are fracture faces (issue 14). The dual-contoured mesh
// of a fragment grid (max(Phi_o, -Phi_c), eq. 6.1) has no memory of where its faces came from, so
// they are told apart by the uncut object's distance field: a face on the object's own surface has
// Phi_o ~ 0 at its centroid (to the trilinear sampling error, well under half a voxel even at sharp
// edges), a face made by a crack lies inside the object, Phi_o < 0. Faces deeper than `depth`
// become the region "inside" (the name every writer, the preview and the glTF materials look for),
// the others "outside". A ring of crack faces within `depth` of the object's surface reads as
// outside: at depth = r_f / 2 that ring is half a voxel wide.
#include "nodes/levelset/level_set.hpp"

namespace cf {

inline constexpr const char* kOutsideRegion = "outside";
inline constexpr double kFractureFaceDepthVoxels = 0.5;  // the depth used by the meshers [voxels of r_f]

// Sets m's regions to {outside, inside} as above, dropping any earlier regions, and reorders the
// triangles (with their corner attributes) so the outside ones come first, each part in its old order. `object` is the uncut
// object's signed distance grid [m], `depth` [m] > 0. Throws std::invalid_argument for a bad depth.
void tag_fracture_faces(SurfaceMesh& m, const LevelSet& object, double depth);

// The area [m^2] of m's triangles in the region named `name` (0 when there is no such region).
double region_area(const SurfaceMesh& m, const std::string& name);

}  // namespace cf
