#include "nodes/initiate/surface_stress.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace cf::initiate {

namespace {

// 2D coordinates of a triangle in its own frame: a -> (0,0), b -> (e1, 0), c -> (e2, e3).
struct Planar {
    double e1, e2, e3;
};

Planar planar_coordinates(const Vec3& a, const Vec3& b, const Vec3& c) {
    Planar p;
    const Vec3 ab = b - a, ac = c - a;
    p.e1 = ab.norm();
    p.e2 = ac.dot(ab) / p.e1;
    p.e3 = (ac - ab * (p.e2 / p.e1)).norm();
    return p;
}

}  // namespace

Mat3 surface_stress(const std::array<Vec3, 3>& x, const std::array<Vec3, 3>& u, const Vec3& q, double E, double nu) {
    const Vec3 cross = (x[1] - x[0]).cross(x[2] - x[0]);
    const double two_area = cross.norm();
    const double scale = std::max({(x[1] - x[0]).norm(), (x[2] - x[0]).norm(), (x[2] - x[1]).norm()});
    if (!(two_area > 1e-12 * scale * scale)) throw std::invalid_argument("surface stress: degenerate triangle");
    const Vec3 n1 = cross / two_area;
    const Vec3 n2 = (x[1] - x[0]).normalized();
    const Vec3 n3 = n1.cross(n2);

    // Rest and deformed 2D coordinates; the deformed triangle is mapped by its own frame, so a
    // rigid rotation of the element produces no stress.
    const Planar e = planar_coordinates(x[0], x[1], x[2]);
    const Planar f = planar_coordinates(x[0] + u[0], x[1] + u[1], x[2] + u[2]);
    // u2d = deformed - rest (the thesis writes rest - deformed with B_e of the opposite sign).
    Eigen::Matrix<double, 6, 1> u2d;
    u2d << 0, 0, f.e1 - e.e1, 0, f.e2 - e.e2, f.e3 - e.e3;
    Eigen::Matrix<double, 3, 6> B;  // derivatives of the linear shape functions, eq. (4.5)
    B << -e.e3, 0, e.e3, 0, 0, 0,                       //
        0, e.e2 - e.e1, 0, -e.e2, 0, e.e1,              //
        e.e2 - e.e1, -e.e3, -e.e2, e.e3, e.e1, 0;
    B /= two_area;
    // Eq. (4.4) with the plane-stress Lame constant lambda* = E nu / (1 - nu^2): lambda* + 2 mu
    // = E / (1 - nu^2) = E*, the modulus of the text's Poisson-correction derivation. (The 3D
    // lambda would leave sigma_zz = E eps_zz (1-nu-nu^2)/((1+nu)(1-2nu)) on the side of a bar in
    // tension, 17 % off for nu = 0.3.)
    const double mu = E / (2 * (1 + nu));
    const double lam = E * nu / (1 - nu * nu);
    Eigen::Matrix3d S;
    S << lam + 2 * mu, lam, 0, lam, lam + 2 * mu, 0, 0, 0, mu;
    const Eigen::Vector3d s = S * (B * u2d);  // (sigma_ab, sigma_perp, tau)
    Eigen::Matrix2d s2;
    s2 << s[0], s[2], s[2], s[1];

    Eigen::Matrix<double, 3, 2> N23;
    N23.col(0) = n2;
    N23.col(1) = n3;
    const Eigen::Matrix<double, 3, 2> qstar = N23 * s2;  // (q2*, q3*)
    const double poisson = q.dot(n1) * nu / (1 - nu);
    const Vec3 q2 = qstar.col(0) + n1 * q.dot(n2) + n2 * poisson;
    const Vec3 q3 = qstar.col(1) + n1 * q.dot(n3) + n3 * poisson;
    return q * n1.transpose() + q2 * n2.transpose() + q3 * n3.transpose();  // eq. (4.6)
}

PrincipalStress principal_stresses(const Mat3& sigma) {
    Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (sigma + sigma.transpose()));
    PrincipalStress p;
    p.values = es.eigenvalues();  // ascending
    p.directions = es.eigenvectors();
    return p;
}

}  // namespace cf::initiate
