#pragma once
// VTK XML PolyData (.vtp) for ParaView: the triangles, a per-triangle Int32 "region" array,
// and any number of extra named per-vertex (PointData) and per-triangle (CellData) arrays of
// doubles with 1 (scalar) or 3 (vector) components. ASCII inline data with full double
// precision, so the file is exact and diffable.
#include "nodes/domain/surface_mesh.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace cf {

struct VtpArray {
    std::string name;
    int components = 1;          // 1 = scalar, 3 = vector
    std::vector<double> values;  // components * (number of points or cells), interleaved
};

struct VtpFields {
    std::vector<VtpArray> point_data;  // one tuple per vertex
    std::vector<VtpArray> cell_data;   // one tuple per triangle ("region" is always added)
};

// Throws std::invalid_argument for an array of the wrong length, a component count other
// than 1 or 3, an empty or duplicate name, or a cell array named "region".
void write_vtp(std::ostream& os, const SurfaceMesh& m, const VtpFields& fields = {});

// Polylines (VTK Lines cells): `lines` are lists of point indices; `point_data` one tuple per point.
// Throws std::invalid_argument for an index out of range, a line of fewer than 2 points, a
// non-finite point or an array as for write_vtp.
void write_vtp_lines(std::ostream& os, const std::vector<Vec3>& points, const std::vector<std::vector<int>>& lines,
                     const std::vector<VtpArray>& point_data = {});

}  // namespace cf
