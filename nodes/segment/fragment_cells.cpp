// OpenVDB translation unit: the cells of the surface mesher (fragment_cells.hpp).
//
// No fragment's distance is rebuilt: psi_i needs the distance to the other fragments only where
// two fragments come within a few voxels of each other (the crack gaps), so one pass over the
// fragments' leaves finds those places (the contact zone) and, for its voxels only, the nearest
// fragments by a brute-force search of a small ball of labelled voxels, on dense blocks copied
// per leaf. Everywhere else a cell is the object offset by the margin.
#include "nodes/segment/fragment_cells.hpp"

#include "graph/cancel_token.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tree/LeafManager.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
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

FragmentCells::FragmentCells(const Fragments& f, double margin_voxels) : g_(std::make_unique<Grids>()) {
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
    std::vector<Coord> ball;
    std::vector<float> ball_length;
    const int R = g.search;
    for (int i = -R; i <= R; ++i)
        for (int j = -R; j <= R; ++j)
            for (int k = -R; k <= R; ++k)
                if (i * i + j * j + k * k <= R * R) {
                    ball.emplace_back(i, j, k);
                    ball_length.push_back(float(std::sqrt(double(i * i + j * j + k * k)) * g.voxel));
                }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, zone_leaves.size(), 4), [&](const tbb::blocked_range<std::size_t>& r) {
        cancel.poll();
        const int B = kDim + 2 * R;
        std::vector<int> lab(std::size_t(B * B * B));
        std::vector<float> val(std::size_t(B * B * B));
        openvdb::tree::ValueAccessor<const IntTree> lab_acc(*g.label);
        // One accessor per fragment met, made on first use and not registered with its tree (a
        // registered accessor per fragment and task serialises on the trees' registries when
        // there are hundreds of fragments).
        using PhiAccessor = openvdb::tree::ValueAccessor<const openvdb::FloatTree, false>;
        std::vector<std::unique_ptr<PhiAccessor>> phi_acc(g.phi.size());
        auto phi_value = [&](int k, const Coord& c) {
            auto& a = phi_acc[std::size_t(k)];
            if (!a) a = std::make_unique<PhiAccessor>(grid_of(g.phi[std::size_t(k)]).tree());
            return a->getValue(c);
        };
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            IntLeaf& leaf = *zone_leaves[l];
            const Coord lo = leaf.origin() - Coord(R);
            bool any = false;
            for (int i = 0; i < B; ++i)
                for (int j = 0; j < B; ++j)
                    for (int k = 0; k < B; ++k) {
                        const Coord c = lo + Coord(i, j, k);
                        const std::size_t at = std::size_t((i * B + j) * B + k);
                        lab[at] = lab_acc.getValue(c);
                        if (lab[at] >= 0) {
                            val[at] = phi_value(lab[at], c);
                            any = true;
                        }
                    }
            std::size_t index = first[l];
            for (auto v = leaf.beginValueOn(); v; ++v, ++index) {
                v.setValue(int(index));
                if (!any) continue;
                Nearest& near = g.nearest[index];
                const Coord x = v.getCoord() - lo;
                for (std::size_t o = 0; o < ball.size(); ++o) {
                    const Coord y = x + ball[o];
                    const std::size_t at = std::size_t((y[0] * B + y[1]) * B + y[2]);
                    if (lab[at] >= 0) near.offer(lab[at], ball_length[o] + val[at]);
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
