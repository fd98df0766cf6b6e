#include "nodes/segment/fracture_faces.hpp"

#include "nodes/segment/surface_fragments.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cf {

namespace {

// v reordered so that the entries with !deep[t] come first, then those with deep[t], each part in
// its old order: counted and scattered in fixed chunks on parallel tasks (a fragment of the
// thesis cases has up to ~500 k triangles, and the last one meshed is tagged while the other core
// idles), the same order as one pass.
template <class T>
void partition_stable(std::vector<T>& v, const std::vector<char>& deep, const std::vector<std::size_t>& out_start,
                      const std::vector<std::size_t>& in_start, std::size_t chunk) {
    std::vector<T> out(v.size());
    tbb::parallel_for(std::size_t(0), out_start.size(), [&](std::size_t c) {
        std::size_t o = out_start[c], i = in_start[c];
        for (std::size_t t = c * chunk, end = std::min(v.size(), t + chunk); t < end; ++t) out[deep[t] ? i++ : o++] = v[t];
    });
    v = std::move(out);
}

}  // namespace

void tag_fracture_faces(SurfaceMesh& m, const LevelSet& object, double depth) {
    if (!(depth > 0) || !std::isfinite(depth))
        throw std::invalid_argument("fracture-face depth must be a positive number of metres");
    const std::size_t n = m.num_triangles();
    std::vector<Vec3> centroids(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t t) { centroids[t] = triangle_centroid(m, t); });
    const std::vector<double> phi = sample_points(object, centroids);
    // Outside faces first, then inside ones, each in their old order: the writers start a group
    // (OBJ g / usemtl) wherever the region changes, so contiguous regions give one group each.
    std::vector<char> deep(n);
    for (std::size_t t = 0; t < n; ++t) deep[t] = phi[t] < -depth;
    constexpr std::size_t kChunk = 1 << 15;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<std::size_t> deep_in(chunks, 0);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        for (std::size_t t = c * kChunk, end = std::min(n, t + kChunk); t < end; ++t) deep_in[c] += std::size_t(deep[t]);
    });
    std::size_t outside = 0;
    for (std::size_t c = 0; c < chunks; ++c) outside += std::min(n, (c + 1) * kChunk) - c * kChunk - deep_in[c];
    std::vector<std::size_t> out_start(chunks), in_start(chunks);
    for (std::size_t c = 0, o = 0, i = outside; c < chunks; ++c) {
        out_start[c] = o;
        in_start[c] = i;
        o += std::min(n, (c + 1) * kChunk) - c * kChunk - deep_in[c];
        i += deep_in[c];
    }
    partition_stable(m.triangles, deep, out_start, in_start, kChunk);
    if (m.has_uv()) partition_stable(m.corner_uv, deep, out_start, in_start, kChunk);
    if (m.has_normals()) partition_stable(m.corner_normal, deep, out_start, in_start, kChunk);
    m.region.assign(outside, 0);
    m.region.resize(n, 1);
    m.region_names = {kOutsideRegion, kInsideRegion};
}

double region_area(const SurfaceMesh& m, const std::string& name) {
    double a = 0;
    for (std::size_t t = 0; t < m.num_triangles(); ++t)
        if (m.region_name(m.region_of(t)) == name) a += triangle_area(m, t);
    return a;
}

}  // namespace cf
