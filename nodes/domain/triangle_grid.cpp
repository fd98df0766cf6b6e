#include "nodes/domain/triangle_grid.hpp"

#include "graph/diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cf {

namespace {

constexpr std::int64_t kIndexLimit = std::int64_t(1) << 20;  // 21 bits per axis in a cell key

}  // namespace

TriangleGrid::TriangleGrid(std::vector<Triangle3> triangles, double cell_size, double max_cell_entries)
    : triangles_(std::move(triangles)), cell_(cell_size) {
    if (!(cell_size > 0) || !std::isfinite(cell_size))
        throw std::invalid_argument("triangle grid: cell size " + graph::format_number(cell_size) + " m must be positive");
    std::vector<std::array<Cell, 2>> ranges(triangles_.size());
    double entries = 0;
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
        const Triangle3& tri = triangles_[t];
        for (const Vec3& v : tri)
            if (!v.allFinite()) throw std::invalid_argument("triangle grid: triangle " + std::to_string(t) + " has a non-finite vertex");
        const Vec3 lo = tri[0].cwiseMin(tri[1]).cwiseMin(tri[2]), hi = tri[0].cwiseMax(tri[1]).cwiseMax(tri[2]);
        if ((lo / cell_).cwiseAbs().maxCoeff() >= double(kIndexLimit) || (hi / cell_).cwiseAbs().maxCoeff() >= double(kIndexLimit))
            throw std::invalid_argument("triangle grid: triangle " + std::to_string(t) + " lies more than 2^20 cells of " +
                                        graph::format_number(cell_) + " m from the origin; use a larger cell size");
        ranges[t] = {cell_of(lo), cell_of(hi)};
        double n = 1;
        for (int a = 0; a < 3; ++a) n *= double(ranges[t][1][a] - ranges[t][0][a] + 1);
        entries += n;
    }
    if (entries > max_cell_entries)
        throw std::invalid_argument("triangle grid: " + std::to_string(triangles_.size()) + " triangles would fill " +
                                    graph::format_number(entries) + " cell lists (limit " + graph::format_number(max_cell_entries) +
                                    "); the cell size " + graph::format_number(cell_) + " m is far smaller than the triangles");
    for (int a = 0; a < 3; ++a) {
        lo_[a] = std::numeric_limits<std::int64_t>::max();
        hi_[a] = std::numeric_limits<std::int64_t>::min();
    }
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
        const auto& r = ranges[t];
        for (int a = 0; a < 3; ++a) {
            lo_[a] = std::min(lo_[a], r[0][a]);
            hi_[a] = std::max(hi_[a], r[1][a]);
        }
        for (std::int64_t i = r[0][0]; i <= r[1][0]; ++i)
            for (std::int64_t j = r[0][1]; j <= r[1][1]; ++j)
                for (std::int64_t k = r[0][2]; k <= r[1][2]; ++k) cells_[key({i, j, k})].push_back(int(t));
    }
}

TriangleGrid::Cell TriangleGrid::cell_of(const Vec3& x) const {
    Cell c;
    for (int a = 0; a < 3; ++a) {
        const double f = std::floor(x[a] / cell_);
        c[a] = std::int64_t(std::clamp(f, -double(kIndexLimit), double(kIndexLimit)));
    }
    return c;
}

std::uint64_t TriangleGrid::key(const Cell& c) {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) k = (k << 21) | std::uint64_t(c[a] + kIndexLimit);
    return k;
}

const std::vector<int>* TriangleGrid::cell_list(const Cell& c) const {
    const auto it = cells_.find(key(c));
    return it == cells_.end() ? nullptr : &it->second;
}

void TriangleGrid::test(int t, const Vec3& x, Hit& best) const {
    const Triangle3& tri = triangles_[std::size_t(t)];
    const TriangleClosestPoint p = closest_point_on_triangle(x, tri[0], tri[1], tri[2]);
    const double d = std::sqrt(p.distance2);
    if (d < best.distance || (d == best.distance && t < best.triangle)) best = Hit{t, p.point, p.barycentric, d};
}

TriangleGrid::Hit TriangleGrid::closest(const Vec3& x) const {
    Hit best;
    if (triangles_.empty()) return best;
    const Cell c0 = cell_of(x);
    // Shells inside the Chebyshev distance from c0 to the occupied range hold no triangles.
    std::int64_t k_start = 0, k_all = 0;
    for (int a = 0; a < 3; ++a) {
        k_start = std::max({k_start, lo_[a] - c0[a], c0[a] - hi_[a]});
        k_all = std::max({k_all, c0[a] - lo_[a], hi_[a] - c0[a]});
    }
    for (std::int64_t k = k_start; k <= k_all; ++k) {
        std::int64_t lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(c0[a] - k, lo_[a]);
            hi[a] = std::min(c0[a] + k, hi_[a]);
        }
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
                const bool edge_ij = std::abs(i - c0[0]) == k || std::abs(j - c0[1]) == k;
                for (std::int64_t l = lo[2]; l <= hi[2]; ++l) {
                    // Only the shell at Chebyshev distance k; the inner cells were visited before.
                    if (!edge_ij && std::abs(l - c0[2]) != k) {
                        l = std::max(l, c0[2] + k - 1);
                        continue;
                    }
                    if (const std::vector<int>* list = cell_list({i, j, l}))
                        for (int t : *list) test(t, x, best);
                }
            }
        // x lies in cell c0, so every triangle not listed in the (2k+1)^3 block around it is at
        // least k cells away.
        if (best.triangle >= 0 && best.distance <= double(k) * cell_) break;
    }
    return best;
}

std::vector<TriangleGrid::Hit> TriangleGrid::within(const Vec3& x, double radius) const {
    std::vector<Hit> hits;
    if (triangles_.empty() || !(radius >= 0)) return hits;
    const Cell lo = cell_of(x - Vec3::Constant(radius)), hi = cell_of(x + Vec3::Constant(radius));
    std::vector<int> candidates;
    for (std::int64_t i = std::max(lo[0], lo_[0]); i <= std::min(hi[0], hi_[0]); ++i)
        for (std::int64_t j = std::max(lo[1], lo_[1]); j <= std::min(hi[1], hi_[1]); ++j)
            for (std::int64_t l = std::max(lo[2], lo_[2]); l <= std::min(hi[2], hi_[2]); ++l)
                if (const std::vector<int>* list = cell_list({i, j, l}))
                    candidates.insert(candidates.end(), list->begin(), list->end());
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    for (int t : candidates) {
        Hit h;
        test(t, x, h);
        if (h.distance <= radius) hits.push_back(h);
    }
    return hits;
}

}  // namespace cf
