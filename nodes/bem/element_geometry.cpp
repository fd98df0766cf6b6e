#include "nodes/bem/element_geometry.hpp"

#include "graph/diagnostics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace cf::bem {

ElementGeometry element_geometry(const SurfaceMesh& mesh, std::size_t t) {
    ElementGeometry g;
    g.nodes = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
        const int v = g.nodes[k];
        if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertices.size())
            throw std::invalid_argument("triangle " + std::to_string(t) + " references vertex " + std::to_string(v) +
                                        " but the mesh has " + std::to_string(mesh.vertices.size()) + " vertices");
        g.p[k] = mesh.vertices[v];
    }
    const Vec3 e1 = g.p[1] - g.p[0], e2 = g.p[2] - g.p[0];
    const Vec3 cr = e1.cross(e2);
    g.diameter = std::max({e1.norm(), e2.norm(), (g.p[2] - g.p[1]).norm()});
    g.area = 0.5 * cr.norm();
    if (!(g.area > 1e-12 * g.diameter * g.diameter))
        throw std::invalid_argument("triangle " + std::to_string(t) + " is degenerate (area " + graph::format_number(g.area) +
                                    " m^2, longest edge " + graph::format_number(g.diameter) +
                                    " m); remove or remesh it");
    g.normal = cr / (2 * g.area);
    g.centroid = (g.p[0] + g.p[1] + g.p[2]) / 3;
    // G = J (J^T J)^-1: its columns are grad s and grad t.
    Eigen::Matrix<double, 3, 2> J;
    J.col(0) = e1;
    J.col(1) = e2;
    const Eigen::Matrix<double, 3, 2> G = J * (J.transpose() * J).inverse();
    g.grad[1] = G.col(0);
    g.grad[2] = G.col(1);
    g.grad[0] = -g.grad[1] - g.grad[2];
    for (int k = 0; k < 3; ++k) {
        g.curl[k] = g.normal.cross(g.grad[k]);
        g.M[k] = g.grad[k] * g.normal.transpose() - g.normal * g.grad[k].transpose();
    }
    return g;
}

std::vector<ElementGeometry> element_geometries(const SurfaceMesh& mesh, const char* what) {
    std::vector<ElementGeometry> out;
    out.reserve(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        try {
            out.push_back(element_geometry(mesh, t));
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string(what) + ": " + e.what());
        }
    }
    return out;
}

}  // namespace cf::bem
