#include "nodes/initiate/initiation.hpp"

#include "graph/cancel_token.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cf::initiate {

namespace {

double segment_distance(const Vec3& p, const Segment& s) {
    const Vec3 d = s[1] - s[0];
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - s[0]).dot(d) / len2, 0.0, 1.0) : 0.0;
    return (p - (s[0] + t * d)).norm();
}

double distance_to_fronts(const Vec3& p, const std::vector<Segment>& segments) {
    double d = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments) d = std::min(d, segment_distance(p, s));
    return d;
}

}  // namespace

std::vector<Initiation> select_initiations(const std::vector<ElementStress>& elements, const ScalarField& strength,
                                           const std::vector<char>& initiated, const std::vector<Segment>& front_segments,
                                           const InitiationSettings& s, const CandidateCheck& admissible,
                                           SelectionCounts* counts) {
    if (!initiated.empty() && initiated.size() != elements.size())
        throw std::invalid_argument("crack initiation: " + std::to_string(initiated.size()) +
                                    " 'initiated' flags for " + std::to_string(elements.size()) + " elements");
    if (!(s.r_c > 0)) throw std::invalid_argument("crack initiation: r_c must be > 0 [m]");
    const int budget = s.max_cracks - s.existing_cracks;
    std::vector<Initiation> out;
    SelectionCounts local;
    SelectionCounts& n = counts ? *counts : local;
    n = SelectionCounts{};

    // Polled every 4096 elements and per candidate (a pass over the fronts and the admissibility
    // check's passes over the surface and crack triangles).
    const CancelToken cancel = CancelToken::current();
    std::vector<Initiation> candidates;
    for (std::size_t e = 0; e < elements.size(); ++e) {
        if ((e & 4095u) == 0) cancel.poll();
        if (!initiated.empty() && initiated[e]) continue;  // (b)
        const ElementStress& el = elements[e];
        const PrincipalStress p = principal_stresses(el.sigma);
        const double S = strength.value(el.centroid);  // strength at the centroid
        const double tensile = p.max() - S;
        const double compressive = -p.min() - strength.compressive_factor * S;
        if (tensile <= 0 && compressive <= 0) continue;  // (a)
        Initiation c;
        c.element = static_cast<int>(e);
        c.compressive = compressive > tensile;
        c.excess = c.compressive ? compressive : tensile;
        c.principal = c.compressive ? p.min() : p.max();
        c.plane_normal = c.compressive ? p.min_direction() : p.max_direction();
        c.centre = initial_crack_centre(el.centroid, el.normal, c.plane_normal, s.r_c);
        candidates.push_back(c);
    }
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](const Initiation& a, const Initiation& b) { return a.excess > b.excess; });

    n.over_strength = static_cast<int>(candidates.size());

    std::vector<Segment> fronts = front_segments;
    for (const Initiation& c : candidates) {
        cancel.poll();
        if (distance_to_fronts(elements[c.element].centroid, fronts) <= s.r_c) {  // (c)
            ++n.skipped_near_front;
            continue;
        }
        if (static_cast<int>(out.size()) >= budget) {  // (d): counted, so a run can say what max_cracks held back
            ++n.over_budget;
            continue;
        }
        if (admissible && !admissible(c)) {
            ++n.rejected;
            continue;
        }
        out.push_back(c);
        const auto hex = hexagon_front(hexagon_crack(c.centre, c.plane_normal, s.r_c, "new"));
        fronts.insert(fronts.end(), hex.begin(), hex.end());
    }
    return out;
}

Vec3 initial_crack_centre(const Vec3& centroid, const Vec3& n, const Vec3& p, double r_c) {
    const double R = 0.2 * r_c;
    const double reach = (n - n.dot(p) * p).norm();  // extent of a unit disk normal to p along n
    return centroid - n * (R * (reach + 0.25));
}

SurfaceMesh hexagon_crack(const Vec3& centre, const Vec3& plane_normal, double r_c, const std::string& name) {
    const Vec3 nrm = plane_normal.normalized();
    // Any unit vector orthogonal to the normal starts the rim.
    const Vec3 helper = std::abs(nrm.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 t1 = (helper - helper.dot(nrm) * nrm).normalized();
    const Vec3 t2 = nrm.cross(t1);
    const double R = 0.2 * r_c;
    SurfaceMesh m;
    m.vertices.push_back(centre);
    for (int k = 0; k < 6; ++k) {
        const double a = k * M_PI / 3;
        m.vertices.push_back(centre + R * (std::cos(a) * t1 + std::sin(a) * t2));
    }
    for (int k = 0; k < 6; ++k) m.triangles.push_back({0, 1 + k, 1 + (k + 1) % 6});  // (t1 x t2) = n: CCW about n
    m.region.assign(6, 0);
    m.region_names = {name};
    return m;
}

std::vector<Segment> hexagon_front(const SurfaceMesh& h) {
    std::vector<Segment> s;
    for (int k = 0; k < 6; ++k) s.push_back({h.vertices[1 + k], h.vertices[1 + (k + 1) % 6]});
    return s;
}

int append_crack_sheet(SurfaceMesh& cracks, const SurfaceMesh& sheet) {
    const int region = cracks.triangles.empty() ? 0 : cracks.num_regions();
    const int offset = static_cast<int>(cracks.vertices.size());
    if (cracks.region.size() != cracks.triangles.size()) cracks.region.assign(cracks.triangles.size(), 0);
    std::vector<std::string> names;
    for (int r = 0; r < region; ++r) names.push_back(cracks.region_name(r));
    names.push_back(sheet.region_names.empty() ? "crack" + std::to_string(region) : sheet.region_names[0]);
    cracks.region_names = names;
    cracks.vertices.insert(cracks.vertices.end(), sheet.vertices.begin(), sheet.vertices.end());
    for (const Tri& t : sheet.triangles) {
        cracks.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
        cracks.region.push_back(region);
    }
    return region;
}

}  // namespace cf::initiate
