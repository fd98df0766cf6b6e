#pragma once
// A rigid-body Animation as a points-as-transforms cache: one point per live piece and frame,
// carrying the attributes Houdini's Transform Pieces SOP applies to the rest geometry (name,
// P, orient, pivot), in VTK XML PolyData files that ParaView and VTK read directly.
//
// Files written into `dir` (all ASCII, every double exact: shortest round-trip decimal,
// locale-independent; each file written atomically):
//  - <stem>_rest.vtp: every piece's rest mesh in its body frame (centre of mass at the origin,
//    so the meshes overlap), triangles only. CellData Int32 "piece" (the piece index of each
//    triangle), Int32 "inside" (1 for a fracture face: region "inside"), and, when some piece has
//    texture coordinates, Float64 x 6 "uv" (u v of the triangle's three corners in order; zeros
//    for a piece without); FieldData String "piece_names" (entry i is piece i's name).
//  - <stem>_<ffff>.vtp for every frame f (4 digits, zero-padded; more digits past 9999): one
//    point and one vertex cell per piece alive at f, in increasing piece index. Point = P, the
//    centre of mass [m]. PointData: "name" (String, the piece name), "piece" (Int32 index),
//    "orient" (Float64 x 4: body-to-world quaternion x y z w, Houdini's order), "pivot"
//    (Float64 x 3: zero, because rest meshes are in the body frame), "v" (Float64 x 3, [m/s]),
//    "w" (Float64 x 3, [rad/s], world axes). FieldData Float64 "TimeValue" (the frame time [s]),
//    which ParaView uses as the time of a file series.
//  - <stem>.pvd: a ParaView collection with one <DataSet timestep="time" part="0" file=...> per
//    frame (file names relative to the .pvd); written last, so it names only files that exist.
// A piece's world geometry is rest vertex x -> P + orient * x. Coordinates are the scene's own
// axes and SI units; Houdini is Y-up, so a Z-up scene needs a -90 degree rotation about X there.
// String arrays are VTK's ASCII form: the UTF-8 bytes of each string as decimal numbers, each
// string ended by 0 (vtkXMLPolyDataReader reads them as vtkStringArray).
#include "nodes/rigid/animation.hpp"

#include <filesystem>
#include <string>

namespace cf::rigid {

// Checks the animation (check_animation) and writes the files above; `stem` must be a plain,
// non-empty file name (no directory separators). Creates `dir` if needed. Throws
// std::invalid_argument for a bad animation or stem, std::runtime_error naming a file that
// cannot be written.
void write_transform_cache(const Animation& a, const std::filesystem::path& dir, const std::string& stem);

// The name of frame f's file: "<stem>_0007.vtp".
std::string transform_cache_frame_name(const std::string& stem, int frame);

}  // namespace cf::rigid
