#pragma once
// VTK PolyData (.vtp) of an SGBEM solution for ParaView: the ordinary surface with the nodal
// displacement "u" [m] (point data), the element traction "traction" [Pa] and "dirichlet"
// (1 where the traction was solved for, 0 where it was prescribed) as cell data, plus the region
// ids; and, when there are cracks, the crack sheets with the opening "du" = [u] = u+ - u- [m]
// (0 at front nodes) and optionally the average displacement "u_average" = u_c (thesis ch. 6.4).
#include "nodes/bem/interior_evaluation.hpp"
#include "nodes/export/vtp_writer.hpp"

#include <filesystem>

namespace cf::bem {

VtpFields surface_fields(const BemSolution& sol);
// `average` may be empty (no u_average array) or hold one value per crack vertex.
VtpFields crack_fields(const BemSolution& sol, const std::vector<Vec3>& average);

// Writes the surface file and, when the solution has cracks, the crack file, each atomically.
// Throws std::runtime_error naming the path when writing fails.
void write_bem_vtk(const BemSolution& sol, const std::filesystem::path& surface_path,
                   const std::filesystem::path& crack_path, bool crack_average);

}  // namespace cf::bem
