// OpenVDB translation unit: the cells of the surface mesher (fragment_cells.hpp).
//
// No fragment's distance is rebuilt: psi_i needs the distance to the other fragments only where
// two fragments come within a few voxels of each other (the crack gaps), so one pass over the
// fragments' leaves finds those places (the contact zone) and, for its voxels only, the nearest
// fragments by a search of a small ball of labelled voxels, on dense blocks copied per leaf: per
// fragment label, a min-plus filter over the leaf's rows that vectorises (the per-voxel search
// over every ball offset, kept as the reference, cost 18 % of a thesis case's CPU with the surface
// mesher). Everywhere else a cell is the object offset by the margin.
#include "nodes/segment/fragment_cells.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/domain/isa_clones.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace cf {

namespace {

using openvdb::Coord;
using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using IntTree = openvdb::Int32Tree;
using IntLeaf = IntTree::LeafNodeType;
using MaskTree = openvdb::MaskTree;
constexpr int kDim = int(FloatLeaf::DIM);

// The nearest fragments of a contact-zone voxel: kNearest distinct labels by ascending distance
// [m] (label -1: none within the search radius). Four, since four fragments meet along the line
// where two cracks cross.
constexpr int kNearest = 4;
struct Nearest {
    std::array<int, kNearest> label;
    std::array<float, kNearest> d;
    Nearest() {
        label.fill(-1);
        d.fill(0);
    }
    void offer(int l, float dist) {
        for (int k = 0; k < kNearest; ++k)
            if (label[std::size_t(k)] == l) {
                if (dist < d[std::size_t(k)]) {
                    d[std::size_t(k)] = dist;
                    settle(k);
                }
                return;
            }
        constexpr std::size_t last = kNearest - 1;
        if (label[last] >= 0 && !(dist < d[last] || (dist == d[last] && l < label[last]))) return;
        label[last] = l;
        d[last] = dist;
        settle(int(last));
    }
    // Restores the order after entry k decreased (ties: the smaller label first, so the result
    // does not depend on the order of the offers).
    void settle(int k) {
        while (k > 0) {
            const std::size_t a = std::size_t(k - 1), b = std::size_t(k);
            const bool swap = label[a] < 0 || d[b] < d[a] || (d[b] == d[a] && label[b] < label[a]);
            if (!swap) break;
            std::swap(label[a], label[b]);
            std::swap(d[a], d[b]);
            --k;
        }
    }
};

constexpr int kLeafVoxels = kDim * kDim * kDim;

// The offsets of the search ball (|o| <= R voxels) and their lengths [m], in two layouts: every
// offset (the per-voxel search) and, per (i, j) column, the run k = -K..K (the per-label filter).
struct BallOffsets {
    struct Column {
        int i, j, half;             // the column's offsets (i, j, -half..half)
        std::size_t first_length;   // its lengths start here in `column_length`
    };
    std::vector<Coord> offset;
    std::vector<float> length;
    std::vector<Column> columns;
    std::vector<float> column_length;
    BallOffsets(int R, double voxel) {
        auto len = [&](int i, int j, int k) { return float(std::sqrt(double(i * i + j * j + k * k)) * voxel); };
        for (int i = -R; i <= R; ++i)
            for (int j = -R; j <= R; ++j) {
                int half = -1;
                for (int k = -R; k <= R; ++k)
                    if (i * i + j * j + k * k <= R * R) {
                        offset.emplace_back(i, j, k);
                        length.push_back(len(i, j, k));
                        half = std::max(half, k);
                    }
                if (half < 0) continue;
                columns.push_back({i, j, half, column_length.size()});
                for (int k = -half; k <= half; ++k) column_length.push_back(len(i, j, k));
            }
    }
};

// d[x, y, z] = min over ball offsets o of |o| + value[(x, y, z) + R + o] for the leaf's rows (x, y)
// marked active, `value` a dense B^3 block (B = 8 + 2R) starting R voxels before the leaf. The z
// run of a row is contiguous, so the inner loop is 8 lanes of add and min (exact IEEE operations:
// every clone gives the same bits).
typedef float Lanes __attribute__((vector_size(kDim * sizeof(float))));  // one leaf row, z = 0..7
CF_AVX2_CLONE void ball_min_rows(const BallOffsets& ball, const float* value, int B, int R, const bool* row_active,
                                 float* d) {
    for (int x = 0; x < kDim; ++x)
        for (int y = 0; y < kDim; ++y) {
            if (!row_active[x * kDim + y]) continue;
            Lanes acc = Lanes{} + std::numeric_limits<float>::infinity();
            for (const BallOffsets::Column& c : ball.columns) {
                const float* row = value + ((x + R + c.i) * B + (y + R + c.j)) * B + R;
                const float* length = ball.column_length.data() + c.first_length;
                for (int k = -c.half; k <= c.half; ++k) {
                    Lanes v;
                    std::memcpy(&v, row + k, sizeof v);
                    const Lanes t = v + length[k + c.half];
                    acc = t < acc ? t : acc;
                }
            }
            std::memcpy(d + (x * kDim + y) * kDim, &acc, sizeof acc);
        }
}

// The labels (-1: none) and each labelled voxel's own fragment value in the dense block of side B
// at `lo`, copied leaf by leaf; `labels` gets the distinct labels met, ascending.
void copy_block(const openvdb::tree::ValueAccessor<const IntTree>& label_acc, const std::vector<LevelSet>& phi,
                const Coord& lo, int B, std::vector<int>& lab, std::vector<float>& val, std::vector<int>& labels) {
    std::fill(lab.begin(), lab.end(), -1);
    labels.clear();
    const Coord hi = lo + Coord(B - 1);
    auto leaf_start = [](int c) { return c & ~(kDim - 1); };
    std::vector<std::pair<int, const FloatLeaf*>> phi_leaf;  // per label met in this leaf
    for (int ox = leaf_start(lo[0]); ox <= hi[0]; ox += kDim)
        for (int oy = leaf_start(lo[1]); oy <= hi[1]; oy += kDim)
            for (int oz = leaf_start(lo[2]); oz <= hi[2]; oz += kDim) {
                const Coord origin(ox, oy, oz);
                const IntLeaf* ll = label_acc.probeConstLeaf(origin);
                if (!ll) continue;
                phi_leaf.clear();
                const Coord a = Coord::maxComponent(lo, origin), b = Coord::minComponent(hi, origin + Coord(kDim - 1));
                for (int x = a[0]; x <= b[0]; ++x)
                    for (int y = a[1]; y <= b[1]; ++y)
                        for (int z = a[2]; z <= b[2]; ++z) {
                            const Coord c(x, y, z);
                            const openvdb::Index n = IntLeaf::coordToOffset(c);
                            const int l = ll->getValue(n);
                            if (l < 0) continue;
                            const std::size_t at = std::size_t(((x - lo[0]) * B + (y - lo[1])) * B + (z - lo[2]));
                            lab[at] = l;
                            auto it = std::find_if(phi_leaf.begin(), phi_leaf.end(), [&](const auto& e) { return e.first == l; });
                            if (it == phi_leaf.end()) {  // a label new to this leaf, perhaps to the block
                                phi_leaf.emplace_back(l, grid_of(phi[std::size_t(l)]).tree().probeConstLeaf(origin));
                                it = phi_leaf.end() - 1;
                                if (std::find(labels.begin(), labels.end(), l) == labels.end()) labels.push_back(l);
                            }
                            val[at] = it->second ? it->second->getValue(n) : grid_of(phi[std::size_t(l)]).tree().getValue(c);
                        }
            }
    std::sort(labels.begin(), labels.end());
}

// Leaves of all fragments grouped by origin (fragment order within a group).
struct LeafRef {
    Coord origin;
    int fragment;
    const FloatLeaf* leaf;
};

}  // namespace

struct FragmentCells::Grids {
    std::vector<LevelSet> phi;           // the fragments' grids (shared handles)
    LevelSet object;                     // the uncut object
    IntTree::Ptr label;                  // fragment of every inside leaf voxel (-1: none)
    IntTree::Ptr zone;                   // contact zone: index into `nearest`
    std::vector<Nearest> nearest;
    double voxel = 0, margin = 0;        // [m]
    int margin_voxels = 2, search = 3;   // search radius [voxels]
    float cap = 0;                       // [m] the distance of a fragment not found in the search
};

FragmentCells::FragmentCells(const Fragments& f, double margin_voxels, NearestSearch search) : g_(std::make_unique<Grids>()) {
    if (!(margin_voxels >= 1 && margin_voxels <= 8))
        throw std::invalid_argument("cell margin must lie in [1, 8] voxels");
    if (f.object.empty())
        throw std::invalid_argument("the surface mesher needs the uncut object with the fragments (segment.fragments "
                                    "gives it); or set mesher: levelset");
    ensure_openvdb_initialized();
    const CancelToken cancel = CancelToken::current();
    Grids& g = *g_;
    g.voxel = f.voxel_size;
    g.margin_voxels = int(std::ceil(margin_voxels));
    g.margin = margin_voxels * f.voxel_size;
    // Outside the object a cell reaches `margin`: the nearest fragments must be known that far out
    // and beyond (the fragment across a gap is a gap further), or the capped distances bend the
    // cells' faces where they meet the offset surface, and dual contouring folds them there.
    g.search = g.margin_voxels + 2;
    g.cap = float(g.search * g.voxel);
    g.object = f.object;
    for (const Fragment& fr : f.fragments) g.phi.push_back(fr.grid);

    // 1. The fragments' leaves by origin.
    std::vector<LeafRef> refs;
    for (std::size_t k = 0; k < f.fragments.size(); ++k)
        for (auto it = grid_of(f.fragments[k].grid).tree().cbeginLeaf(); it; ++it)
            refs.push_back({it->origin(), int(k), &*it});
    std::sort(refs.begin(), refs.end(), [](const LeafRef& a, const LeafRef& b) {
        return a.origin < b.origin || (a.origin == b.origin && a.fragment < b.fragment);
    });
    std::vector<std::size_t> group_start;
    for (std::size_t r = 0; r < refs.size(); ++r)
        if (r == 0 || refs[r].origin != refs[r - 1].origin) group_start.push_back(r);
    group_start.push_back(refs.size());
    const std::size_t groups = group_start.size() - 1;

    // 2. Per origin: the label of every inside voxel (the first fragment holding it inside), and
    // the seeds of the contact zone: voxels a fragment's grid holds outside it that lie inside the
    // object (crack gaps, removed spindles and specks) or that another fragment's grid also holds.
    std::vector<std::unique_ptr<IntLeaf>> label_leaves(groups);
    std::vector<std::unique_ptr<MaskTree::LeafNodeType>> seed_leaves(groups);
    const openvdb::FloatGrid& object = grid_of(g.object);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, groups, 64), [&](const tbb::blocked_range<std::size_t>& r) {
        cancel.poll();
        auto obj = object.getConstAccessor();
        for (std::size_t q = r.begin(); q != r.end(); ++q) {
            const Coord origin = refs[group_start[q]].origin;
            auto lab = std::make_unique<IntLeaf>(origin, -1, false);
            auto seeds = std::make_unique<MaskTree::LeafNodeType>(origin, false, false);
            bool any_seed = false;
            for (std::size_t a = group_start[q]; a < group_start[q + 1]; ++a) {
                const FloatLeaf& leaf = *refs[a].leaf;
                for (auto v = leaf.cbeginValueOn(); v; ++v) {
                    const openvdb::Index n = v.pos();
                    if (*v < 0) {
                        if (!lab->isValueOn(n)) lab->setValueOn(n, refs[a].fragment);
                        continue;
                    }
                    bool seed = obj.getValue(v.getCoord()) < 0;
                    for (std::size_t b = group_start[q]; !seed && b < group_start[q + 1]; ++b)
                        seed = b != a && refs[b].leaf->isValueOn(n);
                    if (seed) {
                        seeds->setValueOn(n);
                        any_seed = true;
                    }
                }
            }
            if (!lab->isEmpty()) label_leaves[q] = std::move(lab);
            if (any_seed) seed_leaves[q] = std::move(seeds);
        }
    });
    g.label = std::make_shared<IntTree>(-1);
    MaskTree zone_mask(false);
    for (std::size_t q = 0; q < groups; ++q) {
        if (label_leaves[q]) g.label->addLeaf(label_leaves[q].release());
        if (seed_leaves[q]) zone_mask.addLeaf(seed_leaves[q].release());
    }
    cancel.poll();

    // 3. The contact zone: every voxel of a cell's domain (its fragment's grid dilated by
    // margin + 1 voxels) within reach of another fragment is within margin + 2 voxels of a seed.
    openvdb::tools::dilateActiveValues(zone_mask, g.margin_voxels + 2, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::IGNORE_TILES);
    g.zone = std::make_shared<IntTree>(-1);
    g.zone->topologyUnion(zone_mask);
    std::vector<IntLeaf*> zone_leaves;
    g.zone->getNodes(zone_leaves);  // in a fixed order: the indices do not depend on the threads
    std::vector<std::size_t> first(zone_leaves.size() + 1, 0);
    for (std::size_t l = 0; l < zone_leaves.size(); ++l) first[l + 1] = first[l] + zone_leaves[l]->onVoxelCount();
    g.nearest.assign(first.back(), Nearest{});

    // 4. The nearest fragments of every zone voxel x: d_k(x) = min over labelled voxels y of
    // fragment k in the ball of radius `search` of |x - y| + phi_k(y). The ball of radius
    // -phi_k(y) about y lies in fragment k, so each term bounds the distance from above; it is
    // exact for the y on the normal through x, and both sides of a gap are estimated alike, so
    // the bisector is symmetric. Labels and values are copied per leaf into a dense block.
    const BallOffsets ball(g.search, g.voxel);
    const int R = g.search;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, zone_leaves.size(), 4), [&](const tbb::blocked_range<std::size_t>& r) {
        cancel.poll();
        const int B = kDim + 2 * R;
        std::vector<int> lab(std::size_t(B * B * B));
        std::vector<float> val(std::size_t(B * B * B)), of_label(val.size());
        std::vector<int> labels;
        std::array<float, kLeafVoxels> d{};
        std::array<bool, kDim * kDim> row_active{};
        const openvdb::tree::ValueAccessor<const IntTree> label_acc(*g.label);
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            IntLeaf& leaf = *zone_leaves[l];
            const Coord lo = leaf.origin() - Coord(R);
            copy_block(label_acc, g.phi, lo, B, lab, val, labels);
            std::size_t index = first[l];
            row_active.fill(false);
            for (auto v = leaf.beginValueOn(); v; ++v, ++index) {
                v.setValue(int(index));
                row_active[v.pos() / kDim] = true;
            }
            if (labels.empty()) continue;
            if (search == NearestSearch::per_voxel) {
                for (auto v = leaf.beginValueOn(); v; ++v) {
                    Nearest& near = g.nearest[std::size_t(v.getValue())];
                    const Coord x = v.getCoord() - lo;
                    for (std::size_t o = 0; o < ball.offset.size(); ++o) {
                        const Coord y = x + ball.offset[o];
                        const std::size_t at = std::size_t((y[0] * B + y[1]) * B + y[2]);
                        if (lab[at] >= 0) near.offer(lab[at], ball.length[o] + val[at]);
                    }
                }
                continue;
            }
            // Per label, the minimum over the ball as a min-plus filter of the label's values
            // (+inf elsewhere) over whole rows of the leaf; offering each label's minimum gives the
            // same kNearest as offering every term (Nearest keeps the least (d, label) pairs).
            for (const int k : labels) {
                for (std::size_t at = 0; at < val.size(); ++at)
                    of_label[at] = lab[at] == k ? val[at] : std::numeric_limits<float>::infinity();
                ball_min_rows(ball, of_label.data(), B, R, row_active.data(), d.data());
                for (auto v = leaf.beginValueOn(); v; ++v) {
                    const float dk = d[v.pos()];
                    if (dk < std::numeric_limits<float>::infinity()) g.nearest[std::size_t(v.getValue())].offer(k, dk);
                }
            }
        }
    });
}

FragmentCells::~FragmentCells() = default;

double FragmentCells::margin() const { return g_->margin; }

LevelSet FragmentCells::cell(std::size_t i, const LevelSet* bound) const {
    const Grids& g = *g_;
    if (bound && !bound->empty() && std::abs(bound->voxel_size - g.voxel) > 1e-9 * g.voxel)
        throw std::invalid_argument("a cell's bound must have the fragments' voxel size");
    const openvdb::FloatGrid* bound_grid = bound && !bound->empty() ? &grid_of(*bound) : nullptr;
    const openvdb::FloatGrid& phi_i = grid_of(g.phi.at(i));
    // The domain: the fragment's grid (its inside tiles stay inside) and margin + 1 voxels more,
    // so the offset surface has values on both sides.
    openvdb::FloatGrid::Ptr psi = phi_i.deepCopy();
    openvdb::tools::dilateActiveValues(psi->tree(), g.margin_voxels + 1, openvdb::tools::NN_FACE_EDGE_VERTEX,
                                       openvdb::tools::IGNORE_TILES);
    const int self = int(i);
    const float margin = float(g.margin), cap = g.cap, step = float(g.voxel);
    openvdb::tree::LeafManager<openvdb::FloatTree> leaves(psi->tree());
    leaves.foreach([&](FloatLeaf& leaf, std::size_t) {
        auto obj = grid_of(g.object).getConstAccessor();
        openvdb::tree::ValueAccessor<const IntTree> zone(*g.zone), label(*g.label);
        std::unique_ptr<openvdb::FloatGrid::ConstAccessor> outer_cell;
        if (bound_grid) outer_cell = std::make_unique<openvdb::FloatGrid::ConstAccessor>(bound_grid->getConstAccessor());
        for (auto v = leaf.beginValueOn(); v; ++v) {
            const Coord c = v.getCoord();
            const float outer = obj.getValue(c) - margin;  // the object offset by the margin
            float bisector;                                 // (d_i - min_{j != i} d_j) / 2
            int at = -1;
            if (zone.probeValue(c, at)) {
                const Nearest& n = g.nearest[std::size_t(at)];
                float own = cap + step, other = cap;  // not found: farther than the search reaches
                for (int k = 0; k < kNearest; ++k) {
                    if (n.label[std::size_t(k)] < 0) break;
                    if (n.label[std::size_t(k)] == self) own = std::min(own, n.d[std::size_t(k)]);
                    else other = std::min(other, n.d[std::size_t(k)]);
                }
                bisector = 0.5f * (own - other);
            } else {
                // Beyond the zone only fragment i (or nothing) is near: its own unless another
                // fragment holds the voxel.
                const int l = label.getValue(c);
                bisector = (l < 0 || l == self) ? -0.5f * cap : 0.5f * cap;
            }
            v.setValue(outer_cell ? std::max({bisector, outer, outer_cell->getValue(c)}) : std::max(bisector, outer));
        }
    });
    return wrap_grid(psi, g.voxel, g.phi[i].half_width);
}

SurfaceMesh FragmentCells::cell_mesh(std::size_t i, double adaptivity) const {
    return level_set_to_mesh(cell(i), adaptivity);
}

}  // namespace cf
