// OpenVDB translation unit: crack grids, strip recording and the marker tests of fig. 27.
#include "nodes/levelset/crack_grids.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/domain/triangle_closest_point.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace cf {

const char* to_string(MarkerHit h) {
    switch (h) {
        case MarkerHit::none: return "none";
        case MarkerHit::left_object: return "left_object";
        case MarkerHit::crossed_crack: return "crossed_crack";
        case MarkerHit::self_intersection: return "self_intersection";
    }
    return "?";
}

namespace {
constexpr int kLeafDim = int(openvdb::FloatTree::LeafNodeType::DIM);  // 8
constexpr int kLeafSize = int(openvdb::FloatTree::LeafNodeType::SIZE);

// Three-way max and min without std::initializer_list (which the hot loops below did not inline).
inline double max3(double a, double b, double c) { return std::max(std::max(a, b), c); }
inline int max3(int a, int b, int c) { return std::max(std::max(a, b), c); }
inline int min3(int a, int b, int c) { return std::min(std::min(a, b), c); }
// floor and ceil to int without the libm call std::floor makes on plain x86-64 (per column, the
// largest cost of the rasteriser after the voxel visits). Exact for |x| < 2^31, far above any
// voxel index here (callers clamp to a block first).
inline int floor_int(double x) {
    const int i = int(x);  // truncation towards zero
    return i - (x < double(i));
}
inline int ceil_int(double x) {
    const int i = int(x);
    return i + (x > double(i));
}

// One triangle prepared for rasterisation: the voxels it may reach are the box [lo_i, hi_i]
// (its bounding box grown by the reach), and, for a planar triangle, in each column along the
// axis closest to its normal only the slab |n.(x - a)| <= reach around its plane.
struct RasterTriangle {
    Triangle3 t;
    bool degenerate = false;
    Vec3 box_lo, box_hi;  // the triangle's own bounding box [m]: distance lower bound
    openvdb::Coord lo_i, hi_i;
    int axis = 2, u = 0, v = 1;
    bool slab = false;
    Vec3 n = Vec3::Zero();
    double half = 0;  // slab half-height along `axis` [m]
    // The plane over a column: axis coordinate c = c0 + cu x_u + cv x_v [m].
    double c0 = 0, cu = 0, cv = 0;
    // In-plane frame of a planar triangle: e along its first edge, m = n x e, and the triangle's
    // extent [e_lo, e_hi] x [m_lo, m_hi] in it (relative to t[0]). With h = n.(p - t0), the squared
    // distance to the triangle is h^2 + (in-plane distance)^2 >= h^2 + gap_e^2 + gap_m^2: a lower
    // bound much tighter than the bounding box for a tilted sliver of a swept strip.
    bool framed = false;
    Vec3 e = Vec3::Zero(), m = Vec3::Zero();
    double e_lo = 0, e_hi = 0, m_lo = 0, m_hi = 0;

    RasterTriangle(const Triangle3& tri, double r_f, double reach)
        : t(tri), degenerate(is_degenerate_triangle(tri[0], tri[1], tri[2])) {
        box_lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
        box_hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
        const Vec3 lo = box_lo.array() - reach, hi = box_hi.array() + reach;
        n = (t[1] - t[0]).cross(t[2] - t[0]);
        const double nn = n.norm();
        const bool planar = nn > 1e-12 * (hi - lo).squaredNorm();
        if (planar) {
            n /= nn;
            n.cwiseAbs().maxCoeff(&axis);
        }
        u = (axis + 1) % 3;
        v = (axis + 2) % 3;
        for (int a = 0; a < 3; ++a) {
            lo_i[a] = int(std::floor(lo[a] / r_f));
            hi_i[a] = int(std::ceil(hi[a] / r_f));
        }
        slab = planar && std::abs(n[axis]) > 1e-3;
        half = slab ? reach / std::abs(n[axis]) : 0;
        if (slab) {
            c0 = n.dot(t[0]) / n[axis];
            cu = -n[u] / n[axis];
            cv = -n[v] / n[axis];
        }
        if (planar && !degenerate) {
            const Vec3 ab = t[1] - t[0];
            if (ab.norm() > 0) {
                framed = true;
                e = ab.normalized();
                m = n.cross(e).normalized();
                const Vec3 ac = t[2] - t[0];
                e_lo = std::min({0.0, e.dot(ab), e.dot(ac)});
                e_hi = std::max({0.0, e.dot(ab), e.dot(ac)});
                m_lo = std::min({0.0, m.dot(ab), m.dot(ac)});
                m_hi = std::max({0.0, m.dot(ab), m.dot(ac)});
            }
        }
    }
    // Squared distance from p to the triangle [m^2].
    // A degenerate triangle (a deactivated marker next to another: p0 == p1) is its edges; the
    // test is made once per triangle, not per voxel.
    double distance2(const Vec3& p) const {
        return (degenerate ? closest_point_on_triangle_edges(p, t[0], t[1], t[2])
                           : closest_point_on_nondegenerate_triangle(p, t[0], t[1], t[2]))
            .distance2;
    }
};

// One or two triangles rasterised together: the two halves of a strip quad (consecutive triangles
// sharing an edge, both with a slab along the same axis) reach nearly the same voxels, so their
// columns are walked once and a voxel beyond the pair's joint box is rejected once. Grouping only
// decides which voxels are looked at: each voxel still takes the minimum over every triangle that
// can reach it, so the values do not depend on it.
struct RasterPrimitive {
    std::uint32_t first = 0, count = 1;  // its triangles in the prepared list
    Vec3 box_lo, box_hi;                 // the joint bounding box [m]
    openvdb::Coord lo_i, hi_i;           // the joint reach box [voxels]
    int axis = 2, u = 0, v = 1;

    // Prepared triangle `index` alone.
    RasterPrimitive(const RasterTriangle& t, std::uint32_t index)
        : first(index), box_lo(t.box_lo), box_hi(t.box_hi), lo_i(t.lo_i), hi_i(t.hi_i), axis(t.axis), u(t.u), v(t.v) {}
    // With the next prepared triangle (same axis) added.
    void join(const RasterTriangle& t) {
        ++count;
        box_lo = box_lo.cwiseMin(t.box_lo);
        box_hi = box_hi.cwiseMax(t.box_hi);
        for (int c = 0; c < 3; ++c) {
            lo_i[c] = std::min(lo_i[c], t.lo_i[c]);
            hi_i[c] = std::max(hi_i[c], t.hi_i[c]);
        }
    }
};

constexpr int kMaxGroup = 2;

bool share_edge(const Triangle3& a, const Triangle3& b) {
    int shared = 0;
    for (const Vec3& p : a)
        for (const Vec3& q : b)
            if (p == q) {
                ++shared;
                break;
            }
    return shared >= 2;
}

// Pairs consecutive triangles that share an edge and slab along the same axis (a strip quad's two
// halves, or two of a surface closure's); every other triangle is a primitive of its own. Grouping
// more (runs of up to 4 or 8 neighbours whose joint reach box stays within 1.5 times one of theirs)
// was measured slower on chain_link_concrete, whose fans are long and thin.
std::vector<RasterPrimitive> raster_primitives(const std::vector<RasterTriangle>& prepared) {
    std::vector<RasterPrimitive> out;
    out.reserve(prepared.size());
    for (std::size_t k = 0; k < prepared.size();) {
        const RasterTriangle& a = prepared[k];
        RasterPrimitive p(a, std::uint32_t(k));
        if (k + 1 < prepared.size()) {
            const RasterTriangle& b = prepared[k + 1];
            if (a.slab && b.slab && a.axis == b.axis && share_edge(a.t, b.t)) p.join(b);
        }
        k += p.count;
        out.push_back(p);
    }
    return out;
}

// The thickened distances of one leaf-sized block: the smallest squared distance over all
// triangles whose band reaches each voxel (min is order-independent, so blocks can run in any
// order and on any thread).
struct BlockDistances {
    // User-provided, so std::vector<BlockDistances>(n) does not zero ~3 kB per block (only the
    // first `count` entries of `list`, and `value` at those offsets, are ever read).
    BlockDistances() {}
    openvdb::Coord origin;
    std::array<float, kLeafSize> value;  // the new value at each offset in `list`
    std::array<std::uint16_t, kLeafSize> list;  // the voxels set or lowered (offsets in the leaf)
    std::size_t count = 0;
};

// `old` is the grid's leaf at this block (null if none): a voxel already holding distance d_old
// can only change where a new triangle comes closer than d_old, so d_old^2 starts the search and
// prunes every triangle whose box is farther (behind a growing front, nearly all of them).
// The block's primitives come nearest first; a pair's triangles are tested one after the other on
// each voxel the pair's joint box admits. With `finish`, each voxel's closest triangle is kept too
// (ties: the first in that fixed order) and `finish` turns the unsigned value into the stored one.
void rasterise_block(BlockDistances& out, const std::vector<RasterTriangle>& tris,
                     const std::vector<RasterPrimitive>& prims, const std::uint32_t* first, const std::uint32_t* last,
                     const openvdb::FloatTree::LeafNodeType* old, double r_f, double thick, double reach,
                     const ClosestTriangleValue* finish) {
    const double reach2 = reach * reach;
    // A triangle is skipped for a voxel when its box is farther than the best distance so
    // far plus a margin far above rounding (so skipping never changes the minimum).
    const double margin = 1e-9 * reach2;
    // best[off]: the smallest squared distance so far, read lazily from the old leaf on the first
    // visit (kUnvisited before): most voxels of a block are never reached by any triangle, and
    // initialising all 512 of every block of every sub-step cost as much as the visits.
    constexpr double kUnvisited = -1;
    std::array<double, kLeafSize> best;
    std::array<std::uint32_t, kLeafSize> closest;
    best.fill(kUnvisited);
    // The old leaf's values, read through one pointer: LeafNode::getValue checks per call whether
    // the buffer is still to be loaded from a file (an out-of-line call in this loop).
    const float* const old_values = old ? old->buffer().data() : nullptr;
    auto start_of = [&](int off) {  // only d^2 < reach^2 is in the band
        if (!old || !old->isValueOn(openvdb::Index(off))) return reach2;
        const double d = double(old_values[off]) + thick;
        return d <= 0 ? 0.0 : std::min(reach2, d * d);
    };
    std::array<std::uint64_t, kLeafSize / 64> lowered{};  // bit per voxel: in out.list already
    out.count = 0;
    const openvdb::Coord o = out.origin;
    const double inv = 1 / r_f;
    // Voxel-centre coordinates of this block along each axis [m], and the offset strides.
    std::array<std::array<double, kLeafDim>, 3> xs;
    for (int a = 0; a < 3; ++a)
        for (int q = 0; q < kLeafDim; ++q) xs[a][q] = (o[a] + q) * r_f;
    constexpr int stride[3] = {kLeafDim * kLeafDim, kLeafDim, 1};
    // Voxel centres k r_f of a column within [lo, hi] [m], widened by kSlack voxels far above
    // rounding (a voxel outside is farther than the reach, so the visit below would skip it
    // anyway: the ranges only save visits, they never decide a value).
    constexpr double kSlack = 1e-6;
    // Per triangle of the primitive, what its column needs: its box distance across the column and
    // the frame coordinates of the column's foot (x_axis = t0_axis).
    struct ColumnOfTriangle {
        double duv, h0, e0, m0;
    };
    // The walk of one primitive, compiled for one and for two triangles (the loops over a pair's
    // triangles unrolled).
    auto walk = [&](auto count, const RasterPrimitive& pr) {
        constexpr int n_tri = decltype(count)::value;
        const RasterTriangle* const rts = &tris[pr.first];
        const int u = pr.u, v = pr.v, axis = pr.axis;
        const int i0 = std::max(pr.lo_i[u], o[u]), i1 = std::min(pr.hi_i[u], o[u] + kLeafDim - 1);
        const int j0 = std::max(pr.lo_i[v], o[v]), j1 = std::min(pr.hi_i[v], o[v] + kLeafDim - 1);
        const double lo_a = pr.box_lo[axis], hi_a = pr.box_hi[axis];
        bool all_slabs = true;
        for (int t = 0; t < n_tri; ++t) all_slabs = all_slabs && rts[t].slab;
        // The block's extent along `axis` [m], one voxel wider on each side.
        const double block_lo = (o[axis] - 1) * r_f, block_hi = (o[axis] + kLeafDim) * r_f;
        for (int i = i0; i <= i1; ++i) {
            const double xu = xs[u][i - o[u]];
            const double du = max3(pr.box_lo[u] - xu, xu - pr.box_hi[u], 0.0);
            // Each plane's axis coordinate in this row is c = base[t] + cv x_v [m] (evaluated in
            // that order in the columns below too, so c is rounded as c0 + cu x_u + cv x_v).
            double base[kMaxGroup];
            for (int t = 0; t < n_tri; ++t) base[t] = rts[t].c0 + rts[t].cu * xu;
            int ja = j0, jb = j1;
            if (all_slabs) {
                // c is linear in x_v, so its slab [c - half, c + half] meets the (widened) block
                // for one interval of x_v only. Columns outside every triangle's interval are not
                // walked: all their voxels lie farther than `half` (plus a voxel) from each plane
                // along `axis`, so farther than the reach from each triangle; walking them would
                // change nothing.
                double lo_j = std::numeric_limits<double>::max(), hi_j = -lo_j;
                for (int t = 0; t < n_tri; ++t) {
                    const RasterTriangle& rt = rts[t];
                    const double a = block_lo - rt.half - base[t], b = block_hi + rt.half - base[t];  // a <= cv x_v <= b
                    if (rt.cv == 0) {
                        if (a <= 0 && 0 <= b) lo_j = -(hi_j = std::numeric_limits<double>::max());
                        continue;
                    }
                    const double p = a / rt.cv * inv, q = b / rt.cv * inv;  // the interval in voxel indices
                    lo_j = std::min(lo_j, std::min(p, q));
                    hi_j = std::max(hi_j, std::max(p, q));
                }
                // One column of margin on each side; clamped to the row before the conversion to
                // int (a nearly level plane sends the bounds far away; no interval: lo_j > hi_j).
                const double lo_c = std::min(std::max(lo_j, double(j0 - 1)), double(j1 + 1));
                const double hi_c = std::min(std::max(hi_j, double(j0 - 1)), double(j1 + 1));
                ja = std::max(j0, floor_int(lo_c) - 1);
                jb = std::min(j1, ceil_int(hi_c) + 1);
            }
            for (int j = ja; j <= jb; ++j) {
                const double xv = xs[v][j - o[v]];
                const double dv = max3(pr.box_lo[v] - xv, xv - pr.box_hi[v], 0.0);
                const double duv = du * du + dv * dv;  // joint box distance across the column
                if (duv > reach2 + margin) continue;
                int k0 = pr.lo_i[axis], k1 = pr.hi_i[axis];
                {
                    // Points with |n.(x - a)| <= reach for some triangle: the hull of the triangles'
                    // intervals along `axis` in this column (a single triangle without a slab: all).
                    int s0 = std::numeric_limits<int>::max(), s1 = std::numeric_limits<int>::min();
                    bool all = false;
                    for (int t = 0; t < n_tri; ++t) {
                        const RasterTriangle& rt = rts[t];
                        if (!rt.slab) {
                            all = true;
                            break;
                        }
                        const double c = base[t] + rt.cv * xv;  // axis coordinate on the plane
                        s0 = std::min(s0, ceil_int((c - rt.half) * inv - kSlack));
                        s1 = std::max(s1, floor_int((c + rt.half) * inv + kSlack));
                    }
                    if (!all) {
                        k0 = std::max(k0, s0);
                        k1 = std::min(k1, s1);
                    }
                }
                // And within the reach of the joint box along the column.
                const double w = std::sqrt(reach2 + margin - duv);
                k0 = max3(k0, o[axis], ceil_int((lo_a - w) * inv - kSlack));
                k1 = min3(k1, o[axis] + kLeafDim - 1, floor_int((hi_a + w) * inv + kSlack));
                if (k0 > k1) continue;
                const int base = (i - o[u]) * stride[u] + (j - o[v]) * stride[v] - o[axis] * stride[axis];
                Vec3 p;
                p[u] = xu;
                p[v] = xv;
                ColumnOfTriangle col[kMaxGroup];
                for (int t = 0; t < n_tri; ++t) {
                    const RasterTriangle& rt = rts[t];
                    ColumnOfTriangle& c = col[t];
                    if constexpr (n_tri > 1) {
                        const double tu = max3(rt.box_lo[u] - xu, xu - rt.box_hi[u], 0.0);
                        const double tv = max3(rt.box_lo[v] - xv, xv - rt.box_hi[v], 0.0);
                        c.duv = tu * tu + tv * tv;
                    } else {
                        c.duv = duv;
                    }
                    c.h0 = c.e0 = c.m0 = 0;
                    if (rt.framed) {
                        const double qu = xu - rt.t[0][u], qv = xv - rt.t[0][v];
                        c.h0 = rt.n[u] * qu + rt.n[v] * qv;
                        c.e0 = rt.e[u] * qu + rt.e[v] * qv;
                        c.m0 = rt.m[u] * qu + rt.m[v] * qv;
                    }
                }
                for (int k = k0; k <= k1; ++k) {
                    const int off = base + k * stride[axis];
                    const double xa = xs[axis][k - o[axis]];
                    const double da = max3(lo_a - xa, xa - hi_a, 0.0);
                    double b = best[off];
                    if (b < 0) b = best[off] = start_of(off);
                    if (duv + da * da > b + margin) continue;  // the joint box is already too far
                    p[axis] = xa;
                    for (int t = 0; t < n_tri; ++t) {
                        const RasterTriangle& rt = rts[t];
                        const ColumnOfTriangle& c = col[t];
                        if constexpr (n_tri > 1) {
                            const double ta = max3(rt.box_lo[axis] - xa, xa - rt.box_hi[axis], 0.0);
                            if (c.duv + ta * ta > b + margin) continue;  // its own box
                        }
                        if (rt.framed) {
                            const double qa = xa - rt.t[0][axis];
                            const double h = c.h0 + rt.n[axis] * qa, pe = c.e0 + rt.e[axis] * qa,
                                         pm = c.m0 + rt.m[axis] * qa;
                            const double ge = max3(rt.e_lo - pe, pe - rt.e_hi, 0.0);
                            const double gm = max3(rt.m_lo - pm, pm - rt.m_hi, 0.0);
                            if (h * h + ge * ge + gm * gm > b + margin) continue;  // the in-plane box too
                        }
                        const double d2 = rt.distance2(p);
                        if (d2 < b) {  // in the band and closer than before
                            b = best[off] = d2;
                            closest[off] = pr.first + std::uint32_t(t);
                            std::uint64_t& word = lowered[off >> 6];
                            const std::uint64_t bit = std::uint64_t(1) << (off & 63);
                            if (!(word & bit)) {
                                word |= bit;
                                out.list[out.count++] = std::uint16_t(off);
                            }
                        }
                    }
                }
            }
        }
    };
    for (const std::uint32_t* it = first; it != last; ++it) {
        const RasterPrimitive& pr = prims[*it];
        if (pr.count == 2)
            walk(std::integral_constant<int, 2>{}, pr);
        else
            walk(std::integral_constant<int, 1>{}, pr);
    }
    for (std::size_t q = 0; q < out.count; ++q) {
        const int off = out.list[q];
        // min_t float(sqrt(d2_t) - thick) == float(sqrt(min_t d2_t) - thick): all steps are monotone.
        out.value[off] = float(std::sqrt(best[off]) - thick);
        if (finish) {
            const int x = off >> 6, y = (off >> 3) & 7, z = off & 7;
            out.value[off] = (*finish)(closest[off], Vec3(xs[0][x], xs[1][y], xs[2][z]), out.value[off]);
        }
    }
}

// Union the thickened distance of the triangles into the grid: every voxel whose value
// d - sqrt(3) r_f/2 lies below the band limit gets min(old, new). Work is split by leaf-sized
// block: each block gathers the triangles whose reach box overlaps it and keeps the smallest
// distance per voxel, in parallel (oneTBB); only creating leaves is sequential. The result does
// not depend on the thread count (min is order-independent). Returns the number of voxels set or
// lowered.
// One (block, primitive) pair of the rasteriser: the primitive's band reaches the leaf-sized block.
struct BlockEntry {
    openvdb::Coord block;
    float near2;  // squared distance from the block centre to the primitive's box [m^2]
    std::uint32_t prim;  // the primitive's index
};

// The blocks a primitive's band reaches, handed to `emit` in a fixed order.
class BlocksOfPrimitive {
public:
    BlocksOfPrimitive(const std::vector<RasterTriangle>& prepared, const std::vector<RasterPrimitive>& prims, double r_f,
                      double reach)
        : prepared_(prepared),
          prims_(prims),
          r_f_(r_f),
          reach2_slack_(reach * reach * (1 + 1e-9)),
          // A block whose centre lies farther from every triangle than the reach plus the block's
          // half-diagonal holds no voxel of the band (triangle inequality). This prunes the far
          // corners of a long, thin, oblique triangle's box (a fan between a stopped marker and a
          // moving neighbour), whose box-based count grows with the square of its length.
          block_reach2_((reach + kBlockHalfDiagonal * r_f) * (reach + kBlockHalfDiagonal * r_f) * (1 + 1e-9)) {}

    template <class Emit>
    void operator()(std::size_t q, Emit&& emit) const {
        const RasterPrimitive& pr = prims_[q];
        const int u = pr.u, v = pr.v, axis = pr.axis;
        for (int bi = pr.lo_i[u] >> 3; bi <= pr.hi_i[u] >> 3; ++bi)
            for (int bj = pr.lo_i[v] >> 3; bj <= pr.hi_i[v] >> 3; ++bj) {
                int k0 = pr.lo_i[axis], k1 = pr.hi_i[axis];
                slab_over_column(pr, bi, bj, k0, k1);
                for (int bk = k0 >> 3; bk <= k1 >> 3; ++bk) {
                    openvdb::Coord block;
                    block[u] = bi * kLeafDim;
                    block[v] = bj * kLeafDim;
                    block[axis] = bk * kLeafDim;
                    // Blocks in the corners of the reach box lie farther than the reach from the
                    // primitive's own box: nothing there can enter the band.
                    if (box_gap2(block, pr) > reach2_slack_ || beyond_reach(block, pr)) continue;
                    emit(BlockEntry{block, near2(block, pr), std::uint32_t(q)});
                }
            }
    }

private:
    static constexpr double kBlockHalfDiagonal = 0.8660254037844386 * (kLeafDim - 1);  // sqrt(3)/2 (DIM - 1) voxels

    // The slabs over block column (bi, bj): each plane is linear, so its extremes are at the
    // column's corners (one voxel of slack for the rounding below). A triangle without a slab
    // leaves the range as it is.
    void slab_over_column(const RasterPrimitive& pr, int bi, int bj, int& k0, int& k1) const {
        const int u = pr.u, v = pr.v, axis = pr.axis;
        int s0 = std::numeric_limits<int>::max(), s1 = std::numeric_limits<int>::min();
        for (std::uint32_t t = pr.first; t < pr.first + pr.count; ++t) {
            const RasterTriangle& rt = prepared_[t];
            if (!rt.slab) return;
            double c_lo = std::numeric_limits<double>::max(), c_hi = -c_lo;
            for (int ci = 0; ci < 2; ++ci)
                for (int cj = 0; cj < 2; ++cj) {
                    Vec3 x;
                    x[u] = (bi * kLeafDim + ci * (kLeafDim - 1)) * r_f_;
                    x[v] = (bj * kLeafDim + cj * (kLeafDim - 1)) * r_f_;
                    x[axis] = 0;
                    const double c = rt.n.dot(rt.t[0] - x) / rt.n[axis];
                    c_lo = std::min(c_lo, c);
                    c_hi = std::max(c_hi, c);
                }
            s0 = std::min(s0, int(std::floor((c_lo - rt.half) / r_f_)) - 1);
            s1 = std::max(s1, int(std::ceil((c_hi + rt.half) / r_f_)) + 1);
        }
        k0 = std::max(k0, s0);
        k1 = std::min(k1, s1);
    }
    // Squared distance from the block centre to the primitive's box [m^2]: primitives nearest a
    // block's centre are rasterised first, so most voxels find their best distance early.
    float near2(const openvdb::Coord& block, const RasterPrimitive& pr) const {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
            const double c = (block[a] + 0.5 * (kLeafDim - 1)) * r_f_;
            const double d = std::max({pr.box_lo[a] - c, c - pr.box_hi[a], 0.0});
            d2 += d * d;
        }
        return float(d2);
    }
    // Squared gap between a block's voxel-centre box and the primitive's box [m^2].
    double box_gap2(const openvdb::Coord& block, const RasterPrimitive& pr) const {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) {
            const double lo = block[a] * r_f_, hi = (block[a] + kLeafDim - 1) * r_f_;
            const double d = std::max({pr.box_lo[a] - hi, lo - pr.box_hi[a], 0.0});
            d2 += d * d;
        }
        return d2;
    }
    bool beyond_reach(const openvdb::Coord& block, const RasterPrimitive& pr) const {
        const Vec3 c = (Vec3(block[0], block[1], block[2]).array() + 0.5 * (kLeafDim - 1)).matrix() * r_f_;
        for (std::uint32_t t = pr.first; t < pr.first + pr.count; ++t)
            if (prepared_[t].distance2(c) <= block_reach2_) return false;
        return true;
    }

    const std::vector<RasterTriangle>& prepared_;
    const std::vector<RasterPrimitive>& prims_;
    const double r_f_, reach2_slack_, block_reach2_;
};

// Every (block, primitive) pair, generated per primitive in parallel (each thread into a list of
// its own, joined after) and sorted by block, nearest primitive first. A primitive reaches a block
// at most once, so (block, near2, primitive) is a total order: the sorted result does not depend
// on the thread count or on the order in which the lists were joined.
std::vector<BlockEntry> block_entries(const std::vector<RasterTriangle>& prepared,
                                      const std::vector<RasterPrimitive>& prims, double r_f, double reach) {
    const BlocksOfPrimitive blocks_of(prepared, prims, r_f, reach);
    tbb::enumerable_thread_specific<std::vector<BlockEntry>> lists;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, prims.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<BlockEntry>& list = lists.local();
        for (std::size_t q = r.begin(); q != r.end(); ++q) blocks_of(q, [&](const BlockEntry& x) { list.push_back(x); });
    });
    std::size_t total = 0;
    for (const auto& l : lists) total += l.size();
    std::vector<BlockEntry> entries;
    entries.reserve(total);
    for (const auto& l : lists) entries.insert(entries.end(), l.begin(), l.end());
    tbb::parallel_sort(entries.begin(), entries.end(), [](const BlockEntry& a, const BlockEntry& b) {
        if (a.block != b.block) return a.block < b.block;
        return a.near2 < b.near2 || (a.near2 == b.near2 && a.prim < b.prim);
    });
    return entries;
}

// Writes a batch of block distances into the grid and returns the voxels set or lowered. Leaves
// for the blocks that change anything are made first (sequential: the tree's structure is not
// thread-safe; a block in a tile is split into a leaf only if some value goes below the tile's,
// or the tile is inactive), then filled in parallel.
std::size_t write_blocks(openvdb::FloatGrid::Accessor& acc, const std::vector<BlockDistances>& blocks, std::size_t count,
                         std::vector<openvdb::FloatTree::LeafNodeType*>& leaves) {
    using LeafT = openvdb::FloatTree::LeafNodeType;
    std::size_t written = 0;
    for (std::size_t b = 0; b < count; ++b) {
        const BlockDistances& bd = blocks[b];
        leaves[b] = nullptr;
        if (!bd.count) continue;
        written += bd.count;
        LeafT* leaf = acc.probeLeaf(bd.origin);
        if (!leaf) {
            const float tile = acc.getValue(bd.origin);
            const bool active = acc.isValueOn(bd.origin);
            bool change = false;
            for (std::size_t q = 0; q < bd.count && !change; ++q) change = !active || bd.value[bd.list[q]] < tile;
            if (change) leaf = acc.touchLeaf(bd.origin);
        }
        leaves[b] = leaf;
    }
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t b) {
        LeafT* leaf = leaves[b];
        if (!leaf) return;
        const BlockDistances& bd = blocks[b];
        for (std::size_t q = 0; q < bd.count; ++q) {
            const int off = bd.list[q];
            const float old = leaf->getValue(openvdb::Index(off));
            if (bd.value[off] < old || !leaf->isValueOn(openvdb::Index(off)))
                leaf->setValueOn(openvdb::Index(off), std::min(bd.value[off], old));
        }
    });
    return written;
}

}  // namespace

std::size_t rasterise_triangle_band(openvdb::FloatGrid& grid, const std::vector<Triangle3>& tris, double r_f,
                                    double thick, double reach, const ClosestTriangleValue* finish) {
    std::vector<RasterTriangle> prepared;
    prepared.reserve(tris.size());
    for (const Triangle3& t : tris) prepared.emplace_back(t, r_f, reach);
    const std::vector<RasterPrimitive> prims = raster_primitives(prepared);
    const std::vector<BlockEntry> entries = block_entries(prepared, prims, r_f, reach);
    // The blocks in order, each with its primitives nearest first.
    std::vector<std::size_t> starts;
    for (std::size_t e = 0; e < entries.size(); ++e)
        if (e == 0 || entries[e].block != entries[e - 1].block) starts.push_back(e);
    starts.push_back(entries.size());
    std::vector<std::uint32_t> order(entries.size());
    for (std::size_t e = 0; e < entries.size(); ++e) order[e] = entries[e].prim;
    const std::size_t num_blocks = starts.size() - 1;
    // In batches, so a huge sheet does not hold every block's distances at once.
    constexpr std::size_t kBatch = 4096;
    std::vector<BlockDistances> blocks(std::min(num_blocks, kBatch));
    std::vector<openvdb::FloatTree::LeafNodeType*> leaves(blocks.size(), nullptr);
    auto acc = grid.getAccessor();
    std::size_t written = 0;
    // Polled per block (a large sheet, e.g. levelset.crack_planar's disk, has tens of thousands);
    // a cancelled grid is half written, and dropped with the node that records it.
    const CancelToken cancel = CancelToken::current();
    cancel.poll();
    for (std::size_t first = 0; first < num_blocks; first += kBatch) {
        const std::size_t count = std::min(kBatch, num_blocks - first);
        tbb::parallel_for(std::size_t(0), count, [&](std::size_t b) {
            cancel.poll();
            const std::size_t g = first + b;
            blocks[b].origin = entries[starts[g]].block;
            rasterise_block(blocks[b], prepared, prims, order.data() + starts[g], order.data() + starts[g + 1],
                            grid.constTree().probeConstLeaf(blocks[b].origin), r_f, thick, reach, finish);
        });
        written += write_blocks(acc, blocks, count, leaves);
    }
    return written;
}

namespace {

std::size_t rasterise_triangles(openvdb::FloatGrid& grid, const std::vector<Triangle3>& tris, double r_f,
                                double half_width) {
    const double thick = crack_half_thickness(r_f);
    return rasterise_triangle_band(grid, tris, r_f, thick, half_width * r_f + thick);  // d < reach: in the band
}

openvdb::FloatGrid::Ptr new_crack_grid(double r_f, double half_width) {
    ensure_openvdb_initialized();
    auto g = openvdb::FloatGrid::create(float(half_width * r_f));
    g->setTransform(openvdb::math::Transform::createLinearTransform(r_f));
    g->setGridClass(openvdb::GRID_LEVEL_SET);
    return g;
}

// Trilinear sampling with a private accessor (one per thread). Unregistered: a registered
// accessor inserts itself into the tree's concurrent hash map on construction and removes itself
// on destruction, and test_marker makes one per crack per marker per sub-step (with 16 cracks,
// cube_compressive spent 5 % of its run there). The grids do not change while it lives.
struct FieldSampler {
    explicit FieldSampler(const LevelSet& ls) : acc(grid_of(ls).tree()), inv(1.0 / ls.voxel_size), h(ls.voxel_size) {}
    double value(const Vec3& p) const {
        return openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(p.x() * inv, p.y() * inv, p.z() * inv));
    }
    Vec3 gradient(const Vec3& p) const {
        Vec3 g;
        for (int a = 0; a < 3; ++a) {
            Vec3 e = Vec3::Zero();
            e[a] = 0.5 * h;
            g[a] = (value(p + e) - value(p - e)) / h;
        }
        return g;
    }
    openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc;
    double inv, h;
};

}  // namespace

std::vector<Triangle3> strip_triangles(const FrontMotion& m) {
    if (m.p0.size() != m.p1.size())
        throw std::invalid_argument("front motion has " + std::to_string(m.p0.size()) + " start and " +
                                    std::to_string(m.p1.size()) + " end positions; they must match");
    std::vector<Triangle3> tris;
    const std::size_t n = m.p0.size();
    auto still = [&](std::size_t i) { return m.p0[i] == m.p1[i]; };
    if (n == 1) {
        if (!still(0)) tris.push_back({m.p0[0], m.p1[0], m.p1[0]});  // a lone marker sweeps a segment
        return tris;
    }
    const std::size_t pairs = m.closed ? n : (n == 0 ? 0 : n - 1);
    for (std::size_t i = 0; i < pairs; ++i) {
        const std::size_t j = (i + 1) % n;
        // Two stopped markers sweep nothing: their segment is the end edge of an earlier strip.
        // (Late in a run most markers have stopped; rasterising their segments every sub-step
        // cost more than the moving part of the front.)
        if (still(i) && still(j)) continue;
        // One stopped marker: the quad collapses to a single fan triangle (its other half would
        // be a segment on the fan's edge, which changes no distance).
        if (still(i)) {
            tris.push_back({m.p0[i], m.p0[j], m.p1[j]});
            continue;
        }
        if (still(j)) {
            tris.push_back({m.p0[i], m.p0[j], m.p1[i]});
            continue;
        }
        tris.push_back({m.p0[i], m.p0[j], m.p1[j]});
        tris.push_back({m.p0[i], m.p1[j], m.p1[i]});
    }
    return tris;
}

std::vector<Triangle3> surface_closure_triangles(const FrontMotion& m, const LevelSet& object) {
    std::vector<Triangle3> tris;
    const std::size_t n = m.p0.size();
    const double r_f = object.voxel_size;
    const std::size_t pairs = m.closed ? n : (n == 0 ? 0 : n - 1);
    for (std::size_t i = 0; i < pairs; ++i) {
        const std::size_t j = (i + 1) % n;
        const bool still_i = m.p0[i] == m.p1[i], still_j = m.p0[j] == m.p1[j];
        if (still_i == still_j) continue;                       // not a fan
        const std::size_t a = still_i ? i : j, b = still_i ? j : i;  // a stopped, b moving
        if (!(sample(object, m.p0[a]) > -2 * r_f) || !(sample(object, m.p1[b]) > -2 * r_f)) continue;
        const Vec3 chord = m.p1[b] - m.p0[a];
        const Vec3 inward = m.p0[b] - m.p0[a];
        const Vec3 plane = chord.cross(inward);
        if (!(plane.norm() > 1e-12 * chord.norm() * inward.norm())) continue;
        Vec3 out = chord.cross(plane).normalized();
        if (out.dot(inward) > 0) out = -out;
        // Between a chord whose ends both lie at the surface and a convex corner of the surface, the
        // plane is at most half the chord wide (a right-angled corner); further out it is not closed.
        const double reach = 0.5 * chord.norm();
        const int samples = std::max(1, int(std::ceil(chord.norm() / r_f)));
        std::vector<Vec3> base, tip;
        bool any = false;
        for (int k = 0; k <= samples; ++k) {
            const Vec3 c = m.p0[a] + (double(k) / samples) * chord;
            double width = 0;
            for (double t = 0; t <= reach; t += 0.5 * r_f)
                if (sample(object, c + t * out) > 0) {
                    width = t + r_f;
                    break;
                }
            any = any || width > 0;
            base.push_back(c);
            tip.push_back(c + width * out);
        }
        if (!any) continue;
        for (int k = 0; k < samples; ++k) {
            tris.push_back({base[k], base[k + 1], tip[k + 1]});
            tris.push_back({base[k], tip[k + 1], tip[k]});
        }
    }
    return tris;
}

namespace {

// test_marker with, per crack, a box [m] holding every voxel whose value may be negative (none
// given: no box). Elsewhere a grid's values are positive, and a trilinear sample reads voxels within
// r_f of the point, so test (b) skips a crack whose box lies farther than r_f from the marker's path:
// the same answer without sampling (with 16 cracks most are far from any one marker).
MarkerTest test_marker_in_boxes(const LevelSet* object, const std::vector<LevelSet>& cracks,
                                const std::vector<Eigen::AlignedBox3d>& boxes, int own, const Vec3& p0, const Vec3& p1) {
    MarkerTest r;
    const Vec3 d = p1 - p0;
    const double len = d.norm();
    // (a) left the object.
    if (object && sample(*object, p1) > 0) {
        r.hit = MarkerHit::left_object;
        return r;
    }
    if (cracks.empty()) return r;
    const double r_f = cracks.front().voxel_size;
    const int steps = std::max(1, int(std::ceil(len / (0.25 * r_f))));
    // The path's box widened by the trilinear stencil (and a margin far above rounding).
    Eigen::AlignedBox3d path(p0.cwiseMin(p1), p0.cwiseMax(p1));
    const Vec3 reach = Vec3::Constant(1.01 * r_f);
    path = Eigen::AlignedBox3d(path.min() - reach, path.max() + reach);
    // (b) crossed another crack anywhere on (0, 1].
    for (std::size_t c = 0; c < cracks.size(); ++c) {
        if (int(c) == own || cracks[c].empty()) continue;
        if (c < boxes.size() && !boxes[c].intersects(path)) continue;
        FieldSampler f(cracks[c]);
        for (int s = 1; s <= steps; ++s) {
            const double alpha = double(s) / steps;
            if (f.value(p0 + alpha * d) < 0) {
                r.hit = MarkerHit::crossed_crack;
                r.other_crack = int(c);
                r.alpha = alpha;
                return r;
            }
        }
    }
    // (c) self-intersection, eq. (6.2): far enough from p0 along a 45-degree cone, close to the
    // crack, and moving towards it.
    if (own >= 0 && std::size_t(own) < cracks.size() && !cracks[own].empty() && len > 0) {
        FieldSampler f(cracks[own]);
        const double phi0 = f.value(p0);
        const double sin45 = std::sqrt(0.5);
        // A marker on its own crack (Phi_f(p0) < 0, the usual case: p0 lies on the recorded front
        // edge) can only run back into the crack after its path has left it, i.e. after some
        // point with Phi_f(x) >= phi(x), the growth eq. (6.2) expects when moving away. Without
        // this, a marker whose path stays inside the recorded sheet (Phi_f flat along it: a
        // marker behind the recorded front, between neighbours that ran ahead, or on the chord
        // of a user crack's curved edge) was stopped whenever trilinear noise tilted the
        // gradient against it: at a front edge the trilinear Phi_f(p0) is about -0.45 r_f, not
        // the exact -0.87 r_f, so phi > 0 already 0.65 r_f along a step of at most r_f.
        bool moved_away = phi0 >= 0;
        for (int s = 1; s <= steps; ++s) {
            const double alpha = double(s) / steps;
            const Vec3 x = p0 + alpha * d;
            const double cone = phi0 + alpha * len * sin45;
            const double phi_x = f.value(x);
            const bool was_away = moved_away;
            if (phi_x >= cone) moved_away = true;
            if (!was_away) continue;
            if (cone <= 0) continue;
            if (phi_x >= crack_half_thickness(r_f)) continue;  // Phi_f(x) < sqrt(3) r_f / 2
            if (f.gradient(x).dot(d) < 0) {
                r.hit = MarkerHit::self_intersection;
                r.alpha = alpha;
                return r;
            }
        }
    }
    return r;
}

}  // namespace

MarkerTest test_marker(const LevelSet* object, const std::vector<LevelSet>& cracks, int own, const Vec3& p0,
                       const Vec3& p1) {
    return test_marker_in_boxes(object, cracks, {}, own, p0, p1);
}

struct CrackRecorder::Impl {
    double r_f = 0, half_width = 3;
    std::vector<openvdb::FloatGrid::Ptr> grids;
    // Per grid, a box [m] holding every voxel centre whose value may be negative (Phi_f < 0 lies
    // within sqrt(3) r_f / 2 of a recorded triangle): the start grid's leaves and active tiles, then
    // each recorded triangle's box widened by r_f. test (b) of fig. 27 skips a crack whose box lies
    // farther than r_f from the marker's path (test_marker_in_boxes).
    std::vector<Eigen::AlignedBox3d> boxes;
};

CrackRecorder::CrackRecorder(double r_f, double half_width) : impl_(std::make_unique<Impl>()) {
    if (!(r_f > 0)) throw std::invalid_argument("crack voxel size r_f must be positive");
    impl_->r_f = r_f;
    impl_->half_width = half_width;
}
CrackRecorder::CrackRecorder(const CrackLevelSets& start) : CrackRecorder(start.voxel_size, start.half_width) {
    for (const LevelSet& ls : start.cracks) {
        if (std::abs(ls.voxel_size - start.voxel_size) > 1e-12 * start.voxel_size)
            throw std::invalid_argument("crack grids have different voxel sizes");
        impl_->grids.push_back(grid_of(ls).deepCopy());
        Eigen::AlignedBox3d box;
        openvdb::CoordBBox b;
        if (impl_->grids.back()->tree().evalLeafBoundingBox(b))
            box = Eigen::AlignedBox3d(Vec3(b.min().x(), b.min().y(), b.min().z()) * impl_->r_f,
                                      Vec3(b.max().x(), b.max().y(), b.max().z()) * impl_->r_f);
        impl_->boxes.push_back(box);
    }
}
CrackRecorder::~CrackRecorder() = default;
CrackRecorder::CrackRecorder(CrackRecorder&&) noexcept = default;
CrackRecorder& CrackRecorder::operator=(CrackRecorder&&) noexcept = default;

int CrackRecorder::add_crack() {
    impl_->grids.push_back(new_crack_grid(impl_->r_f, impl_->half_width));
    impl_->grids.back()->setName("crack" + std::to_string(impl_->grids.size() - 1));
    impl_->boxes.emplace_back();  // empty
    return int(impl_->grids.size()) - 1;
}
std::size_t CrackRecorder::num_cracks() const { return impl_->grids.size(); }
double CrackRecorder::voxel_size() const { return impl_->r_f; }

std::size_t CrackRecorder::add_triangles(int crack, const std::vector<Triangle3>& tris) {
    if (crack < 0 || std::size_t(crack) >= impl_->grids.size())
        throw std::out_of_range("crack index " + std::to_string(crack) + " out of range");
    for (const Triangle3& t : tris)
        for (const Vec3& p : t)
            if (!p.allFinite()) throw std::invalid_argument("crack triangle with a non-finite coordinate");
    Eigen::AlignedBox3d& box = impl_->boxes[std::size_t(crack)];
    const Vec3 widen = Vec3::Constant(impl_->r_f);
    for (const Triangle3& t : tris)
        for (const Vec3& p : t) {
            box.extend(p - widen);
            box.extend(p + widen);
        }
    return rasterise_triangles(*impl_->grids[crack], tris, impl_->r_f, impl_->half_width);
}

std::vector<std::vector<MarkerTest>> CrackRecorder::record_substep(const std::vector<FrontMotion>& motions,
                                                                   const LevelSet* object,
                                                                   std::size_t* voxels_written) {
    if (motions.size() != impl_->grids.size())
        throw std::invalid_argument("record_substep got " + std::to_string(motions.size()) + " front motions for " +
                                    std::to_string(impl_->grids.size()) + " cracks");
    for (const FrontMotion& m : motions)
        if (m.p0.size() != m.p1.size()) throw std::invalid_argument("front motion with mismatched p0/p1 sizes");
    // Phase 1 (read-only): test against the grids up to the previous sub-step.
    std::vector<LevelSet> views;
    for (auto& g : impl_->grids) views.push_back(wrap_grid(g, impl_->r_f, impl_->half_width));
    std::vector<std::vector<MarkerTest>> tests(motions.size());
    tbb::parallel_for(std::size_t(0), motions.size(), [&](std::size_t c) {
        const FrontMotion& m = motions[c];
        tests[c].resize(m.p0.size());
        tbb::parallel_for(std::size_t(0), m.p0.size(), [&](std::size_t i) {
            if (m.p0[i] != m.p1[i]) tests[c][i] = test_marker_in_boxes(object, views, impl_->boxes, int(c), m.p0[i], m.p1[i]);
        });
    });
    views.clear();
    // Phase 2: each crack writes only its own grid, so cracks run in parallel.
    std::vector<std::size_t> written(motions.size(), 0);
    tbb::parallel_for(std::size_t(0), motions.size(), [&](std::size_t c) {
        std::vector<Triangle3> tris = strip_triangles(motions[c]);
        if (object) {
            const std::vector<Triangle3> closure = surface_closure_triangles(motions[c], *object);
            tris.insert(tris.end(), closure.begin(), closure.end());
        }
        written[c] = add_triangles(int(c), tris);
    });
    if (voxels_written) {
        *voxels_written = 0;
        for (std::size_t w : written) *voxels_written += w;
    }
    return tests;
}

CrackLevelSets CrackRecorder::snapshot() const {
    CrackLevelSets s;
    s.voxel_size = impl_->r_f;
    s.half_width = impl_->half_width;
    for (const auto& g : impl_->grids) s.cracks.push_back(wrap_grid(g->deepCopy(), impl_->r_f, impl_->half_width));
    return s;
}

CrackLevelSets CrackRecorder::release() {
    CrackLevelSets s;
    s.voxel_size = impl_->r_f;
    s.half_width = impl_->half_width;
    for (auto& g : impl_->grids) s.cracks.push_back(wrap_grid(std::move(g), impl_->r_f, impl_->half_width));
    impl_->grids.clear();
    return s;
}

LevelSet planar_disk_crack(const Vec3& center, const Vec3& normal, double radius, double r_f, double half_width) {
    if (!(radius > 0) || !std::isfinite(radius))
        throw std::invalid_argument("planar crack radius must be positive, got " + graph::format_quantity(radius, "m"));
    if (!(normal.norm() > 0) || !normal.allFinite())
        throw std::invalid_argument("planar crack normal must be a non-zero vector");
    if (!center.allFinite()) throw std::invalid_argument("planar crack centre must be finite");
    const Vec3 n = normal.normalized();
    Vec3 e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 e2 = n.cross(e1);
    // Chord sag R (1 - cos(pi/N)) <= r_f/10; rings about 16 voxels apart keep triangles compact.
    const double sag = std::min(0.1 * r_f / radius, 1.0);
    const int sectors = std::clamp(int(std::ceil(M_PI / std::acos(1 - sag))), 8, 4096);
    const int rings = std::clamp(int(std::ceil(radius / (16 * r_f))), 1, 4096);
    std::vector<Triangle3> tris;
    auto point = [&](int ring, int sector) {
        const double r = radius * ring / rings, a = 2 * M_PI * sector / sectors;
        return Vec3(center + r * (std::cos(a) * e1 + std::sin(a) * e2));
    };
    for (int ring = 0; ring < rings; ++ring)
        for (int s = 0; s < sectors; ++s) {
            const int s1 = (s + 1) % sectors;
            if (ring == 0) {
                tris.push_back({center, point(1, s), point(1, s1)});
            } else {
                tris.push_back({point(ring, s), point(ring + 1, s), point(ring + 1, s1)});
                tris.push_back({point(ring, s), point(ring + 1, s1), point(ring, s1)});
            }
        }
    CrackRecorder rec(r_f, half_width);
    rec.add_crack();
    rec.add_triangles(0, tris);
    return rec.release().cracks.front();
}

LevelSet reference_strip_level_set(const std::vector<Triangle3>& tris, double r_f, double half_width) {
    ensure_openvdb_initialized();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> faces;
    for (const Triangle3& t : tris) {
        const unsigned base = unsigned(points.size());
        for (const Vec3& p : t) points.emplace_back(float(p.x()), float(p.y()), float(p.z()));
        faces.emplace_back(base, base + 1, base + 2);
    }
    const double thick = crack_half_thickness(r_f);
    auto xform = openvdb::math::Transform::createLinearTransform(r_f);
    // Band: distances up to half_width r_f + thickness, so d - thick covers the same band.
    auto g = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, points, faces, {},
                                                                              float(half_width + thick / r_f));
    const float t = float(thick);
    for (auto it = g->beginValueOn(); it; ++it) it.setValue(*it - t);
    return wrap_grid(g, r_f, half_width);
}

}  // namespace cf
