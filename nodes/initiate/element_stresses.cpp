#include "nodes/initiate/element_stresses.hpp"

#include <stdexcept>
#include <string>

namespace cf::initiate {

double youngs_modulus(const bem::ElasticConstants& c) { return 2 * c.mu * (1 + c.nu); }

std::vector<ElementStress> surface_element_stresses(const bem::BemSolution& sol) {
    if (!sol.surface) throw std::invalid_argument("surface stress: the BEM solution has no surface operators");
    const SurfaceMesh& m = sol.surface->mesh;
    if (sol.displacement.size() != m.num_vertices() || sol.traction.size() != m.num_triangles())
        throw std::invalid_argument("surface stress: the BEM solution has " + std::to_string(sol.displacement.size()) +
                                    " nodal displacements and " + std::to_string(sol.traction.size()) +
                                    " element tractions for a surface of " + std::to_string(m.num_vertices()) +
                                    " vertices and " + std::to_string(m.num_triangles()) + " triangles");
    const double E = youngs_modulus(sol.surface->elastic), nu = sol.surface->elastic.nu;
    std::vector<ElementStress> out(m.num_triangles());
    for (std::size_t e = 0; e < m.num_triangles(); ++e) {
        const Tri& t = m.triangles[e];
        const std::array<Vec3, 3> x{m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
        const std::array<Vec3, 3> u{sol.displacement[t[0]], sol.displacement[t[1]], sol.displacement[t[2]]};
        out[e].sigma = surface_stress(x, u, sol.traction[e], E, nu);  // eq. (4.6)
        out[e].centroid = triangle_centroid(m, e);
        out[e].normal = triangle_normal(m, e);
    }
    return out;
}

std::vector<CrackFaceStress> crack_face_stresses(const bem::BemSolution& sol, const std::vector<Vec3>& uc) {
    if (!sol.surface || !sol.cracks) throw std::invalid_argument("crack face stress: the BEM solution has no crack sheets");
    const SurfaceMesh& m = sol.cracks->cracks;
    if (sol.crack_opening.size() != m.num_vertices() || uc.size() != m.num_vertices())
        throw std::invalid_argument("crack face stress: " + std::to_string(sol.crack_opening.size()) + " openings and " +
                                    std::to_string(uc.size()) + " average displacements for " +
                                    std::to_string(m.num_vertices()) + " crack vertices");
    const double E = youngs_modulus(sol.surface->elastic), nu = sol.surface->elastic.nu;
    const Vec3 free = Vec3::Zero();  // traction-free faces
    std::vector<CrackFaceStress> out(m.num_triangles());
    for (std::size_t e = 0; e < m.num_triangles(); ++e) {
        const Tri& t = m.triangles[e];
        std::array<Vec3, 3> up, um;
        for (int k = 0; k < 3; ++k) {
            up[k] = uc[t[k]] + 0.5 * sol.crack_opening[t[k]];  // u+ = u_c + [u]/2
            um[k] = uc[t[k]] - 0.5 * sol.crack_opening[t[k]];  // u- = u_c - [u]/2
        }
        const Vec3 n = triangle_normal(m, e);
        const Vec3 c = triangle_centroid(m, e);
        // "-" face: outward normal +n, the triangle as it is.
        out[e].minus.sigma = surface_stress({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]}, um, free, E, nu);
        out[e].minus.centroid = c;
        out[e].minus.normal = n;
        // "+" face: outward normal -n, the triangle reversed (corners a, c, b).
        out[e].plus.sigma = surface_stress({m.vertices[t[0]], m.vertices[t[2]], m.vertices[t[1]]}, {up[0], up[2], up[1]},
                                           free, E, nu);
        out[e].plus.centroid = c;
        out[e].plus.normal = -n;
    }
    return out;
}

double strength_excess(const ElementStress& e, const ScalarField& strength) {
    const PrincipalStress p = principal_stresses(e.sigma);
    const double S = strength.value(e.centroid);
    return std::max(p.max() - S, -p.min() - strength.compressive_factor * S);
}

}  // namespace cf::initiate
