#include "nodes/initiate/initiate_verification.hpp"

#include "nodes/initiate/surface_stress.hpp"
#include "nodes/registration.hpp"

#include <cmath>
#include <sstream>

namespace cf::initiate {

SurfaceMesh verification_cube(int m, double L) {
    SurfaceMesh mesh;
    // Each face: origin corner o, in-plane axes a, b with a x b = outward normal.
    struct Face {
        Vec3 o, a, b;
    };
    const double h = L / 2;
    const Face faces[6] = {{Vec3(-h, -h, -h), Vec3(0, 0, L), Vec3(0, L, 0)},   // x = -h
                           {Vec3(h, -h, -h), Vec3(0, L, 0), Vec3(0, 0, L)},    // x = +h
                           {Vec3(-h, -h, -h), Vec3(L, 0, 0), Vec3(0, 0, L)},   // y = -h
                           {Vec3(-h, h, -h), Vec3(0, 0, L), Vec3(L, 0, 0)},    // y = +h
                           {Vec3(-h, -h, -h), Vec3(0, L, 0), Vec3(L, 0, 0)},   // z = -h
                           {Vec3(-h, -h, h), Vec3(L, 0, 0), Vec3(0, L, 0)}};   // z = +h
    for (int f = 0; f < 6; ++f) {
        const int base = static_cast<int>(mesh.vertices.size());
        for (int i = 0; i <= m; ++i)
            for (int j = 0; j <= m; ++j) mesh.vertices.push_back(faces[f].o + faces[f].a * (double(i) / m) + faces[f].b * (double(j) / m));
        auto id = [&](int i, int j) { return base + i * (m + 1) + j; };
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < m; ++j) {
                mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
                mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
                mesh.region.push_back(f);
                mesh.region.push_back(f);
            }
    }
    mesh.region_names = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    return mesh;
}

double uniaxial_surface_stress_error(int m, double L, double sigma, double E, double nu, bool side) {
    const SurfaceMesh mesh = verification_cube(m, L);
    auto u = [&](const Vec3& x) -> Vec3 { return Vec3(-nu * x.x(), -nu * x.y(), x.z()) * (sigma / E); };
    Mat3 exact = Mat3::Zero();
    exact(2, 2) = sigma;
    double err = 0;
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const Vec3 n = triangle_normal(mesh, t);
        if ((std::abs(n.z()) < 0.5) != side) continue;
        const Tri& tri = mesh.triangles[t];
        const std::array<Vec3, 3> x = {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
        const Mat3 s = surface_stress(x, {u(x[0]), u(x[1]), u(x[2])}, exact * n, E, nu);
        err = std::max(err, (s - exact).norm() / sigma);
    }
    return err;
}

}  // namespace cf::initiate

namespace cf {

namespace {

VerificationResult surface_stress_uniaxial() {
    // PMMA (thesis-cases.yaml), 1 MPa tension on a 0.1 m cube, 4 x 4 squares per face (192 triangles).
    const double E = 3.1e9, nu = 0.327, sigma = 1e6, L = 0.1;
    const double side = initiate::uniaxial_surface_stress_error(4, L, sigma, E, nu, true);
    const double ends = initiate::uniaxial_surface_stress_error(4, L, sigma, E, nu, false);
    VerificationResult r;
    r.error = std::max(side, ends);
    r.tolerance = 0.01;
    r.passed = r.error <= r.tolerance;
    std::ostringstream os;
    os << "cube 192 triangles, u = (sigma/E)(-nu x, -nu y, z): max |sigma_e - sigma e_z e_z^T|_F / sigma = " << side
       << " on side faces, " << ends << " on top/bottom faces";
    r.details = os.str();
    return r;
}

}  // namespace

void add_initiate_verification_cases(std::vector<VerificationCase>& cases) {
    cases.push_back({"surface_stress_uniaxial", "case 4: surface stress eq. (4.6) of the uniaxial cube within 1 %",
                     surface_stress_uniaxial});
}

}  // namespace cf
