#include "nodes/rigid/mass_properties.hpp"

#include "graph/diagnostics.hpp"

#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <string>

namespace cf::rigid {

MassProperties mass_properties(const SurfaceMesh& mesh, double density) {
    if (!(density > 0)) throw std::invalid_argument("density must be positive [kg/m^3], got " + graph::format_quantity(density, "kg/m^3"));
    if (mesh.triangles.empty()) throw std::invalid_argument("the body mesh has no triangles");
    // Reference point inside the vertex cloud keeps the tetrahedra small (no cancellation of large terms).
    Vec3 p = Vec3::Zero();
    for (const Vec3& v : mesh.vertices) p += v;
    p /= static_cast<double>(mesh.vertices.size());
    double V = 0;
    Vec3 first = Vec3::Zero();
    Mat3 second = Mat3::Zero();
    for (const Tri& t : mesh.triangles) {
        const Vec3 a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p, c = mesh.vertices[t[2]] - p;
        const double vt = a.dot(b.cross(c)) / 6;
        const Vec3 s = a + b + c;
        V += vt;
        first += vt * s / 4;
        second += vt / 20 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
    if (!(V > 0))
        throw std::invalid_argument("the body mesh encloses a non-positive volume (" + graph::format_number(V) +
                                    " m^3): it must be closed and face outward");
    MassProperties m;
    m.volume = V;
    m.mass = density * V;
    const Vec3 g = first / V;  // centre relative to p
    m.centre = p + g;
    const Mat3 C = second - V * g * g.transpose();  // second moment about the centre
    m.inertia = density * (C.trace() * Mat3::Identity() - C);
    const Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (m.inertia + m.inertia.transpose()));
    m.principal_moments = es.eigenvalues();
    m.principal_axes = es.eigenvectors();
    if (m.principal_axes.determinant() < 0) m.principal_axes.col(2) *= -1;
    return m;
}

}  // namespace cf::rigid
