#pragma once
// Guards for the writers: a mesh with an out-of-range index or a region array of the wrong
// length would otherwise write a corrupt file (or read out of bounds).
#include "nodes/domain/surface_mesh.hpp"

namespace cf {

// Throws std::invalid_argument describing the first problem.
void check_writable(const SurfaceMesh& m);

}  // namespace cf
