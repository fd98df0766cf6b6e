#pragma once
// Shared set-up of the deformed-fragment tests (ch. 6.4): a unit cube [-0.5, 0.5]^3 at r_f = 0.02 m,
// a general linear displacement field u = A x + b, and a BEM solution holding its exact P1/P0 data
// on the cube plus a planar crack sheet at z = z0 with a uniform opening.
#include "nodes/bem/solver.hpp"
#include "nodes/bem/test_meshes.hpp"
#include "nodes/levelset/level_set.hpp"
#include "tests/levelset/test_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace cf::displacement_fixture {

inline constexpr double kRf = 0.02;   // voxel size [m] for the unit cube
inline constexpr double kZ0 = 0.031;  // crack plane, off the voxel lattice [m]
inline const double kH = std::sqrt(3.0) * kRf / 2;  // crack half thickness
// Dual-contouring vertices (one per voxel) on one cut face inside |x|, |y| < 0.5 - 3 r_f: at
// least (0.88 m / r_f - 1)^2.
inline constexpr std::size_t kFaceVertices = 43 * 43;

// A general linear field (rotation + strain) u = A x + b [m].
inline Eigen::Matrix3d field_A() {
    Eigen::Matrix3d A;
    A << 1.0, 0.4, -0.3, 0.2, -0.5, 0.6, -0.7, 0.1, 0.8;
    return 1e-3 * A;
}
inline const Vec3 kB = 1e-3 * Vec3(0.5, -0.2, 0.3);
inline Vec3 field(const Vec3& x) { return field_A() * x + kB; }

// Candidate closest points of x on the cube [-0.5, 0.5]^3 surface: the unique clamp outside, the
// nearest face(s) inside (every face within 1e-12 m of the minimum: ties are ambiguous).
inline std::vector<Vec3> closest_on_cube(const Vec3& x, double* distance) {
    const bool in = (x.cwiseAbs().array() <= 0.5).all();
    if (!in) {
        const Vec3 y = x.cwiseMax(Vec3::Constant(-0.5)).cwiseMin(Vec3::Constant(0.5));
        *distance = (x - y).norm();
        return {y};
    }
    double dmin = 1e9;
    for (int a = 0; a < 3; ++a) dmin = std::min(dmin, 0.5 - std::abs(x[a]));
    std::vector<Vec3> ys;
    for (int a = 0; a < 3; ++a)
        if (0.5 - std::abs(x[a]) <= dmin + 1e-12) {
            Vec3 y = x;
            y[a] = x[a] >= 0 ? 0.5 : -0.5;
            ys.push_back(y);
        }
    *distance = dmin;
    return ys;
}

inline LevelSet cube_grid() { return level_set_from_mesh(testmesh::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), kRf); }

// Coarse crack sheet: the square [-0.5, 0.5]^2 at z = z0 in n x n cells, normal +z (- below, + above).
inline SurfaceMesh crack_sheet(int n) {
    SurfaceMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.vertices.emplace_back(-0.5 + double(i) / n, -0.5 + double(j) / n, kZ0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    m.region.assign(m.triangles.size(), 0);
    m.region_names = {"crack"};
    return m;
}

// A BEM solution holding the exact P1/P0 data of u = A x + b on the unit cube (traction sigma n,
// constant strain) plus a crack sheet with a uniform opening; u_c is then evaluated by the
// representation formula (not set by hand).
inline std::shared_ptr<const bem::BemSolution> planar_crack_solution(const Vec3& opening) {
    Material mat;
    mat.E = 1;
    mat.nu = 0.3;
    bem::AssemblyOptions opt;
    opt.single_layer = false;
    auto sol = std::make_shared<bem::BemSolution>();
    sol->surface = bem::assemble_surface_operators(bem::bem_cube_mesh(2, 1.0), mat, opt);
    const Eigen::Matrix3d eps = 0.5 * (field_A() + field_A().transpose());
    const Eigen::Matrix3d sigma = mat.lambda() * eps.trace() * Eigen::Matrix3d::Identity() + 2 * mat.mu() * eps;
    for (const Vec3& x : sol->surface->mesh.vertices) sol->displacement.push_back(field(x));
    for (const auto& g : sol->surface->geometry) sol->traction.push_back(sigma * g.normal);
    auto cr = std::make_shared<bem::CrackOperators>();
    cr->cracks = crack_sheet(4);
    sol->cracks = cr;
    sol->crack_opening.assign(cr->cracks.num_vertices(), opening);
    return sol;
}

}  // namespace cf::displacement_fixture
