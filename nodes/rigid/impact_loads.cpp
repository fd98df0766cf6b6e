#include "nodes/rigid/impact_loads.hpp"

#include "nodes/domain/triangle_closest_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace cf::rigid {

int closest_triangle(const SurfaceMesh& mesh, const Vec3& p) {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
        const Tri& tri = mesh.triangles[t];
        const Vec3 q = closest_point_on_triangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]).point;
        const double d2 = (q - p).squaredNorm();
        if (d2 < best_d2) {  // strict: the lowest index wins ties (deterministic)
            best_d2 = d2;
            best = static_cast<int>(t);
        }
    }
    return best;
}

ImpactLoads impact_loads(const SurfaceMesh& mesh, const std::vector<double>& curvature, const ContactBody& body,
                         const std::vector<BodyContact>& contacts, double rigid_step, const ContactDurationLimits& limits) {
    if (curvature.size() != mesh.num_triangles())
        throw std::invalid_argument("impact loads: " + std::to_string(curvature.size()) + " curvatures for " +
                                    std::to_string(mesh.num_triangles()) + " BEM triangles");
    if (!(rigid_step > 0)) throw std::invalid_argument("impact loads: the rigid step must be positive [s]");
    ImpactLoads out;
    out.traction.assign(mesh.num_triangles(), Vec3::Zero());
    out.shortest_duration = std::numeric_limits<double>::infinity();
    for (const BodyContact& c : contacts) {
        if (!c.point.allFinite() || !c.direction.allFinite() || !std::isfinite(c.impulse) || !(c.impulse >= 0))
            throw std::invalid_argument("impact loads: a contact with a non-finite point, direction or impulse");
        if (c.impulse == 0) continue;
        const int e = closest_triangle(mesh, c.point);
        ContactBody self = body;
        self.mean_curvature = curvature[static_cast<std::size_t>(e)];
        const ContactDuration tc = hertz_contact_duration(self, c.partner, c.approach_speed, limits);
        const double duration = std::min(tc.seconds, rigid_step);
        const double area = triangle_area(mesh, static_cast<std::size_t>(e));
        out.traction[static_cast<std::size_t>(e)] += c.impulse / (duration * area) * c.direction.normalized();
        out.impulse += c.impulse;
        out.force += c.impulse / duration;
        out.contact_duration = std::max(out.contact_duration, duration);
        out.shortest_duration = std::min(out.shortest_duration, duration);
        ++out.contacts;
    }
    if (out.contacts == 0) out.shortest_duration = 0;
    return out;
}

}  // namespace cf::rigid
