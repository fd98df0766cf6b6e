// OpenVDB translation unit: the broken object (eq. 6.1) and the tile-aware connected-component
// search with detail-preserving over-segmentation (ch. 6.3, App. B listing 1).
#include "nodes/segment/fragments.hpp"

#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace cf {

using openvdb::Coord;
using FloatTree = openvdb::FloatTree;
using LeafT = FloatTree::LeafNodeType;

LevelSet broken_object(const LevelSet& object, const CrackLevelSets& cracks) {
    ensure_openvdb_initialized();
    const auto& obj = grid_of(object);
    openvdb::FloatGrid::Ptr out = obj.deepCopy();
    const openvdb::CoordBBox obox = obj.evalActiveVoxelBoundingBox();
    for (std::size_t c = 0; c < cracks.cracks.size(); ++c) {
        const LevelSet& ls = cracks.cracks[c];
        const std::string name = "crack " + std::to_string(c);
        if (ls.empty() || grid_of(ls).activeVoxelCount() == 0)
            throw std::invalid_argument(name + " is empty (no voxels recorded); remove it or record its front first");
        if (std::abs(ls.voxel_size - object.voxel_size) > 1e-9 * object.voxel_size)
            throw std::invalid_argument(name + " has voxel size " + std::to_string(ls.voxel_size) +
                                        " m but the object has " + std::to_string(object.voxel_size) +
                                        " m; build both with the same r_f");
        if (!obox.hasOverlap(grid_of(ls).evalActiveVoxelBoundingBox()))
            throw std::invalid_argument(name + " lies entirely outside the object; move it inside or remove it");
        openvdb::FloatGrid::Ptr crack = grid_of(ls).deepCopy();
        openvdb::tools::csgDifference(*out, *crack);  // max(Phi_o, -Phi_c), eq. (6.1)
    }
    out->setName("broken_object");
    return wrap_grid(out, object.voxel_size, object.half_width);
}

int over_segmentation_ring(double s, double r_f) { return int(std::lround(1 + s / r_f)); }

namespace {

struct CoordHash {
    std::size_t operator()(const Coord& c) const {
        return std::size_t(c[0]) * 73856093u ^ std::size_t(c[1]) * 19349663u ^ std::size_t(c[2]) * 83492791u;
    }
};

// Tile dimension (voxels per side) for a value found at accessor depth 0 (root tile), 1, 2.
int tile_dim_at_depth(int depth) {
    switch (depth) {
        case 0: return FloatTree::RootNodeType::ChildNodeType::DIM;              // 4096
        case 1: return FloatTree::RootNodeType::ChildNodeType::ChildNodeType::DIM;  // 128
        default: return LeafT::DIM;                                              // 8
    }
}

int find_root(std::vector<int>& parent, int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}
void unite(std::vector<int>& parent, int a, int b) {
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a == b) return;
    if (a < b) std::swap(a, b);  // smaller index becomes the root: deterministic labels
    parent[a] = b;
}

// The items of the search: voxels of leaf nodes (512 slots per leaf) and tiles; "inside" means
// value + s <= 0 (tiles only when tiles are used).
class ItemIndex {
public:
    ItemIndex(const openvdb::FloatGrid& g, float s, bool use_tiles) : grid_(g), acc_(g.getConstAccessor()), s_(s) {
        for (auto it = g.tree().cbeginLeaf(); it; ++it) {
            leaf_index_[&*it] = int(leaves_.size());
            leaves_.push_back(&*it);
        }
        tile_base_ = leaves_.size() * LeafT::SIZE;
        if (use_tiles) {
            auto it = g.tree().cbeginValueAll();
            it.setMaxDepth(FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
            for (; it; ++it) {
                if (!it.isTileValue() || *it + s > 0) continue;
                const openvdb::CoordBBox b = it.getBoundingBox();
                tile_index_[b.min()] = int(tiles_.size());
                tiles_.push_back(b);
                tile_values_.push_back(*it);
                tile_levels_.push_back(int(it.getLevel()));
            }
        }
    }
    std::size_t size() const { return tile_base_ + tiles_.size(); }
    const std::vector<const LeafT*>& leaves() const { return leaves_; }
    const std::vector<openvdb::CoordBBox>& tiles() const { return tiles_; }
    std::size_t tile_base() const { return tile_base_; }
    float tile_value(std::size_t t) const { return tile_values_[t]; }
    int tile_level(std::size_t t) const { return tile_levels_[t]; }
    bool voxel_inside(float v) const { return v + s_ <= 0; }

    // Item holding coordinate c if it is inside, else -1.
    long long inside_item(const Coord& c) {
        const int depth = acc_.getValueDepth(c);
        if (depth < 0) return -1;  // background: outside
        if (depth == int(FloatTree::DEPTH) - 1) {
            const LeafT* leaf = acc_.probeConstLeaf(c);
            const openvdb::Index off = LeafT::coordToOffset(c);
            if (!voxel_inside(leaf->getValue(off))) return -1;
            return (long long)(leaf_index_.at(leaf)) * LeafT::SIZE + off;
        }
        const int dim = tile_dim_at_depth(depth);
        const Coord origin(c[0] & ~(dim - 1), c[1] & ~(dim - 1), c[2] & ~(dim - 1));
        auto it = tile_index_.find(origin);
        return it == tile_index_.end() ? -1 : (long long)(tile_base_ + it->second);
    }

private:
    const openvdb::FloatGrid& grid_;
    openvdb::FloatGrid::ConstAccessor acc_;
    float s_;
    std::vector<const LeafT*> leaves_;
    std::unordered_map<const LeafT*, int> leaf_index_;
    std::size_t tile_base_ = 0;
    std::vector<openvdb::CoordBBox> tiles_;
    std::vector<float> tile_values_;
    std::vector<int> tile_levels_;
    std::unordered_map<Coord, int, CoordHash> tile_index_;
};

}  // namespace

Fragments find_fragments(const LevelSet& broken, const SegmentOptions& options) {
    ensure_openvdb_initialized();
    const auto& in = grid_of(broken);
    const double r_f = broken.voxel_size;
    const double s = options.threshold < 0 ? r_f : options.threshold;
    if (!(s >= 0 && s <= r_f * (1 + 1e-9))) {
        std::ostringstream m;
        m << "over-segmentation threshold s = " << s << " m is outside [0, r_f] = [0, " << r_f
          << "] m: the d-ring copy only restores the surface detail for spindles thinner than one voxel "
             "(ch. 6.3); use 0 <= s <= "
          << r_f << " m";
        throw std::invalid_argument(m.str());
    }
    const float sf = float(s);
    const int d = over_segmentation_ring(s, r_f);
    ItemIndex items(in, sf, options.use_tiles);
    const std::size_t n = items.size();
    std::vector<int> parent(n);
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<char> inside(n, 0);

    // 1. Union inside voxels with their 26 neighbours (within a leaf: direct offsets).
    const auto& leaves = items.leaves();
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        const LeafT& leaf = *leaves[l];
        const long long base = (long long)l * LeafT::SIZE;
        for (openvdb::Index off = 0; off < LeafT::SIZE; ++off)
            if (items.voxel_inside(leaf.getValue(off))) inside[base + off] = 1;
    }
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        const LeafT& leaf = *leaves[l];
        const long long base = (long long)l * LeafT::SIZE;
        const Coord origin = leaf.origin();
        for (openvdb::Index off = 0; off < LeafT::SIZE; ++off) {
            if (!inside[base + off]) continue;
            const Coord local = LeafT::offsetToLocalCoord(off);
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz) {
                        if (!dx && !dy && !dz) continue;
                        const Coord nl = local + Coord(dx, dy, dz);
                        long long other;
                        if (nl[0] >= 0 && nl[0] < 8 && nl[1] >= 0 && nl[1] < 8 && nl[2] >= 0 && nl[2] < 8) {
                            other = base + LeafT::coordToOffset(nl);
                            if (!inside[other]) continue;
                        } else {
                            other = items.inside_item(origin + nl);
                            if (other < 0) continue;
                            inside[other] = 1;
                        }
                        unite(parent, int(base + off), int(other));
                    }
        }
    }
    // 2. Tiles: one probe just beyond each face (ch. 6.3). A neighbour at least as large as
    // the tile covers the whole face, so this probe finds it; smaller neighbours (voxels,
    // smaller tiles) find the tile from their own side.
    for (std::size_t t = 0; t < items.tiles().size(); ++t) {
        const int item = int(items.tile_base() + t);
        inside[item] = 1;
        const openvdb::CoordBBox& b = items.tiles()[t];
        const Coord probes[6] = {b.min().offsetBy(-1, 0, 0), b.min().offsetBy(0, -1, 0), b.min().offsetBy(0, 0, -1),
                                 b.max().offsetBy(1, 0, 0),  b.max().offsetBy(0, 1, 0),  b.max().offsetBy(0, 0, 1)};
        for (const Coord& p : probes) {
            const long long other = items.inside_item(p);
            if (other >= 0) unite(parent, item, int(other));
        }
    }
    // 3. Components in order of their smallest item (deterministic).
    std::vector<int> label(n, -1);
    int count = 0;
    std::vector<int> comp_of_root(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        if (!inside[i]) continue;
        const int r = find_root(parent, int(i));
        if (comp_of_root[r] < 0) comp_of_root[r] = count++;
        label[i] = comp_of_root[r];
    }
    // 4. One grid per component: inside voxels with their values, the 26 neighbours with the
    // input values (any sign), then the d-ring (Chebyshev distance 2..d) only where the input
    // is positive; shallow negative voxels there (-s < value <= 0) get the over-segmented
    // value value + s > 0, and voxels inside another fragment get +r_f/2: never copy a
    // neighbouring fragment.
    const float bg = in.background();
    std::vector<openvdb::FloatGrid::Ptr> grids(count);
    for (int k = 0; k < count; ++k) {
        grids[k] = openvdb::FloatGrid::create(bg);
        grids[k]->setTransform(in.transform().copy());
        grids[k]->setGridClass(openvdb::GRID_LEVEL_SET);
    }
    std::vector<openvdb::FloatGrid::Accessor> accs;
    for (auto& g : grids) accs.push_back(g->getAccessor());
    auto in_acc = in.getConstAccessor();
    // Inside voxels with an outside neighbour. For d <= 2 only they can reach an outside voxel
    // at distance 2 that no inside voxel touches (the midpoint would otherwise be inside and
    // adjacent to it), so the d-ring pass visits only them.
    std::vector<char> boundary(leaves.size() * LeafT::SIZE, 0);
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        const LeafT& leaf = *leaves[l];
        const long long base = (long long)l * LeafT::SIZE;
        for (openvdb::Index off = 0; off < LeafT::SIZE; ++off) {
            const int k = label[base + off];
            if (k < 0) continue;
            const Coord c = leaf.offsetToGlobalCoord(off);
            accs[k].setValue(c, leaf.getValue(off));
            for (int dx = -1; dx <= 1; ++dx)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dz = -1; dz <= 1; ++dz) {
                        const Coord nc = c.offsetBy(dx, dy, dz);
                        if (items.inside_item(nc) >= 0) continue;
                        accs[k].setValue(nc, in_acc.getValue(nc));
                        boundary[base + off] = 1;
                    }
        }
    }
    if (d >= 2) {
        for (std::size_t l = 0; l < leaves.size(); ++l) {
            const LeafT& leaf = *leaves[l];
            const long long base = (long long)l * LeafT::SIZE;
            for (openvdb::Index off = 0; off < LeafT::SIZE; ++off) {
                const int k = label[base + off];
                if (k < 0 || !boundary[base + off]) continue;
                const Coord c = leaf.offsetToGlobalCoord(off);
                for (int dx = -d; dx <= d; ++dx)
                    for (int dy = -d; dy <= d; ++dy)
                        for (int dz = -d; dz <= d; ++dz) {
                            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) < 2) continue;
                            const Coord nc = c.offsetBy(dx, dy, dz);
                            if (accs[k].isValueOn(nc)) continue;
                            const long long item = items.inside_item(nc);
                            if (item >= 0 && label[item] == k) continue;
                            const float v = in_acc.getValue(nc);
                            float value;
                            if (item >= 0) value = float(0.5 * r_f);  // another fragment
                            else value = v > 0 ? v : v + sf;
                            accs[k].setValue(nc, value);
                        }
            }
        }
    }
    accs.clear();  // before structural changes (addTile)
    // Inside tiles keep their place in the hierarchy (FloatTree::addTile levels: 1 = 8^3 ...).
    for (std::size_t t = 0; t < items.tiles().size(); ++t) {
        const int k = label[items.tile_base() + t];
        grids[k]->tree().addTile(openvdb::Index(items.tile_level(t)), items.tiles()[t].min(), items.tile_value(t), false);
    }
    Fragments result;
    result.voxel_size = r_f;
    result.threshold = s;
    result.used_tiles = options.use_tiles;
    for (int k = 0; k < count; ++k) {
        openvdb::FloatGrid& g = *grids[k];
        openvdb::tools::signedFloodFill(g.tree());
        g.setName("fragment");
        Fragment f;
        f.active_voxels = g.activeVoxelCount();
        // Volume, centroid and bbox of the inside: linear Heaviside clamp(1/2 - phi/r_f, 0, 1)
        // per voxel (exact for a planar interface), whole inside tiles. LevelSetMeasure is not
        // used here: its 3-voxel Dirac delta needs a full outside band, which a fragment has
        // only up to its d-ring.
        double w_sum = 0;
        Vec3 wx = Vec3::Zero();
        Coord lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
        for (auto it = g.tree().cbeginValueAll(); it; ++it) {
            const float v = *it;
            if (v >= 0.5f * float(r_f)) continue;
            const openvdb::CoordBBox b = it.getBoundingBox();
            const double w = it.isTileValue() ? 1.0 : std::clamp(0.5 - v / r_f, 0.0, 1.0);
            if (w <= 0) continue;
            const double vox = double(b.volume());
            const Vec3 centre = 0.5 * r_f * Vec3(b.min()[0] + b.max()[0], b.min()[1] + b.max()[1], b.min()[2] + b.max()[2]);
            w_sum += w * vox;
            wx += w * vox * centre;
            if (v < 0) {
                lo = Coord::minComponent(lo, b.min());
                hi = Coord::maxComponent(hi, b.max());
            }
        }
        f.volume = w_sum * r_f * r_f * r_f;
        f.centroid = w_sum > 0 ? Vec3(wx / w_sum) : Vec3::Zero();
        f.bbox = Box3{r_f * Vec3(lo[0], lo[1], lo[2]), r_f * Vec3(hi[0], hi[1], hi[2])};
        f.grid = wrap_grid(grids[k], r_f, broken.half_width);
        result.fragments.push_back(std::move(f));
    }
    std::stable_sort(result.fragments.begin(), result.fragments.end(), [](const Fragment& a, const Fragment& b) {
        if (a.volume != b.volume) return a.volume > b.volume;
        return std::lexicographical_compare(a.bbox.min.data(), a.bbox.min.data() + 3, b.bbox.min.data(),
                                            b.bbox.min.data() + 3);
    });
    for (std::size_t i = 0; i < result.fragments.size(); ++i) {
        // Names appear in .vdb files.
        std::const_pointer_cast<LevelSetGrid>(result.fragments[i].grid.grid)->grid->setName("fragment" + std::to_string(i));
    }
    return result;
}

}  // namespace cf
