#pragma once
// Writers for probe samples: CSV (one row per point) and, for a grid slice, VTK PolyData (.vtp) of
// the slice's cells inside the body, for ParaView. Full-precision text, written atomically.
#include "nodes/probes/probe_points.hpp"

#include <filesystem>

namespace cf::probes {

// Columns: point (or i,j for a slice), x, y, z [m], ux, uy, uz [m], sxx, syy, szz, syz, sxz, sxy,
// s1, s2, s3 [Pa] (principal stresses, largest first). `slice` null: user points.
void write_probe_csv(const std::filesystem::path& path, const std::vector<ProbeSample>& samples, const GridSlice* slice);

// The slice's inside points with the quads whose four corners are inside (two triangles each);
// point arrays u, stress_diagonal (sxx, syy, szz), stress_shear (syz, sxz, sxy), sigma_1..3.
void write_probe_slice_vtp(const std::filesystem::path& path, const std::vector<ProbeSample>& samples, const GridSlice& slice);

}  // namespace cf::probes
