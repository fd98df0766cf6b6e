#pragma once
// Shared set-up of the initiation tests: a unit cube solved by the SGBEM under uniaxial load,
// the exact box signed distance, and a fracture state for it.
#include "nodes/bem/operators.hpp"
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/fields/closed_form_fields.hpp"
#include "nodes/propagate/fracture_state.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace cf::initiate::testing {

inline Material test_material() {
    Material m;
    m.E = 1e10;
    m.nu = 0.25;
    return m;
}

// Cube [-L/2, L/2]^3 (m x m squares per face) under pure Neumann uniaxial load along z:
// traction +-load on z_max / z_min (load > 0: tension), traction-free sides.
inline std::shared_ptr<const bem::BemSolution> solve_uniaxial(const SurfaceMesh& cube, double load,
                                                              const SurfaceMesh* cracks = nullptr) {
    bem::AssemblyOptions opt;
    opt.single_layer = false;  // pure Neumann: V is not needed
    const auto ops = bem::assemble_surface_operators(cube, test_material(), opt);
    const bem::ResolvedConditions bc =
        bem::resolve(bem::parse_boundary_conditions("z_max: traction 0 0 " + std::to_string(load) + "; z_min: traction 0 0 " +
                                                    std::to_string(-load) + "; *: traction 0 0 0"),
                     cube);
    std::shared_ptr<const bem::CrackOperators> crack_ops;
    if (cracks && cracks->num_triangles() > 0) crack_ops = bem::append_crack_elements(*ops, nullptr, *cracks);
    return bem::solve_sgbem(ops, crack_ops, bc, {}, nullptr);
}

inline ScalarField strength_field(double S, double fc) {
    return make_field(std::make_shared<HomogeneousField>(S), FieldQuantity::strength, fc);
}

// Exact signed distance of the axis-aligned cube [-h, h]^3 (negative inside).
inline double box_distance(const Vec3& p, double h) {
    const Vec3 q = p.cwiseAbs() - Vec3::Constant(h);
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace cf::initiate::testing
