#include "nodes/shape/notched_bar.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace cf {
namespace {

constexpr double max_triangles = 4e6;  // refuse before allocating more than this

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

std::string metres(double v) {
    std::ostringstream s;
    s << v << " m";
    return s.str();
}

// Cells per interval so that no cell is longer than the target edge length.
int cells_for(double length, double resolution) {
    return std::max(1, static_cast<int>(std::ceil(length / resolution - 1e-9)));
}

// Grid coordinates through every breakpoint, each interval split uniformly into cells no longer
// than the resolution. Breakpoints closer than `merge` are one.
std::vector<double> graded_nodes(std::vector<double> breaks, double resolution, double merge) {
    std::sort(breaks.begin(), breaks.end());
    std::vector<double> unique;
    for (double b : breaks)
        if (unique.empty() || b - unique.back() > merge) unique.push_back(b);
    std::vector<double> nodes{unique.front()};
    for (std::size_t k = 0; k + 1 < unique.size(); ++k) {
        const double a = unique[k], b = unique[k + 1];
        const int n = cells_for(b - a, resolution);
        for (int i = 1; i < n; ++i) nodes.push_back(a + (b - a) * i / n);
        nodes.push_back(b);
    }
    return nodes;
}

// The bar's cross-section in the (x, z) plane, triangulated; triangles counter-clockwise in (x, z).
struct Profile {
    std::vector<std::array<double, 2>> points;
    std::vector<Tri> triangles;
};

// Builds a profile from lattice cells. A vertex is named by its lattice column i, row k and a
// side (-1, 0, +1) that tells apart the two walls of a V-notch, which share (i, k) below the apex.
class ProfileLattice {
public:
    int vertex(int i, int k, int side, double x, double z) {
        auto [it, inserted] = index_.emplace(std::array<int, 3>{i, k, side}, static_cast<int>(profile_.points.size()));
        if (inserted) profile_.points.push_back({x, z});
        return it->second;
    }
    // Quad a, b, c, e counter-clockwise in (x, z) from the lower left. The diagonal is mirrored
    // about x = 0 so the mesh is as symmetric as the 3-point-bending test.
    void quad(int a, int b, int c, int e, bool left_of_centre) {
        if (left_of_centre) {
            profile_.triangles.push_back({a, b, c});
            profile_.triangles.push_back({a, c, e});
        } else {
            profile_.triangles.push_back({a, b, e});
            profile_.triangles.push_back({b, c, e});
        }
    }
    Profile take() { return std::move(profile_); }

private:
    std::map<std::array<int, 3>, int> index_;
    Profile profile_;
};

void check(const NotchedBarSpec& s) {
    require(s.length > 0, "parameter 'length' must be > 0 m, got " + metres(s.length));
    require(s.height > 0, "parameter 'height' must be > 0 m, got " + metres(s.height));
    require(s.depth > 0, "parameter 'depth' must be > 0 m, got " + metres(s.depth));
    require(s.notch_width > 0 && s.notch_width < s.length,
            "parameter 'notch_width' must be in (0, length = " + metres(s.length) + "), got " + metres(s.notch_width));
    require(s.notch_depth > 0 && s.notch_depth < s.height,
            "parameter 'notch_depth' must be in (0, height = " + metres(s.height) + "), got " + metres(s.notch_depth));
    require(s.strip_width > 0, "parameter 'strip_width' must be > 0 m, got " + metres(s.strip_width));
    require(s.resolution > 0, "parameter 'resolution' must be > 0 m, got " + metres(s.resolution));
    require(0.5 * (s.support_span + s.strip_width) <= 0.5 * s.length,
            "the support strips stick out of the bar: support_span + strip_width = " +
                metres(s.support_span + s.strip_width) + " exceeds length = " + metres(s.length) +
                "; reduce 'support_span' or 'strip_width'");
    require(0.5 * (s.support_span - s.strip_width) > 0.5 * s.notch_width,
            "the support strips reach the notch: support_span - strip_width = " +
                metres(s.support_span - s.strip_width) + " must exceed notch_width = " + metres(s.notch_width) +
                "; increase 'support_span' or reduce 'strip_width' or 'notch_width'");
    require(s.strip_width <= s.length, "parameter 'strip_width' (load strip) must not exceed length = " + metres(s.length));
}

// V-notch. Above the apex (z >= zmin + d) a plain lattice on the columns xs (which include 0,
// the apex). Below it, the left and right parts of the lattice lean into the notch: between the
// inner support edge a and the notch, each column slides from its bottom position (columns
// squeezed linearly from [a, 0] into [a, -w/2]) up to its place at the apex height, so the x = 0
// column becomes the two notch walls and every cell stays a mildly sheared quad.
Profile v_notch_profile(const NotchedBarSpec& s, const std::vector<double>& xs, int n_low, int n_high) {
    const double H = s.height, w = s.notch_width, d = s.notch_depth, zmin = -0.5 * H;
    const double a = -0.5 * s.support_span + 0.5 * s.strip_width;  // the inner support edge column, < -w/2 (checked)
    const int i0 = static_cast<int>(std::find(xs.begin(), xs.end(), 0.0) - xs.begin());
    // Only the load strip's edges -/+ strip_width/2 can come close enough to the apex to merge with it.
    require(i0 < static_cast<int>(xs.size()), "parameter 'strip_width' = " + metres(s.strip_width) +
                                                  " is too small next to the bar's size; widen the load strip");
    const int nx = static_cast<int>(xs.size()) - 1, rows = n_low + n_high;
    auto z_at = [&](int k) {
        if (k == n_low) return zmin + d;
        if (k == rows) return 0.5 * H;
        return k < n_low ? zmin + d * k / n_low : zmin + d + (H - d) * (k - n_low) / n_high;
    };
    auto lean = [&](double x, int k) {  // a column x <= 0 at lower-band row k
        if (x <= a || k >= n_low) return x;
        const double bottom = a + (x - a) * (-0.5 * w - a) / (-a);
        return bottom + (x - bottom) * k / n_low;
    };
    ProfileLattice lattice;
    auto vertex = [&](int i, int k, int side) {
        const bool split = i == i0 && k < n_low;  // a notch wall vertex
        const double x = xs[i] < 0 || (xs[i] == 0 && side < 0) ? lean(xs[i], k) : -lean(-xs[i], k);
        return lattice.vertex(i, k, split ? side : 0, x, z_at(k));
    };
    for (int i = 0; i < nx; ++i)
        for (int k = 0; k < rows; ++k) {
            const bool left = i + 1 <= i0;
            const int side = left ? -1 : 1;
            lattice.quad(vertex(i, k, side), vertex(i + 1, k, side), vertex(i + 1, k + 1, side), vertex(i, k + 1, side),
                         left);
        }
    return lattice.take();
}

// Rectangular slot: a plain lattice on columns xs and rows zs with the slot's cells left out.
Profile slot_profile(const NotchedBarSpec& s, const std::vector<double>& xs, const std::vector<double>& zs) {
    const double zmin = -0.5 * s.height;
    const int nx = static_cast<int>(xs.size()) - 1, rows = static_cast<int>(zs.size()) - 1;
    ProfileLattice lattice;
    auto vertex = [&](int i, int k) { return lattice.vertex(i, k, 0, xs[i], zs[k]); };
    for (int i = 0; i < nx; ++i)
        for (int k = 0; k < rows; ++k) {
            const double xc = 0.5 * (xs[i] + xs[i + 1]), zc = 0.5 * (zs[k] + zs[k + 1]);
            if (std::abs(xc) < 0.5 * s.notch_width && zc < zmin + s.notch_depth) continue;
            lattice.quad(vertex(i, k), vertex(i + 1, k), vertex(i + 1, k + 1), vertex(i, k + 1), xc < 0);
        }
    return lattice.take();
}

// make_notched_bar's steps, in the order it calls them.

// The (x, z) profile of the bar on graded columns and rows; `ny` the cells along y. Refuses
// resolutions that would make more than max_triangles.
Profile bar_profile(const NotchedBarSpec& s, double merge, int& ny) {
    const double L = s.length, H = s.height, D = s.depth, w = s.notch_width, h = s.resolution;
    const double sc = 0.5 * s.support_span, sw = 0.5 * s.strip_width;
    const bool vee = s.notch == NotchShape::V;
    // Columns through the bar's ends, the strip edges, and the notch: its apex (V) or walls (slot).
    std::vector<double> x_breaks{-0.5 * L, 0.5 * L, -sc - sw, -sc + sw, sc - sw, sc + sw, -sw, sw};
    if (vee) x_breaks.push_back(0);
    else x_breaks.insert(x_breaks.end(), {-0.5 * w, 0.5 * w});
    const std::vector<double> xs = graded_nodes(x_breaks, h, merge);
    const std::vector<double> zs = graded_nodes({-0.5 * H, -0.5 * H + s.notch_depth, 0.5 * H}, h, merge);
    const int n_low = cells_for(std::hypot(s.notch_depth, 0.5 * w), h), n_high = cells_for(H - s.notch_depth, h);
    ny = cells_for(D, h);
    const double nx = static_cast<double>(xs.size() - 1);
    const double rows = vee ? n_low + n_high : static_cast<double>(zs.size() - 1);
    const double estimate = 4 * nx * rows + 2 * ny * (2 * nx + 2 * rows + 2);
    require(estimate <= max_triangles, "parameter 'resolution' = " + metres(h) + " would make about " +
                                           std::to_string(static_cast<long long>(estimate)) + " triangles (limit " +
                                           std::to_string(static_cast<long long>(max_triangles)) + "); increase it");
    return vee ? v_notch_profile(s, xs, n_low, n_high) : slot_profile(s, xs, zs);
}

// Directed boundary edges of the profile: used by one triangle only, domain on their left.
struct ProfileBoundary {
    std::vector<std::pair<int, int>> edges;
    std::vector<int> is_boundary;  // per profile point
};

ProfileBoundary profile_boundary(const Profile& prof) {
    std::map<std::pair<int, int>, int> uses;
    for (const Tri& t : prof.triangles)
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
    ProfileBoundary out;
    out.is_boundary.assign(prof.points.size(), 0);
    for (const Tri& t : prof.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            if (uses[std::minmax(a, b)] == 1) {
                out.edges.push_back({a, b});
                out.is_boundary[a] = out.is_boundary[b] = 1;
            }
        }
    return out;
}

enum BarRegion { kRest = 0, kSupportLeft = 1, kSupportRight = 2, kLoad = 3, kNotch = 4 };

// The region of the wall over the profile's boundary edge (a, b): the load strip on top, the
// support strips below, the notch's faces, the rest.
int wall_region(const NotchedBarSpec& s, const Profile& prof, double merge, int a, int b) {
    const double L = s.length, H = s.height;
    const double sc = 0.5 * s.support_span, sw = 0.5 * s.strip_width;
    const auto &pa = prof.points[a], &pb = prof.points[b];
    const double xm = 0.5 * (pa[0] + pb[0]);
    auto at_z = [&](double z) { return std::abs(pa[1] - z) <= merge && std::abs(pb[1] - z) <= merge; };
    auto at_x = [&](double x) { return std::abs(pa[0] - x) <= merge && std::abs(pb[0] - x) <= merge; };
    if (at_z(0.5 * H)) return std::abs(xm) <= sw ? kLoad : kRest;
    if (at_z(-0.5 * H)) {
        if (std::abs(xm + sc) <= sw) return kSupportLeft;
        if (std::abs(xm - sc) <= sw) return kSupportRight;
        return kRest;
    }
    if (at_x(-0.5 * L) || at_x(0.5 * L)) return kRest;
    return kNotch;
}

}  // namespace

SurfaceMesh make_notched_bar(const NotchedBarSpec& s) {
    check(s);
    const double D = s.depth;
    const double merge = 1e-9 * std::max({s.length, s.height, D});
    int ny = 0;
    const Profile prof = bar_profile(s, merge, ny);
    const ProfileBoundary boundary = profile_boundary(prof);

    // The profile extruded along y.
    SurfaceMesh m;
    m.region_names = {"rest", "support_left", "support_right", "load", "notch"};
    // Layer j of the extrusion sits at y = -D/2 + D j / ny; interior layers carry only the
    // profile's boundary vertices (the walls), the two end layers carry all (the caps).
    std::vector<std::vector<int>> id(ny + 1, std::vector<int>(prof.points.size(), -1));
    for (int j = 0; j <= ny; ++j) {
        const double y = j == ny ? 0.5 * D : D * (double(j) / ny - 0.5);
        for (std::size_t v = 0; v < prof.points.size(); ++v) {
            if (j != 0 && j != ny && !boundary.is_boundary[v]) continue;
            id[j][v] = static_cast<int>(m.vertices.size());
            m.vertices.push_back(s.centre + Vec3(prof.points[v][0], y, prof.points[v][1]));
        }
    }
    auto add = [&m](int a, int b, int c, int region) {
        m.triangles.push_back({a, b, c});
        m.region.push_back(region);
    };
    // Caps: counter-clockwise in (x, z) faces -y (x cross z = -y), so the front cap keeps the
    // winding and the back cap reverses it.
    for (const Tri& t : prof.triangles) {
        add(id[0][t[0]], id[0][t[1]], id[0][t[2]], kRest);
        add(id[ny][t[0]], id[ny][t[2]], id[ny][t[1]], kRest);
    }
    // Walls: the front cap walks a -> b along a boundary edge, so the wall walks b -> a there.
    for (const auto& [a, b] : boundary.edges) {
        const int region = wall_region(s, prof, merge, a, b);
        for (int j = 0; j < ny; ++j) {
            add(id[j][b], id[j][a], id[j + 1][a], region);
            add(id[j][b], id[j + 1][a], id[j + 1][b], region);
        }
    }
    return m;
}

}  // namespace cf
