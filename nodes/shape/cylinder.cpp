#include "nodes/shape/cylinder.hpp"

#include "graph/diagnostics.hpp"

#include <cmath>
#include <stdexcept>

namespace cf {
namespace {

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

}  // namespace

SurfaceMesh make_cylinder(const CylinderSpec& spec) {
    require(spec.radius > 0, "parameter 'radius' must be > 0 m, got " + graph::format_quantity(spec.radius, "m"));
    require(spec.height > 0, "parameter 'height' must be > 0 m, got " + graph::format_quantity(spec.height, "m"));
    require(spec.segments >= 3, "parameter 'segments' must be >= 3, got " + std::to_string(spec.segments));
    require(spec.rings >= 1, "parameter 'rings' must be >= 1, got " + std::to_string(spec.rings));
    require(spec.cap_rings >= 1, "parameter 'cap_rings' must be >= 1, got " + std::to_string(spec.cap_rings));

    const int bands = spec.caps == CapStyle::Fan ? 1 : spec.cap_rings;
    const double triangles = 2.0 * spec.segments * spec.rings + 2.0 * spec.segments * (2.0 * bands - 1);
    require(triangles <= 4e6, "segments, rings and cap_rings would make " + std::to_string(static_cast<long long>(triangles)) +
                                  " triangles (limit 4000000); reduce them");

    enum { side = 0, top = 1, bottom = 2 };
    const int s = spec.segments;
    const double pi = std::acos(-1.0);
    SurfaceMesh m;
    m.region_names = {"side", "top", "bottom"};
    auto add = [&m](int a, int b, int c, int region) {
        m.triangles.push_back({a, b, c});
        m.region.push_back(region);
    };
    // A ring of s vertices at radius rho and height z (relative to the centre); returns its first index.
    auto ring = [&](double rho, double z) {
        const int first = static_cast<int>(m.vertices.size());
        for (int i = 0; i < s; ++i) {
            const double phi = 2 * pi * i / s;
            m.vertices.push_back(spec.centre + Vec3(rho * std::cos(phi), rho * std::sin(phi), z));
        }
        return first;
    };

    // Side: rings+1 rims from bottom to top. Walking +phi then +z faces outward (e_phi x e_z = e_r).
    std::vector<int> rim(spec.rings + 1);
    for (int k = 0; k <= spec.rings; ++k)
        rim[k] = ring(spec.radius, k == spec.rings ? 0.5 * spec.height : spec.height * (double(k) / spec.rings - 0.5));
    for (int k = 0; k < spec.rings; ++k)
        for (int i = 0; i < s; ++i) {
            const int j = (i + 1) % s;
            const int a = rim[k] + i, b = rim[k] + j, c = rim[k + 1] + j, d = rim[k + 1] + i;
            add(a, b, c, side);
            add(a, c, d, side);
        }

    // Caps. Walking +r then +phi faces +z (e_r x e_phi = e_z): keep that winding on top, flip below.
    auto cap = [&](int outer_rim, double z, int region) {
        const bool up = region == top;
        auto face = [&](int a, int b, int c) { up ? add(a, b, c, region) : add(a, c, b, region); };
        int outer = outer_rim;
        for (int band = bands - 1; band >= 1; --band) {  // from the rim inwards
            const int inner = ring(spec.radius * band / bands, z);
            for (int i = 0; i < s; ++i) {
                const int j = (i + 1) % s;
                face(inner + i, outer + i, outer + j);
                face(inner + i, outer + j, inner + j);
            }
            outer = inner;
        }
        const int centre = static_cast<int>(m.vertices.size());
        m.vertices.push_back(spec.centre + Vec3(0, 0, z));
        for (int i = 0; i < s; ++i) face(centre, outer + i, outer + (i + 1) % s);
    };
    cap(rim[spec.rings], 0.5 * spec.height, top);
    cap(rim[0], -0.5 * spec.height, bottom);
    return m;
}

}  // namespace cf
