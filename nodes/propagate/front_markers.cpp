#include "nodes/propagate/front_markers.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>

#include <cmath>
#include <stdexcept>

namespace cf::propagate {

int markers_per_edge(double r_c, double r_f) {
    if (!(r_c > 0) || !(r_f > 0)) throw std::invalid_argument("markers per edge: r_c and r_f must be > 0 [m]");
    return std::max(1, static_cast<int>(std::ceil(r_c / r_f - 1e-9)));
}

std::vector<Vec3> FrontMarkers::positions() const {
    std::vector<Vec3> p;
    p.reserve(markers.size());
    for (const MarkerState& m : markers) p.push_back(m.position);
    return p;
}

FrontMarkers place_markers(const CrackFront& front, const SurfaceMesh& cracks, int n) {
    if (n < 1) throw std::invalid_argument("place_markers: at least one marker per edge");
    FrontMarkers fm;
    fm.closed = front.closed;
    fm.per_edge = n;
    const std::size_t N = front.nodes.size();
    for (std::size_t i = 0; i < front.num_edges(); ++i) {
        const Vec3& a = cracks.vertices.at(front.nodes[i]);
        const Vec3& b = cracks.vertices.at(front.nodes[(i + 1) % N]);
        for (int k = 0; k < n; ++k) {
            MarkerState m;
            m.position = a + (static_cast<double>(k) / n) * (b - a);
            fm.markers.push_back(m);
        }
    }
    if (!front.closed && N > 0) {
        MarkerState m;
        m.position = cracks.vertices.at(front.nodes.back());
        fm.markers.push_back(m);
    }
    if (!front.sifs.empty()) interpolate_front_state(fm, front, false);
    return fm;
}

void interpolate_front_state(FrontMarkers& fm, const CrackFront& front, bool keep_history) {
    const std::size_t N = front.nodes.size(), n = fm.per_edge;
    const std::size_t expected = front.closed ? N * n : (N == 0 ? 0 : (N - 1) * n + 1);
    if (fm.markers.size() != expected || front.sifs.size() != N || front.frames.size() != N)
        throw std::invalid_argument("interpolate_front_state: " + std::to_string(fm.markers.size()) + " markers, " +
                                    std::to_string(N) + " nodes, " + std::to_string(front.sifs.size()) + " SIFs, " +
                                    std::to_string(front.frames.size()) + " frames (expected " + std::to_string(expected) +
                                    " markers)");
    for (std::size_t m = 0; m < fm.markers.size(); ++m) {
        const std::size_t i = std::min(m / n, N - 1), k = m - i * n;
        const std::size_t j = (i + 1) % N;
        const double wj = static_cast<double>(k) / n, wi = 1 - wj;
        MarkerState& s = fm.markers[m];
        if (keep_history) {
            s.K_old = s.K;
            s.has_old = true;
        }
        const Sifs& Ki = front.sifs[i];
        const Sifs& Kj = front.sifs[k == 0 ? i : j];
        s.K = {wi * Ki.KI + wj * Kj.KI, wi * Ki.KII + wj * Kj.KII, wi * Ki.KIII + wj * Kj.KIII};
        const FrontFrame& fi = front.frames[i];
        const FrontFrame& fj = front.frames[k == 0 ? i : j];
        const FrontFrame f = orthonormalised(wi * fi.n1 + wj * fj.n1, wi * fi.n3 + wj * fj.n3);
        s.n1 = f.n1;
        s.n2 = f.n2;
    }
}

double polyline_length(const std::vector<Vec3>& p, bool closed) {
    double L = 0;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) L += (p[i + 1] - p[i]).norm();
    if (closed && p.size() > 1) L += (p.front() - p.back()).norm();
    return L;
}

std::vector<Vec3> resample_polyline(const std::vector<Vec3>& p, bool closed, std::size_t count, double start) {
    std::vector<Vec3> out;
    if (p.empty() || count == 0) return out;
    const double L = polyline_length(p, closed);
    if (!(L > 0)) return std::vector<Vec3>(count, p.front());
    const std::size_t segs = closed ? p.size() : p.size() - 1;
    // Cumulative arc length at each vertex.
    std::vector<double> s(segs + 1, 0);
    for (std::size_t i = 0; i < segs; ++i) s[i + 1] = s[i] + (p[(i + 1) % p.size()] - p[i]).norm();
    const double step = closed ? L / count : (count > 1 ? L / (count - 1) : 0);
    std::size_t seg = 0;
    for (std::size_t c = 0; c < count; ++c) {
        double t = closed ? std::fmod(start + c * step, L) : c * step;
        if (t < 0) t += L;
        if (!closed && c + 1 == count) t = L;
        if (closed) seg = 0;  // start may wrap: search from the beginning
        while (seg + 1 < segs && s[seg + 1] < t) ++seg;
        const double len = s[seg + 1] - s[seg];
        const double u = len > 0 ? std::clamp((t - s[seg]) / len, 0.0, 1.0) : 0.0;
        out.push_back(p[seg] + u * (p[(seg + 1) % p.size()] - p[seg]));
    }
    return out;
}

double advance_markers(FrontMarkers& fm, const ScalarField& toughness, const PropagationSettings& settings, int substep,
                       int n_substeps, bool planar) {
    const double w_t = blend_weight(substep, n_substeps);
    std::vector<double> moved(fm.markers.size(), 0);
    tbb::parallel_for(std::size_t(0), fm.markers.size(), [&](std::size_t i) {
        const MarkerStep st = marker_substep(fm.markers[i], toughness, settings, w_t, planar);
        fm.markers[i].position += st.displacement;
        moved[i] = st.displacement.norm();
    });
    // Slide the markers back to equal spacing (closed: marker 0 stays where it moved to).
    const std::vector<Vec3> even = resample_polyline(fm.positions(), fm.closed, fm.markers.size(), 0);
    for (std::size_t i = 0; i < fm.markers.size(); ++i) fm.markers[i].position = even[i];
    double mx = 0;
    for (double d : moved) mx = std::max(mx, d);
    return mx;
}

}  // namespace cf::propagate
