#include "nodes/propagate/opening_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace cf::propagate {

namespace {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
}

}  // namespace

Vec3 opening_from_sifs(const Sifs& K, const FrontFrame& f, double d, double E, double nu) {
    const double mu = E / (2 * (1 + nu));
    const double c = 4 * std::sqrt(std::max(d, 0.0)) / (mu * std::sqrt(2 * M_PI));
    return c * ((1 - nu) * K.KI * f.n1 + (1 - nu) * K.KII * f.n2 + K.KIII * f.n3);
}

std::size_t estimate_openings_left_behind(const SurfaceMesh& cracks, const CrackFront& old_front, const CrackFront& new_front,
                                          double E, double nu, bem::CrackOpeningEstimate& est) {
    est.opening.resize(cracks.num_vertices(), Vec3::Zero());
    est.known.resize(cracks.num_vertices(), 0);
    if (old_front.sifs.size() != old_front.nodes.size() || old_front.frames.size() != old_front.nodes.size()) return 0;
    const std::set<int> still(new_front.nodes.begin(), new_front.nodes.end());
    std::size_t set = 0;
    const std::size_t n = new_front.nodes.size();
    for (std::size_t i = 0; i < old_front.nodes.size(); ++i) {
        const int v = old_front.nodes[i];
        if (still.count(v) || est.known[v]) continue;
        const Vec3& p = cracks.vertices[v];
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < new_front.num_edges(); ++k)
            d = std::min(d, distance_to_segment(p, cracks.vertices[new_front.nodes[k]], cracks.vertices[new_front.nodes[(k + 1) % n]]));
        if (n == 1) d = (p - cracks.vertices[new_front.nodes[0]]).norm();
        if (!std::isfinite(d)) continue;
        est.opening[v] = opening_from_sifs(old_front.sifs[i], old_front.frames[i], d, E, nu);
        est.known[v] = 1;
        ++set;
    }
    return set;
}

}  // namespace cf::propagate
