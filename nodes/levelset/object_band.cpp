// OpenVDB translation unit: the object's narrow band by exact distances (levelset.from_mesh
// band: exact, issue 17). One closest-point query per (voxel of the band, candidate triangle), in
// OpenVDB's index space from float corners as meshToVolume computes it, the sign from the same
// query by the angle-weighted pseudo-normal of the closest feature; leaf-sized blocks in parallel
// (oneTBB), each building its own leaf, so the grid is the same for any thread count; the interior
// stays tiles.
#include "nodes/levelset/level_set_grid.hpp"

#include "nodes/domain/triangle_closest_point.hpp"

#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>

namespace cf {
namespace {

using LeafT = openvdb::FloatTree::LeafNodeType;
constexpr int kDim = int(LeafT::DIM);    // 8
constexpr int kSize = int(LeafT::SIZE);  // 512

// Angle-weighted pseudo-normals of a closed, manifold, outward oriented shell (J. A. Baerentzen and
// H. Aanaes, "Signed distance computation using the angle weighted pseudonormal", IEEE TVCG 2005):
// the sign of (p - q).N at the closest point q, with N the pseudo-normal of the face, edge or
// vertex holding q, is the side of p for any p off the surface.
class PseudoNormals {
public:
    PseudoNormals(const std::vector<Vec3>& points, const std::vector<Tri>& tris)
        : tris_(tris), face_(tris.size()), edge_(tris.size()), vertex_(points.size(), Vec3::Zero()) {
        std::map<std::pair<int, int>, Vec3> edges;
        for (std::size_t t = 0; t < tris.size(); ++t) {
            const Tri& f = tris[t];
            face_[t] = (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]).normalized();
            for (int k = 0; k < 3; ++k) {
                const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
                const Vec3 u = (points[b] - points[a]).normalized(), w = (points[c] - points[a]).normalized();
                vertex_[a] += std::acos(std::clamp(u.dot(w), -1.0, 1.0)) * face_[t];
                auto [it, fresh] = edges.emplace(std::minmax(a, b), face_[t]);
                if (!fresh) it->second += face_[t];
            }
        }
        for (std::size_t t = 0; t < tris.size(); ++t)
            for (int k = 0; k < 3; ++k) edge_[t][k] = edges.at(std::minmax(tris[t][k], tris[t][(k + 1) % 3]));
    }
    const Vec3& of(std::uint32_t t, TriangleFeature feature) const {
        const Tri& f = tris_[t];
        switch (feature) {
            case TriangleFeature::vertex_a: return vertex_[f[0]];
            case TriangleFeature::vertex_b: return vertex_[f[1]];
            case TriangleFeature::vertex_c: return vertex_[f[2]];
            case TriangleFeature::edge_ab: return edge_[t][0];
            case TriangleFeature::edge_bc: return edge_[t][1];
            case TriangleFeature::edge_ca: return edge_[t][2];
            case TriangleFeature::face: break;
        }
        return face_[t];
    }

private:
    const std::vector<Tri>& tris_;
    std::vector<Vec3> face_;
    std::vector<std::array<Vec3, 3>> edge_;  // per triangle: edges ab, bc, ca
    std::vector<Vec3> vertex_;
};

// The band's value at squared index-space distance d2 [voxels^2], signed: meshToVolume's
// voxel * sqrt(float(d2)), final. meshToVolume then renormalises (MeshToVolume.h of OpenVDB 10:
// shift by -offset, one upwind renormalisation step kept where it is smaller, shift back by
// offset - epsilon), which this band ran too until 2026-12-06. On exact distances that step only
// moves values where upwind differences see a kink, and always inwards: by up to 0.86 voxel inside
// the armadillo's thin parts (6185 voxels changed sign, thickening them), by one float ulp on a
// sixth of a box's voxels. It also needed one more voxel layer to read, and took half of a box's
// band time. The two shifts are kept (per voxel, in the same float arithmetic): they move every
// value by epsilon = 1e-7 m, and without them every band value would change, not only those the
// renormalisation touched.
inline float band_value(double d2, bool inside, float voxel) {
    namespace m2v = openvdb::tools::mesh_to_volume_internal;
    const float d = std::sqrt(float(d2));
    const float offset = float(0.8 * voxel);
    float v = voxel * (inside ? -d : d);
    v += -offset;
    v += offset - m2v::Tolerance<float>::epsilon();
    return v;
}

// The sign into the tiles and the leaves' inactive voxels (+-width), then pruned.
void finish_band(openvdb::FloatGrid& grid, float voxel_size, float half_width, const CancelToken& cancel) {
    const float width = half_width * voxel_size;
    openvdb::FloatTree& tree = grid.tree();
    tree.root().setBackground(width, /*updateChildNodes=*/false);
    openvdb::tools::signedFloodFillWithValues(tree, width, -width);
    if (cancel.requested()) return;
    prune_level_set_polled(tree, width, -width, cancel);
}

// A triangle in index space: its corners, bounding box and unit normal (for a cheap lower bound of
// the distance: the distance to its plane).
struct IndexTriangle {
    Vec3 a, b, c, lo, hi, n;
    double na = 0;  // n.a
};

// One (block, triangle) pair: the triangle's reach meets the leaf-sized block.
struct BlockEntry {
    openvdb::Coord block;
    float near2;  // squared distance from the block centre to the triangle's box [voxels^2]
    std::uint32_t tri;
};

// Squared distance from x to the interval [lo, hi].
inline double gap2(double x, double lo, double hi) {
    const double d = x < lo ? lo - x : (x > hi ? x - hi : 0.0);
    return d * d;
}

// The blocks whose voxel centres may lie within `reach` [voxels] of triangle t, in a fixed order.
template <class Emit>
void blocks_of(const IndexTriangle& t, double reach, Emit&& emit) {
    const double reach2 = reach * reach * (1 + 1e-9);
    // A block whose centre lies farther from the triangle than the reach plus the block's
    // half-diagonal holds no voxel within the reach (triangle inequality).
    const double half_diagonal = 0.8660254037844386 * (kDim - 1);
    const double block_reach2 = (reach + half_diagonal) * (reach + half_diagonal) * (1 + 1e-9);
    openvdb::Coord lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = int(std::floor(t.lo[a] - reach)) & ~(kDim - 1);
        hi[a] = int(std::ceil(t.hi[a] + reach)) & ~(kDim - 1);
    }
    for (int x = lo[0]; x <= hi[0]; x += kDim)
        for (int y = lo[1]; y <= hi[1]; y += kDim)
            for (int z = lo[2]; z <= hi[2]; z += kDim) {
                const int o[3] = {x, y, z};
                double box = 0, near = 0;
                Vec3 centre;
                for (int a = 0; a < 3; ++a) {
                    box += std::max({t.lo[a] - (o[a] + kDim - 1), o[a] - t.hi[a], 0.0}) *
                           std::max({t.lo[a] - (o[a] + kDim - 1), o[a] - t.hi[a], 0.0});
                    centre[a] = o[a] + 0.5 * (kDim - 1);
                    near += gap2(centre[a], t.lo[a], t.hi[a]);
                }
                if (box > reach2) continue;
                if (std::abs(t.n.dot(centre) - t.na) > reach + half_diagonal) continue;
                if (closest_point_on_nondegenerate_triangle(centre, t.a, t.b, t.c).distance2 > block_reach2) continue;
                emit(BlockEntry{openvdb::Coord(x, y, z), float(near), 0});
            }
}

// The signed band of one block: for every voxel centre within `reach` of the surface, the
// smallest squared distance over the block's triangles (nearest first; a triangle is queried only
// where a lower bound of its distance, from its box and its plane, is below the best so far) and
// the sign of the winning query. Returns null if no voxel of the block is within reach.
std::unique_ptr<LeafT> band_leaf(const openvdb::Coord& origin, const std::uint32_t* first, const std::uint32_t* last,
                                 const std::vector<IndexTriangle>& tris, const PseudoNormals& normals, double reach,
                                 float voxel, float background) {
    const double reach2 = reach * reach;
    // Only strict improvements count, and a lower bound skips a triangle only when it exceeds the
    // best by far more than rounding: skipping never changes the minimum.
    const double margin = 1e-9 * reach2;
    std::array<double, kSize> best;
    std::array<bool, kSize> inside;
    best.fill(reach2);
    inside.fill(false);
    for (const std::uint32_t* it = first; it != last; ++it) {
        const IndexTriangle& t = tris[*it];
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(origin[a], int(std::floor(t.lo[a] - reach)));
            hi[a] = std::min(origin[a] + kDim - 1, int(std::ceil(t.hi[a] + reach)));
        }
        for (int x = lo[0]; x <= hi[0]; ++x) {
            const double gx = gap2(x, t.lo[0], t.hi[0]);
            for (int y = lo[1]; y <= hi[1]; ++y) {
                const double gxy = gx + gap2(y, t.lo[1], t.hi[1]);
                if (gxy > reach2 + margin) continue;
                const int row = ((x - origin[0]) * kDim + (y - origin[1])) * kDim - origin[2];
                const double plane0 = t.n[0] * x + t.n[1] * y - t.na;
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    const int off = row + z;
                    const double bound = std::max(gxy + gap2(z, t.lo[2], t.hi[2]),
                                                  (plane0 + t.n[2] * z) * (plane0 + t.n[2] * z));
                    if (bound > best[off] + margin) continue;
                    const Vec3 p(x, y, z);
                    const TriangleClosestPoint q = closest_point_on_nondegenerate_triangle(p, t.a, t.b, t.c);
                    if (q.distance2 < best[off]) {
                        best[off] = q.distance2;
                        inside[off] = (p - q.point).dot(normals.of(*it, q.feature)) < 0;
                    }
                }
            }
        }
    }
    std::unique_ptr<LeafT> leaf;
    for (int off = 0; off < kSize; ++off) {
        if (!(best[off] < reach2)) continue;
        if (!leaf) leaf = std::make_unique<LeafT>(origin, background, false);
        leaf->setValueOn(openvdb::Index(off), band_value(best[off], inside[off], voxel));
    }
    return leaf;
}

}  // namespace

openvdb::FloatGrid::Ptr exact_band_grid(const SurfaceMesh& mesh, double r_f, double half_width, const CancelToken& cancel) {
    const auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    const float voxel = float(r_f);  // meshToVolume works with the transform's float voxel size
    // The band itself: its values are final, no renormalisation needs neighbours beyond it.
    const double reach = half_width;
    // Vertices rounded to float (meshToLevelSet's input), then to float index-space corners (as
    // its TransformPoints gives them).
    std::vector<Vec3> points, corners;
    points.reserve(mesh.vertices.size());
    corners.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) {
        points.emplace_back(float(v.x()), float(v.y()), float(v.z()));
        const openvdb::Vec3s q(xform->worldToIndex(openvdb::Vec3d(points.back().x(), points.back().y(), points.back().z())));
        corners.emplace_back(q.x(), q.y(), q.z());
    }
    const PseudoNormals normals(points, mesh.triangles);
    std::vector<IndexTriangle> tris(mesh.triangles.size());
    for (std::size_t i = 0; i < tris.size(); ++i) {
        IndexTriangle& t = tris[i];
        const Tri& f = mesh.triangles[i];
        t.a = corners[f[0]];
        t.b = corners[f[1]];
        t.c = corners[f[2]];
        t.lo = t.a.cwiseMin(t.b).cwiseMin(t.c);
        t.hi = t.a.cwiseMax(t.b).cwiseMax(t.c);
        t.n = (t.b - t.a).cross(t.c - t.a).normalized();
        t.na = t.n.dot(t.a);
    }
    // Every (block, triangle) pair, generated per triangle in parallel (counted, then written to
    // its place) and sorted by block, nearest triangle first: a total order, so the result does not
    // depend on the thread count.
    std::vector<std::size_t> first_entry(tris.size() + 1, 0);
    tbb::parallel_for(std::size_t(0), tris.size(), [&](std::size_t t) {
        std::size_t n = 0;
        blocks_of(tris[t], reach, [&](const BlockEntry&) { ++n; });
        first_entry[t + 1] = n;
    });
    for (std::size_t t = 0; t < tris.size(); ++t) first_entry[t + 1] += first_entry[t];
    std::vector<BlockEntry> entries(first_entry.back());
    tbb::parallel_for(std::size_t(0), tris.size(), [&](std::size_t t) {
        std::size_t e = first_entry[t];
        blocks_of(tris[t], reach, [&](BlockEntry x) {
            x.tri = std::uint32_t(t);
            entries[e++] = x;
        });
    });
    cancel.poll();
    tbb::parallel_sort(entries.begin(), entries.end(), [](const BlockEntry& a, const BlockEntry& b) {
        if (a.block != b.block) return a.block < b.block;
        return a.near2 < b.near2 || (a.near2 == b.near2 && a.tri < b.tri);
    });
    std::vector<std::size_t> starts;
    for (std::size_t e = 0; e < entries.size(); ++e)
        if (e == 0 || entries[e].block != entries[e - 1].block) starts.push_back(e);
    starts.push_back(entries.size());
    std::vector<std::uint32_t> order(entries.size());
    for (std::size_t e = 0; e < entries.size(); ++e) order[e] = entries[e].tri;
    // Each block builds its own leaf in parallel; the leaves join the tree in block order.
    const std::size_t num_blocks = starts.size() - 1;
    const float background = float(reach * r_f);
    std::vector<std::unique_ptr<LeafT>> leaves(num_blocks);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_blocks, 16), [&](const tbb::blocked_range<std::size_t>& r) {
        cancel.poll();
        for (std::size_t b = r.begin(); b != r.end(); ++b)
            leaves[b] = band_leaf(entries[starts[b]].block, order.data() + starts[b], order.data() + starts[b + 1], tris,
                                  normals, reach, voxel, background);
    });
    auto g = openvdb::FloatGrid::create(background);
    g->setTransform(xform->copy());
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    openvdb::FloatTree& tree = g->tree();
    for (auto& leaf : leaves)
        if (leaf) tree.addLeaf(leaf.release());
    finish_band(*g, voxel, float(half_width), cancel);
    return g;
}

}  // namespace cf
