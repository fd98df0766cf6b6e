#include "nodes/rigid/contact_duration.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cf::rigid {

ContactDuration hertz_contact_duration(const ContactBody& a, const ContactBody& b, double v, const ContactDurationLimits& lim) {
    for (const ContactBody* c : {&a, &b}) {
        if (!(c->E > 0)) throw std::invalid_argument("contact body: Young's modulus must be positive [Pa]");
        if (!(c->nu >= 0 && c->nu < 0.5)) throw std::invalid_argument("contact body: Poisson's ratio must lie in [0, 0.5)");
        if (c->mass < 0) throw std::invalid_argument("contact body: mass must not be negative [kg] (0: static)");
    }
    if (a.mass == 0 && b.mass == 0) throw std::invalid_argument("a contact between two static bodies has no duration");
    ContactDuration d;
    d.E = 1 / ((1 - a.nu * a.nu) / a.E + (1 - b.nu * b.nu) / b.E);
    d.m = 1 / ((a.mass > 0 ? 1 / a.mass : 0.0) + (b.mass > 0 ? 1 / b.mass : 0.0));
    const double curvature = std::abs(a.mean_curvature) + std::abs(b.mean_curvature);
    d.R = curvature > 1 / lim.max_radius ? 1 / curvature : lim.max_radius;
    d.radius_capped = !(curvature > 1 / lim.max_radius);
    d.v = std::abs(v) > lim.min_speed ? std::abs(v) : lim.min_speed;
    d.speed_raised = !(std::abs(v) > lim.min_speed);
    d.seconds = 2.87 * std::pow(d.m * d.m / (d.E * d.E * d.R * d.v), 0.2);
    return d;
}

std::vector<double> vertex_mean_curvature(const SurfaceMesh& mesh) {
    const std::size_t n = mesh.num_vertices();
    std::vector<Vec3> laplace(n, Vec3::Zero());
    std::vector<double> area(n, 0.0);
    for (const Tri& t : mesh.triangles) {
        const Vec3 p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        const double A = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
        if (!(A > 0)) continue;
        double cot[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
            cot[k] = u.dot(w) / u.cross(w).norm();  // cotangent of the angle at corner k
        }
        const bool obtuse = cot[0] < 0 || cot[1] < 0 || cot[2] < 0;
        for (int k = 0; k < 3; ++k) {
            const int i = t[k], j = t[(k + 1) % 3];
            // Edge (i, j) is opposite corner l: weight cot(l) / 2 (cotangent Laplacian).
            const Vec3 e = mesh.vertices[j] - mesh.vertices[i];
            laplace[i] += 0.5 * cot[(k + 2) % 3] * e;
            laplace[j] -= 0.5 * cot[(k + 2) % 3] * e;
            // Mixed Voronoi area of corner k (Meyer et al.): Voronoi for non-obtuse triangles.
            if (!obtuse) {
                const Vec3 a = mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[i], b = mesh.vertices[t[(k + 2) % 3]] - mesh.vertices[i];
                area[i] += (a.squaredNorm() * cot[(k + 2) % 3] + b.squaredNorm() * cot[(k + 1) % 3]) / 8;
            } else {
                area[i] += cot[k] < 0 ? A / 2 : A / 4;
            }
        }
    }
    std::vector<double> H(n, 0.0);
    for (std::size_t v = 0; v < n; ++v)
        if (area[v] > 0) H[v] = laplace[v].norm() / (2 * area[v]);
    return H;
}

std::vector<double> triangle_mean_curvature(const SurfaceMesh& mesh) {
    const std::vector<double> Hv = vertex_mean_curvature(mesh);
    std::vector<double> out(mesh.num_triangles());
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t)
        out[t] = (Hv[mesh.triangles[t][0]] + Hv[mesh.triangles[t][1]] + Hv[mesh.triangles[t][2]]) / 3;
    return out;
}

}  // namespace cf::rigid
