#include "nodes/rigid/balanced_tractions.hpp"

#include <Eigen/Cholesky>

#include <stdexcept>
#include <string>

namespace cf::rigid {

namespace {

struct Element {
    double area;
    Vec3 arm;  // centroid minus the mesh's area centroid
};

std::vector<Element> elements(const SurfaceMesh& mesh) {
    std::vector<Element> e(mesh.num_triangles());
    double A = 0;
    Vec3 c = Vec3::Zero();
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const Tri& tr = mesh.triangles[t];
        const Vec3 a = mesh.vertices[tr[0]], b = mesh.vertices[tr[1]], d = mesh.vertices[tr[2]];
        e[t].area = 0.5 * (b - a).cross(d - a).norm();
        e[t].arm = (a + b + d) / 3;
        A += e[t].area;
        c += e[t].area * e[t].arm;
    }
    if (!(A > 0)) throw std::invalid_argument("balanced tractions: the mesh has no area");
    c /= A;
    for (Element& x : e) x.arm -= c;
    return e;
}

// Cross-product matrix [r]_x, so [r]_x q = r x q.
Mat3 cross_matrix(const Vec3& r) {
    Mat3 m;
    m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    return m;
}

}  // namespace

void traction_resultants(const SurfaceMesh& mesh, const std::vector<Vec3>& q, Vec3& force, Vec3& torque) {
    if (q.size() != mesh.num_triangles())
        throw std::invalid_argument("balanced tractions: " + std::to_string(q.size()) + " tractions for " +
                                    std::to_string(mesh.num_triangles()) + " triangles");
    const auto e = elements(mesh);
    force.setZero();
    torque.setZero();
    for (std::size_t t = 0; t < e.size(); ++t) {
        force += e[t].area * q[t];
        torque += e[t].area * e[t].arm.cross(q[t]);
    }
}

BalancedTractions balance_tractions(const SurfaceMesh& mesh, const std::vector<Vec3>& q, bool area_weighted) {
    BalancedTractions out;
    traction_resultants(mesh, q, out.removed_force, out.removed_torque);
    const auto e = elements(mesh);
    // S_e = [A_e I; A_e [r_e]_x] (6 x 3), S W^-1 S^T = sum S_e S_e^T / w_e, w_e = 1 or A_e.
    Eigen::Matrix<double, 6, 6> SS = Eigen::Matrix<double, 6, 6>::Zero();
    for (const Element& x : e) {
        Eigen::Matrix<double, 6, 3> Se;
        Se.topRows<3>() = x.area * Mat3::Identity();
        Se.bottomRows<3>() = x.area * cross_matrix(x.arm);
        SS += Se * Se.transpose() / (area_weighted ? x.area : 1.0);
    }
    Eigen::Matrix<double, 6, 1> b;
    b << out.removed_force, out.removed_torque;
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(SS);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * ldlt.vectorD().maxCoeff()))
        throw std::invalid_argument("balanced tractions: the surface cannot carry a torque about every axis (degenerate mesh)");
    const Eigen::Matrix<double, 6, 1> v = ldlt.solve(b);
    out.traction.resize(q.size());
    for (std::size_t t = 0; t < e.size(); ++t) {
        // q_c,e = S_e^T v / w_e
        const Vec3 qc = (e[t].area * v.head<3>() + e[t].area * cross_matrix(e[t].arm).transpose() * v.tail<3>()) /
                        (area_weighted ? e[t].area : 1.0);
        out.traction[t] = q[t] - qc;
    }
    return out;
}

}  // namespace cf::rigid
