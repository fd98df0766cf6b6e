// OpenVDB translation unit: the broken object (eq. 6.1) and the tile-aware connected-component
// search with detail-preserving over-segmentation (ch. 6.3, App. B listing 1), in parallel
// (oneTBB) with a result independent of the thread count: a concurrent union-find over the pieces
// of the leaves (26-connected parts, on bit masks) and the inside tiles whose roots are the
// smallest items of their components, then each fragment grid built block by block from bit
// masks. Work scales with the leaves (surface and crack bands), not with the interior's tiles.
#include "nodes/segment/fragments.hpp"

#include "graph/diagnostics.hpp"
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/SignedFloodFill.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace cf {

using openvdb::Coord;
using FloatTree = openvdb::FloatTree;
using LeafT = FloatTree::LeafNodeType;

LevelSet broken_object(const LevelSet& object, const CrackLevelSets& cracks) {
    ensure_openvdb_initialized();
    const auto& obj = grid_of(object);
    const CancelToken cancel = CancelToken::current();  // polled per crack and, in the copies and the CSG, per node
    openvdb::FloatGrid::Ptr out = deep_copy_polled(obj, cancel);
    const openvdb::CoordBBox obox = obj.evalActiveVoxelBoundingBox();
    for (std::size_t c = 0; c < cracks.cracks.size(); ++c) {
        cancel.poll();
        const LevelSet& ls = cracks.cracks[c];
        const std::string name = "crack " + std::to_string(c);
        if (ls.empty() || grid_of(ls).activeVoxelCount() == 0)
            throw std::invalid_argument(name + " is empty (no voxels recorded); remove it or record its front first");
        if (std::abs(ls.voxel_size - object.voxel_size) > 1e-9 * object.voxel_size)
            throw std::invalid_argument(name + " has voxel size " + graph::format_number(ls.voxel_size) +
                                        " m but the object has " + graph::format_number(object.voxel_size) +
                                        " m; build both with the same r_f");
        if (!obox.hasOverlap(grid_of(ls).evalActiveVoxelBoundingBox()))
            throw std::invalid_argument(name + " lies entirely outside the object; move it inside or remove it");
        openvdb::FloatGrid::Ptr crack = deep_copy_polled(grid_of(ls), cancel);
        csg_difference_polled(*out, *crack, cancel);  // max(Phi_o, -Phi_c), eq. (6.1)
    }
    out->setName("broken_object");
    return wrap_grid(out, object.voxel_size, object.half_width);
}

LevelSet fill_crack_slits(const LevelSet& fragment, const LevelSet& parent, const std::vector<LevelSet>& cracks) {
    ensure_openvdb_initialized();
    openvdb::FloatGrid::Ptr out = grid_of(fragment).deepCopy();
    const float bg = static_cast<float>(fragment.background());
    const float depth = static_cast<float>(2 * fragment.voxel_size);
    auto acc = out->getAccessor();
    const auto fine = grid_of(fragment).getConstAccessor();
    const auto whole = grid_of(parent).getConstAccessor();
    for (const LevelSet& c : cracks) {
        if (c.empty()) continue;
        if (std::abs(c.voxel_size - fragment.voxel_size) > 1e-9 * fragment.voxel_size)
            throw std::invalid_argument("fill_crack_slits: a crack grid's voxel size differs from the fragment's");
        // Phi' = min(Phi_f, max(Phi_c, Phi_f - 2 r_f)) inside the parent: the crack's thickened volume
        // joins the fragment only where the fragment surrounds it (within 2 r_f of its material).
        for (auto it = grid_of(c).cbeginValueOn(); it; ++it) {
            const Coord ijk = it.getCoord();
            const float f = fine.getValue(ijk);
            if (f >= bg || whole.getValue(ijk) >= 0) continue;
            const float filled = std::min(f, std::max(*it, f - depth));
            if (filled < f) acc.setValue(ijk, filled);
        }
    }
    out->setName(grid_of(fragment).getName());
    return wrap_grid(out, fragment.voxel_size, fragment.half_width);
}

int over_segmentation_ring(double s, double r_f) { return int(std::lround(1 + s / r_f)); }

namespace {

using ConstAccessor = openvdb::tree::ValueAccessor<const FloatTree, false>;  // unregistered, one per thread
constexpr int kLeafDim = int(LeafT::DIM);          // 8
constexpr int kLeafSize = int(LeafT::SIZE);        // 512
constexpr int kRegion = kLeafDim + 4;              // a block and the 2-voxel ring around it (d <= 2)

// Index of a leaf by its address and of a tile by its origin: open addressing with linear
// probing over a power-of-two table (the lookups of every block's 27 neighbours dominate the
// search's set-up; std::unordered_map took several times longer). Filled once, then read-only.
template <typename Key>
class FlatIndex {
public:
    void reserve(std::size_t n) {
        std::size_t cap = 16;
        while (cap < 2 * n) cap <<= 1;
        keys_.assign(cap, empty());
        values_.assign(cap, -1);
        mask_ = cap - 1;
    }
    void insert(const Key& k, int v) {
        std::size_t i = hash(k) & mask_;
        while (!(keys_[i] == empty())) i = (i + 1) & mask_;
        keys_[i] = k;
        values_[i] = v;
    }
    int find(const Key& k) const {  // -1 if absent
        if (keys_.empty()) return -1;
        for (std::size_t i = hash(k) & mask_;; i = (i + 1) & mask_) {
            if (keys_[i] == k) return values_[i];
            if (keys_[i] == empty()) return -1;
        }
    }

private:
    static Key empty() {
        if constexpr (std::is_pointer_v<Key>) return nullptr;
        else return Key(std::numeric_limits<int>::min());
    }
    static std::size_t hash(const Key& k) {
        std::uint64_t h;
        if constexpr (std::is_pointer_v<Key>) h = std::uint64_t(reinterpret_cast<std::uintptr_t>(k)) >> 4;
        else h = std::uint64_t(std::uint32_t(k[0])) * 73856093u ^ std::uint64_t(std::uint32_t(k[1])) * 19349663u ^
                 std::uint64_t(std::uint32_t(k[2])) * 83492791u;
        return std::size_t((h * 0x9E3779B97F4A7C15ull) >> 20);
    }
    std::vector<Key> keys_;
    std::vector<int> values_;
    std::size_t mask_ = 0;
};

// Tile dimension (voxels per side) for a value found at accessor depth 0 (root tile), 1, 2.
int tile_dim_at_depth(int depth) {
    switch (depth) {
        case 0: return FloatTree::RootNodeType::ChildNodeType::DIM;              // 4096
        case 1: return FloatTree::RootNodeType::ChildNodeType::ChildNodeType::DIM;  // 128
        default: return LeafT::DIM;                                              // 8
    }
}

// What one leaf-sized (8^3, aligned) block of the input holds: a leaf, or a single value (a tile
// or the background), which is an inside item of the search when it is an indexed tile.
struct BlockRef {
    int leaf = -1;       // index into the leaf list, or -1
    int tile = -1;       // index of an inside tile (tiles used), or -1
    float value = 0;     // the block's value when it is not a leaf
};
using BlockNeighbourhood = std::array<BlockRef, 27>;  // (bx, by, bz) in {-1,0,1}^3, x slowest
int block_slot(int bx, int by, int bz) { return (bx + 1) * 9 + (by + 1) * 3 + (bz + 1); }

// The search works on pieces, not voxels: a piece is a 26-connected set of inside voxels within
// one leaf (value + s <= 0), found on the leaf's bit mask; items of the union-find are the pieces
// (in leaf iteration order, each leaf's pieces by their smallest voxel offset) and then the inside
// tiles (tiles used). A component's smallest item therefore holds its smallest voxel in the
// order leaf, offset, then tiles: the numbering is that of a voxel-by-voxel search.
// ItemIndex: the leaves and inside tiles of the input and where a block of it lies. Read-only
// after construction, so any number of threads may query it, each with its own accessor.
class ItemIndex {
public:
    ItemIndex(const openvdb::FloatGrid& g, float s, bool use_tiles, const CancelToken& cancel) : tree_(g.tree()), s_(s) {
        leaves_.reserve(g.tree().leafCount());
        for (auto it = g.tree().cbeginLeaf(); it; ++it) {
            if ((leaves_.size() & 4095) == 0) cancel.poll();  // a million leaves take about a second
            leaves_.push_back(&*it);
        }
        leaf_index_.reserve(leaves_.size());
        for (std::size_t l = 0; l < leaves_.size(); ++l) leaf_index_.insert(leaves_[l], int(l));
        if (use_tiles) {
            auto it = g.tree().cbeginValueAll();
            it.setMaxDepth(FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only
            for (; it; ++it) {
                if (!it.isTileValue() || *it + s > 0) continue;
                tiles_.push_back(it.getBoundingBox());
                tile_values_.push_back(*it);
                tile_levels_.push_back(int(it.getLevel()));
            }
        }
        tile_index_.reserve(tiles_.size());
        for (std::size_t t = 0; t < tiles_.size(); ++t) tile_index_.insert(tiles_[t].min(), int(t));
        if (leaves_.size() * kLeafSize / 2 + tiles_.size() >= std::size_t(std::numeric_limits<int>::max()))
            throw std::invalid_argument("broken object has " + std::to_string(leaves_.size()) +
                                        " leaf nodes, too many for the fragment search (at most " +
                                        std::to_string(std::numeric_limits<int>::max() / (LeafT::SIZE / 2)) +
                                        "); use a larger voxel size r_f");
    }
    ConstAccessor accessor() const { return ConstAccessor(tree_); }
    const std::vector<const LeafT*>& leaves() const { return leaves_; }
    const std::vector<openvdb::CoordBBox>& tiles() const { return tiles_; }
    float tile_value(std::size_t t) const { return tile_values_[t]; }
    int tile_level(std::size_t t) const { return tile_levels_[t]; }
    bool voxel_inside(float v) const { return v + s_ <= 0; }

    // Index of the inside tile holding c (c not in a leaf, found at accessor depth `depth`), else -1.
    int tile_at(const Coord& c, int depth) const {
        if (depth < 0 || tiles_.empty()) return -1;  // background: outside
        const int dim = tile_dim_at_depth(depth);
        return tile_index_.find(Coord(c[0] & ~(dim - 1), c[1] & ~(dim - 1), c[2] & ~(dim - 1)));
    }

    // The leaf holding c (its index, with the voxel offset), or else the inside tile (-1 if none).
    struct Place {
        int leaf = -1;
        openvdb::Index offset = 0;
        int tile = -1;
    };
    Place place(ConstAccessor& acc, const Coord& c) const {
        Place p;
        const int depth = acc.getValueDepth(c);
        if (depth == int(FloatTree::DEPTH) - 1) {
            p.leaf = leaf_index_.find(acc.probeConstLeaf(c));
            p.offset = LeafT::coordToOffset(c);
        } else {
            p.tile = tile_at(c, depth);
        }
        return p;
    }

    // The block with origin o (a multiple of 8).
    BlockRef block_at(ConstAccessor& acc, const Coord& o) const {
        BlockRef b;
        const int depth = acc.getValueDepth(o);
        if (depth == int(FloatTree::DEPTH) - 1) {
            b.leaf = leaf_index_.find(acc.probeConstLeaf(o));
            return b;
        }
        b.value = acc.getValue(o);
        b.tile = tile_at(o, depth);
        return b;
    }
    BlockNeighbourhood neighbourhood(ConstAccessor& acc, const Coord& o) const {
        BlockNeighbourhood n;
        for (int bx = -1; bx <= 1; ++bx)
            for (int by = -1; by <= 1; ++by)
                for (int bz = -1; bz <= 1; ++bz)
                    n[block_slot(bx, by, bz)] = block_at(acc, o.offsetBy(bx * kLeafDim, by * kLeafDim, bz * kLeafDim));
        return n;
    }

private:
    const FloatTree& tree_;
    float s_;
    std::vector<const LeafT*> leaves_;
    FlatIndex<const LeafT*> leaf_index_;
    std::vector<openvdb::CoordBBox> tiles_;
    std::vector<float> tile_values_;
    std::vector<int> tile_levels_;
    FlatIndex<Coord> tile_index_;
};

// Union-find shared by all threads. Links always go from the larger root to the smaller one
// (compare-and-swap on the root), so parent[i] <= i and every root is the smallest item of its
// component: the final forest's roots do not depend on the order of the unions, hence not on
// the thread count. Path halving only ever replaces a parent by one of its ancestors.
class ConcurrentForest {
public:
    explicit ConcurrentForest(std::size_t n) : parent_(n) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) parent_[i].store(int(i), std::memory_order_relaxed);
        });
    }
    int parent(int x) const { return parent_[x].load(std::memory_order_relaxed); }
    int find(int x) {
        int p = parent(x);
        while (p != x) {
            const int gp = parent(p);
            if (gp != p) parent_[x].store(gp, std::memory_order_relaxed);
            x = p;
            p = gp;
        }
        return x;
    }
    void unite(int a, int b) {
        for (;;) {
            a = find(a);
            b = find(b);
            if (a == b) return;
            if (a < b) std::swap(a, b);
            int expected = a;
            if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_acq_rel)) return;
        }
    }

private:
    std::vector<std::atomic<int>> parent_;
};

// A leaf's voxels as bits: word x, bit 8 y + z (= offset & 63).
using LeafMask = std::array<std::uint64_t, kLeafDim>;
// Rows along z of a leaf and its 1-voxel ring (10 bits each).
using RingRows = std::array<std::array<std::uint16_t, kLeafDim + 2>, kLeafDim + 2>;

constexpr std::uint64_t kZ0 = 0x0101010101010101ull, kZ7 = 0x8080808080808080ull;  // z = 0, z = 7

bool any_bit(const LeafMask& m) {
    std::uint64_t a = 0;
    for (std::uint64_t w : m) a |= w;
    return a != 0;
}

// 26-neighbourhood dilation within the leaf.
LeafMask dilate26(const LeafMask& f) {
    LeafMask yz, out;
    for (int x = 0; x < kLeafDim; ++x) {
        const std::uint64_t w = f[std::size_t(x)];
        const std::uint64_t d = w | ((w << 1) & ~kZ0) | ((w >> 1) & ~kZ7);  // z +- 1 within each row
        yz[std::size_t(x)] = d | (d << 8) | (d >> 8);                         // y +- 1
    }
    for (int x = 0; x < kLeafDim; ++x)
        out[std::size_t(x)] = yz[std::size_t(x)] | (x > 0 ? yz[std::size_t(x - 1)] : 0) |
                              (x + 1 < kLeafDim ? yz[std::size_t(x + 1)] : 0);
    return out;
}

// The voxels of the neighbouring leaf in direction (dx, dy, dz) (each in {-1, 0, 1}) that are
// 26-neighbours of the voxels of m, in that leaf's own coordinates. Empty iff m has no voxel on
// the face, edge or corner facing that direction.
LeafMask across(const LeafMask& m, int dx, int dy, int dz) {
    LeafMask yz{};
    for (int x = 0; x < kLeafDim; ++x) {
        std::uint64_t w = m[std::size_t(x)];
        if (dz > 0) w = (w & kZ7) >> 7;
        else if (dz < 0) w = (w & kZ0) << 7;
        else w = w | ((w << 1) & ~kZ0) | ((w >> 1) & ~kZ7);
        if (dy > 0) w >>= 56;
        else if (dy < 0) w <<= 56;
        else w = w | (w << 8) | (w >> 8);
        yz[std::size_t(x)] = w;
    }
    LeafMask out{};
    if (dx > 0) out[0] = yz[kLeafDim - 1];
    else if (dx < 0) out[kLeafDim - 1] = yz[0];
    else
        for (int x = 0; x < kLeafDim; ++x)
            out[std::size_t(x)] = yz[std::size_t(x)] | (x > 0 ? yz[std::size_t(x - 1)] : 0) |
                                  (x + 1 < kLeafDim ? yz[std::size_t(x + 1)] : 0);
    return out;
}

bool overlap(const LeafMask& a, const LeafMask& b) {
    std::uint64_t o = 0;
    for (int x = 0; x < kLeafDim; ++x) o |= a[std::size_t(x)] & b[std::size_t(x)];
    return o != 0;
}

// A kRegion^3 mask as rows along z: bit z of rows[x][y] (z in [0, kRegion)).
using RegionRows = std::array<std::array<std::uint16_t, kRegion>, kRegion>;
// The central 8^3 of a region, bit z + 2 of rows[x][y] for block coordinates x, y, z.
using BlockRows = std::array<std::array<std::uint16_t, kLeafDim>, kLeafDim>;

// Box dilation (Chebyshev radius r in {1, 2}) of a region mask onto the central block.
BlockRows dilate_to_block(const RegionRows& in, int r) {
    RegionRows z;  // along z: shifts within each row
    for (int x = 0; x < kRegion; ++x)
        for (int y = 0; y < kRegion; ++y) {
            const unsigned m = in[x][y];
            unsigned d = m | (m << 1) | (m >> 1);
            if (r >= 2) d |= (m << 2) | (m >> 2);
            z[x][y] = std::uint16_t(d);
        }
    std::array<std::array<std::uint16_t, kLeafDim>, kRegion> zy;  // and along y
    for (int x = 0; x < kRegion; ++x)
        for (int y = 0; y < kLeafDim; ++y) {
            unsigned d = 0;
            for (int t = y + 2 - r; t <= y + 2 + r; ++t) d |= z[x][t];
            zy[x][y] = std::uint16_t(d);
        }
    BlockRows out;  // and along x
    for (int x = 0; x < kLeafDim; ++x)
        for (int y = 0; y < kLeafDim; ++y) {
            unsigned d = 0;
            for (int t = x + 2 - r; t <= x + 2 + r; ++t) d |= zy[t][y];
            out[x][y] = std::uint16_t(d);
        }
    return out;
}

// The pieces and their components: per leaf its pieces (bit masks) and boundary voxels (inside
// with an outside 26-neighbour), a label per piece and per inside tile (-1: not inside).
struct Labelling {
    std::vector<std::uint32_t> piece_begin;  // leaf l's pieces: [piece_begin[l], piece_begin[l + 1])
    std::vector<LeafMask> piece;             // per piece
    std::vector<LeafMask> boundary;          // per leaf
    std::vector<int> piece_label;            // per piece
    std::vector<int> tile_label;             // per tile
    int count = 0;
};

// The parallel connected-component search of find_fragments (its steps 1-3): pieces with the
// pieces of the 26 neighbouring leaves they touch and with the inside tiles next to them (all
// on bit masks), tiles with their 6 face neighbours; then numbered in order of their smallest
// item (deterministic).
class ComponentSearch {
public:
    ComponentSearch(const ItemIndex& items, const std::vector<BlockNeighbourhood>& nbhd, const CancelToken& cancel)
        : items_(items), nbhd_(nbhd), leaves_(items.leaves()), cancel_(cancel) {}

    Labelling run() {
        find_pieces();
        ConcurrentForest forest(out_.piece.size() + items_.tiles().size());
        // 1. Pieces across leaf faces, edges and corners, and with inside tiles; boundary voxels.
        tbb::parallel_for(std::size_t(0), leaves_.size(), [&](std::size_t l) {
            cancel_.poll();
            link_across(l, forest);
            mark_boundary(l);
        });
        // 2. Tiles with their face neighbours. 3. Components numbered.
        link_tiles(forest);
        number_components(forest);
        return std::move(out_);
    }

private:
    // Inside bits per leaf, then each leaf's pieces: flooded (26-neighbourhood) from the lowest
    // remaining voxel, so the pieces come in order of their smallest offset.
    void find_pieces() {
        const std::size_t n = leaves_.size();
        masks_.assign(n, LeafMask{});
        std::vector<std::vector<LeafMask>> pieces(n);
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t l) {
            cancel_.poll();
            const LeafT& leaf = *leaves_[l];
            const float* v = leaf.buffer().data();
            LeafMask& m = masks_[l];
            for (int off = 0; off < kLeafSize; ++off)
                if (items_.voxel_inside(v[off])) m[std::size_t(off >> 6)] |= std::uint64_t(1) << (off & 63);
            LeafMask remaining = m;
            for (int x = 0; x < kLeafDim; ++x)
                while (remaining[std::size_t(x)]) {
                    LeafMask piece{};
                    piece[std::size_t(x)] = remaining[std::size_t(x)] & (~remaining[std::size_t(x)] + 1);  // lowest bit
                    for (;;) {
                        LeafMask grown = dilate26(piece);
                        bool changed = false;
                        for (int w = 0; w < kLeafDim; ++w) {
                            grown[std::size_t(w)] &= m[std::size_t(w)];
                            changed |= grown[std::size_t(w)] != piece[std::size_t(w)];
                        }
                        if (!changed) break;
                        piece = grown;
                    }
                    for (int w = 0; w < kLeafDim; ++w) remaining[std::size_t(w)] &= ~piece[std::size_t(w)];
                    pieces[l].push_back(piece);
                }
        });
        out_.piece_begin.assign(n + 1, 0);
        for (std::size_t l = 0; l < n; ++l) out_.piece_begin[l + 1] = out_.piece_begin[l] + std::uint32_t(pieces[l].size());
        out_.piece.resize(out_.piece_begin[n]);
        out_.boundary.assign(n, LeafMask{});
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t l) {
            std::copy(pieces[l].begin(), pieces[l].end(), out_.piece.begin() + std::ptrdiff_t(out_.piece_begin[l]));
        });
    }

    int tile_item(int t) const { return int(out_.piece.size()) + t; }

    // Leaf l's pieces with the pieces of the neighbouring leaves they touch (each pair of leaves
    // once: from the leaf with the neighbour in a positive direction) and with inside tiles.
    void link_across(std::size_t l, ConcurrentForest& forest) const {
        const std::uint32_t p0 = out_.piece_begin[l], p1 = out_.piece_begin[l + 1];
        if (p0 == p1) return;
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    if (dx == 0 && dy == 0 && dz == 0) continue;
                    const BlockRef& b = nbhd_[l][block_slot(dx, dy, dz)];
                    const bool positive = dx > 0 || (dx == 0 && (dy > 0 || (dy == 0 && dz > 0)));
                    if (b.leaf >= 0 && !positive) continue;
                    if (b.leaf < 0 && b.tile < 0) continue;
                    for (std::uint32_t p = p0; p < p1; ++p) {
                        const LeafMask a = across(out_.piece[p], dx, dy, dz);
                        if (!any_bit(a)) continue;
                        if (b.leaf < 0) {
                            forest.unite(int(p), tile_item(b.tile));
                            continue;
                        }
                        const std::uint32_t q0 = out_.piece_begin[std::size_t(b.leaf)], q1 = out_.piece_begin[std::size_t(b.leaf) + 1];
                        for (std::uint32_t q = q0; q < q1; ++q)
                            if (overlap(a, out_.piece[q])) forest.unite(int(p), int(q));
                    }
                }
    }

    // Inside bits of leaf l's block and its 1-voxel ring: bit z + 1 of rows[x + 1][y + 1] for
    // block coordinates x, y, z in [-1, 8]. Inside tiles count as inside.
    RingRows ring_rows(std::size_t l) const {
        static constexpr int kPart[3][3] = {{0, 1, kLeafDim - 1}, {1, 1 + kLeafDim, 0}, {1 + kLeafDim, kLeafDim + 2, 0}};
        RingRows rows{};
        for (int bx = 0; bx < 3; ++bx)
            for (int by = 0; by < 3; ++by)
                for (int bz = 0; bz < 3; ++bz) {
                    const BlockRef& b = nbhd_[l][std::size_t(bx * 9 + by * 3 + bz)];
                    for (int x = kPart[bx][0]; x < kPart[bx][1]; ++x)
                        for (int y = kPart[by][0]; y < kPart[by][1]; ++y) {
                            unsigned bits;  // the block's row, bit z for block z
                            if (b.leaf >= 0) {
                                const std::uint64_t w = masks_[std::size_t(b.leaf)][std::size_t(x - kPart[bx][0] + kPart[bx][2])];
                                bits = unsigned(w >> (8 * (y - kPart[by][0] + kPart[by][2]))) & 0xFFu;
                            } else {
                                bits = b.tile >= 0 ? 0xFFu : 0u;
                            }
                            // Block z in [first, first + count) goes to region z from kPart[bz][0].
                            const int first = kPart[bz][2], count = kPart[bz][1] - kPart[bz][0];
                            const unsigned part = (bits >> first) & ((1u << count) - 1u);
                            rows[std::size_t(x)][std::size_t(y)] |= std::uint16_t(part << kPart[bz][0]);
                        }
                }
        return rows;
    }

    // Boundary voxels of leaf l: inside with an outside 26-neighbour, in this leaf or beyond its
    // faces (the outside voxels of the leaf and its 1-voxel ring, dilated by one onto the leaf).
    void mark_boundary(std::size_t l) {
        const LeafMask& m = masks_[l];
        if (!any_bit(m)) return;
        const RingRows in = ring_rows(l);
        for (int x = 0; x < kLeafDim; ++x) {
            std::uint64_t near_outside = 0;
            for (int y = 0; y < kLeafDim; ++y) {
                unsigned d = 0;
                for (int tx = x; tx <= x + 2; ++tx)
                    for (int ty = y; ty <= y + 2; ++ty) {
                        const unsigned o = ~unsigned(in[std::size_t(tx)][std::size_t(ty)]) & 0x3FFu;
                        d |= o | (o << 1) | (o >> 1);
                    }
                near_outside |= std::uint64_t((d >> 1) & 0xFFu) << (8 * y);
            }
            out_.boundary[l][std::size_t(x)] = near_outside & m[std::size_t(x)];
        }
    }

    // The item of an inside voxel or tile at c, or -1.
    int inside_item(ConstAccessor& acc, const Coord& c) const {
        const ItemIndex::Place p = items_.place(acc, c);
        if (p.leaf < 0) return p.tile >= 0 ? tile_item(p.tile) : -1;
        const std::uint64_t bit = std::uint64_t(1) << (p.offset & 63);
        for (std::uint32_t q = out_.piece_begin[std::size_t(p.leaf)]; q < out_.piece_begin[std::size_t(p.leaf) + 1]; ++q)
            if (out_.piece[q][p.offset >> 6] & bit) return int(q);
        return -1;
    }

    // 2. Tiles: one probe just beyond each face (ch. 6.3). A neighbour at least as large as
    // the tile covers the whole face, so this probe finds it; smaller neighbours (voxels,
    // smaller tiles) find the tile from their own side.
    void link_tiles(ConcurrentForest& forest) const {
        tbb::enumerable_thread_specific<ConstAccessor> accs([&] { return items_.accessor(); });
        tbb::parallel_for(std::size_t(0), items_.tiles().size(), [&](std::size_t t) {
            cancel_.poll();
            ConstAccessor& acc = accs.local();
            const int item = tile_item(int(t));
            const openvdb::CoordBBox& b = items_.tiles()[t];
            const Coord probes[6] = {b.min().offsetBy(-1, 0, 0), b.min().offsetBy(0, -1, 0), b.min().offsetBy(0, 0, -1),
                                     b.max().offsetBy(1, 0, 0),  b.max().offsetBy(0, 1, 0),  b.max().offsetBy(0, 0, 1)};
            for (const Coord& p : probes) {
                const int other = inside_item(acc, p);
                if (other >= 0) forest.unite(item, other);
            }
        });
    }

    // 3. Components numbered in order of their smallest item, which is their root.
    void number_components(ConcurrentForest& forest) {
        const int pieces = int(out_.piece.size()), n = pieces + int(items_.tiles().size());
        std::vector<int> label(std::size_t(n), -1);
        int next = 0;
        for (int i = 0; i < n; ++i) {
            const int r = forest.find(i);
            label[std::size_t(i)] = r == i ? next++ : label[std::size_t(r)];
        }
        out_.count = next;
        out_.tile_label.assign(label.begin() + pieces, label.end());
        label.resize(std::size_t(pieces));
        out_.piece_label = std::move(label);
    }

    const ItemIndex& items_;
    const std::vector<BlockNeighbourhood>& nbhd_;
    const std::vector<const LeafT*>& leaves_;
    const CancelToken cancel_;
    std::vector<LeafMask> masks_;  // inside voxels per leaf
    Labelling out_;
};

Labelling label_components(const ItemIndex& items, const std::vector<BlockNeighbourhood>& nbhd, const CancelToken& cancel) {
    return ComponentSearch(items, nbhd, cancel).run();
}

// The leaves that one block of the input contributes to the fragments' grids (step 4 of
// find_fragments, gathered per block so blocks run in parallel).
struct BlockOutput {
    std::vector<std::pair<int, std::unique_ptr<LeafT>>> leaves;  // (fragment, leaf)
};

class FragmentBlockBuilder {
public:
    FragmentBlockBuilder(const ItemIndex& items, const Labelling& lab, int d, float sf, float bg, double r_f)
        : items_(items), lab_(lab), d_(d), sf_(sf), bg_(bg), half_voxel_(float(0.5 * r_f)) {}

    BlockOutput build(const Coord& origin, const BlockNeighbourhood& nb) const {
        BlockOutput out;
        const Region region = gather_region(nb);
        if (region.parts.empty()) return out;
        RegionRows any_inside{};
        for (const LabelRows& p : region.parts)
            for (int x = 0; x < R; ++x)
                for (int y = 0; y < R; ++y) any_inside[x][y] |= p.voxels[x][y] | p.tiles[x][y];
        for (const LabelRows& p : region.parts) {
            if (!candidate(p)) continue;
            std::unique_ptr<LeafT> leaf = fragment_leaf(origin, nb, p, any_inside);
            if (leaf) out.leaves.emplace_back(p.label, std::move(leaf));
        }
        return out;
    }

private:
    static constexpr int R = kRegion;

    // One component's inside leaf voxels, inside tile voxels and boundary voxels over the block
    // and its 2-voxel ring (region index = block coordinate + 2), as rows along z.
    struct LabelRows {
        int label = -1;
        RegionRows voxels{}, tiles{}, boundary{};
    };
    struct Region {
        std::vector<LabelRows> parts;  // sorted by label
    };

    static LabelRows& part_of(Region& g, int label) {
        auto it = std::lower_bound(g.parts.begin(), g.parts.end(), label,
                                   [](const LabelRows& p, int k) { return p.label < k; });
        if (it == g.parts.end() || it->label != label) {
            it = g.parts.insert(it, LabelRows{});
            it->label = label;
        }
        return *it;
    }

    // The region filled block by block: for each axis, the region part [begin, end) of the lower,
    // central and upper block and the block coordinate where it starts.
    Region gather_region(const BlockNeighbourhood& nb) const {
        static constexpr int kPart[3][3] = {{0, 2, kLeafDim - 2}, {2, 2 + kLeafDim, 0}, {2 + kLeafDim, R, 0}};
        Region g;
        auto add = [](RegionRows& rows, const LeafMask& m, int bx, int by, int bz) {
            const int first = kPart[bz][2], count = kPart[bz][1] - kPart[bz][0];
            for (int x = kPart[bx][0]; x < kPart[bx][1]; ++x) {
                const std::uint64_t w = m[std::size_t(x - kPart[bx][0] + kPart[bx][2])];
                if (!w) continue;
                for (int y = kPart[by][0]; y < kPart[by][1]; ++y) {
                    const unsigned bits = unsigned(w >> (8 * (y - kPart[by][0] + kPart[by][2]))) & 0xFFu;
                    rows[std::size_t(x)][std::size_t(y)] |= std::uint16_t(((bits >> first) & ((1u << count) - 1u)) << kPart[bz][0]);
                }
            }
        };
        static const LeafMask kFull = [] {
            LeafMask f;
            f.fill(~std::uint64_t(0));
            return f;
        }();
        for (int bx = 0; bx < 3; ++bx)
            for (int by = 0; by < 3; ++by)
                for (int bz = 0; bz < 3; ++bz) {
                    const BlockRef& b = nb[std::size_t(bx * 9 + by * 3 + bz)];
                    if (b.leaf < 0) {
                        if (b.tile < 0) continue;
                        add(part_of(g, lab_.tile_label[std::size_t(b.tile)]).tiles, kFull, bx, by, bz);
                        continue;
                    }
                    const LeafMask& bd = lab_.boundary[std::size_t(b.leaf)];
                    for (std::uint32_t p = lab_.piece_begin[std::size_t(b.leaf)]; p < lab_.piece_begin[std::size_t(b.leaf) + 1]; ++p) {
                        LabelRows& rows = part_of(g, lab_.piece_label[p]);
                        add(rows.voxels, lab_.piece[p], bx, by, bz);
                        LeafMask pb;
                        for (int w = 0; w < kLeafDim; ++w) pb[std::size_t(w)] = lab_.piece[p][std::size_t(w)] & bd[std::size_t(w)];
                        add(rows.boundary, pb, bx, by, bz);
                    }
                }
        return g;
    }

    // Fragments that can write here: inside voxels within 1 (own voxels and their neighbours),
    // boundary voxels within d (the d-ring).
    bool candidate(const LabelRows& p) const {
        unsigned any = 0;
        for (int x = 1; x < R - 1; ++x)
            for (int y = 1; y < R - 1; ++y) any |= p.voxels[x][y] & 0x7FEu;
        if (any) return true;
        if (d_ < 2) return false;
        for (int x = 0; x < R; ++x)
            for (int y = 0; y < R; ++y) any |= p.boundary[x][y];
        return any != 0;
    }

    // Fragment k's leaf over the central block (null when it writes nothing there): its own
    // voxels, their outside 26-neighbours with the input value, and the d-ring where the input is
    // positive; shallow negative voxels there get value + s; another fragment's inside voxels and
    // tiles within the d-ring get +r_f/2 (never copy a neighbour); its own tiles are added as tiles.
    std::unique_ptr<LeafT> fragment_leaf(const Coord& origin, const BlockNeighbourhood& nb, const LabelRows& k,
                                         const RegionRows& any_inside) const {
        const BlockRows copied = dilate_to_block(k.voxels, 1);
        BlockRows ring{};
        if (d_ >= 2) ring = dilate_to_block(k.boundary, 2);
        const BlockRef& centre = nb[13];
        const float* values = centre.leaf >= 0 ? items_.leaves()[std::size_t(centre.leaf)]->buffer().data() : nullptr;
        std::unique_ptr<LeafT> leaf;
        for (int x = 0; x < kLeafDim; ++x)
            for (int y = 0; y < kLeafDim; ++y) {
                const unsigned in = (any_inside[x + 2][y + 2] >> 2) & 0xFFu;
                const unsigned own = ((k.voxels[x + 2][y + 2] | k.tiles[x + 2][y + 2]) >> 2) & 0xFFu;
                const unsigned vox = (k.voxels[x + 2][y + 2] >> 2) & 0xFFu;
                const unsigned cp = (copied[x][y] >> 2) & 0xFFu, rg = (ring[x][y] >> 2) & 0xFFu;
                const unsigned own_value = in & vox;              // own voxel: the input value
                const unsigned neighbour = in & ~own & rg;        // another fragment in the ring: +r_f/2
                const unsigned outside_copy = ~in & cp;           // outside 26-neighbour: the input value
                const unsigned outside_ring = ~in & ~cp & rg;     // d-ring: shallow negatives over-segmented
                unsigned write = (own_value | neighbour | outside_copy | outside_ring) & 0xFFu;
                if (!write) continue;
                if (!leaf) leaf = std::make_unique<LeafT>(origin, bg_, false);
                for (; write; write &= write - 1) {
                    const int z = __builtin_ctz(write);
                    const openvdb::Index off = openvdb::Index((x << 6) | (y << 3) | z);
                    const float v = values ? values[off] : centre.value;
                    const unsigned bit = 1u << z;
                    float w;
                    if (neighbour & bit) w = half_voxel_;
                    else if (outside_ring & bit) w = v > 0 ? v : v + sf_;
                    else w = v;
                    leaf->setValueOn(off, w);
                }
            }
        return leaf;
    }

    const ItemIndex& items_;
    const Labelling& lab_;
    int d_;
    float sf_, bg_, half_voxel_;
};

// find_fragments' steps, in the order it calls them.

// The over-segmentation threshold s in [0, r_f] (default r_f).
double checked_threshold(double r_f, const SegmentOptions& options) {
    const double s = options.threshold < 0 ? r_f : options.threshold;
    if (!(s >= 0 && s <= r_f * (1 + 1e-9))) {
        std::ostringstream m;
        m << "over-segmentation threshold s = " << s << " m is outside [0, r_f] = [0, " << r_f
          << "] m: the d-ring copy only restores the surface detail for spindles thinner than one voxel "
             "(ch. 6.3); use 0 <= s <= "
          << r_f << " m";
        throw std::invalid_argument(m.str());
    }
    return s;
}

// The blocks that may receive fragment voxels: every leaf's block (in leaf order, so block l is
// leaf l) and then, sorted and once each, the non-leaf blocks next to a leaf.
std::vector<Coord> output_blocks(const std::vector<const LeafT*>& leaves, const std::vector<BlockNeighbourhood>& nbhd,
                                 const CancelToken& cancel) {
    std::vector<Coord> blocks;
    blocks.reserve(leaves.size());
    for (const LeafT* leaf : leaves) blocks.push_back(leaf->origin());
    std::vector<Coord> extra;
    for (std::size_t l = 0; l < leaves.size(); ++l) {
        if ((l & 4095u) == 0) cancel.poll();
        for (int slot = 0; slot < 27; ++slot)
            if (nbhd[l][slot].leaf < 0)
                extra.push_back(leaves[l]->origin().offsetBy((slot / 9 - 1) * kLeafDim, (slot / 3 % 3 - 1) * kLeafDim,
                                                             (slot % 3 - 1) * kLeafDim));
    }
    cancel.poll();
    tbb::parallel_sort(extra.begin(), extra.end());  // 0.15 s serial for the 1 mm box: halved
    cancel.poll();
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    blocks.insert(blocks.end(), extra.begin(), extra.end());
    return blocks;
}

// One fragment's level set: its leaves (moved in) and its inside tiles, which keep their place in
// the hierarchy (FloatTree::addTile levels: 1 = 8^3 ...), signed-flood-filled.
// A fragment may hold most of the object: polled every 4096 leaves (a tenth of a second on a
// loaded machine), not only once per fragment.
openvdb::FloatGrid::Ptr fragment_grid(const openvdb::FloatGrid& in, const ItemIndex& items,
                                      std::vector<std::unique_ptr<LeafT>>& leaves, const std::vector<std::size_t>& tiles,
                                      const CancelToken& cancel) {
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(in.background());
    grid->setTransform(in.transform().copy());
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    std::size_t added = 0;
    for (auto& leaf : leaves) {
        if ((++added & 4095u) == 0) cancel.poll();
        grid->tree().addLeaf(leaf.release());
    }
    leaves.clear();
    for (std::size_t t : tiles)
        grid->tree().addTile(openvdb::Index(items.tile_level(t)), items.tiles()[t].min(), items.tile_value(t), false);
    openvdb::tools::signedFloodFill(grid->tree());
    grid->setName("fragment");
    return grid;
}

// Volume, centroid and bbox of a fragment's inside: linear Heaviside clamp(1/2 - phi/r_f, 0, 1)
// per voxel (exact for a planar interface), whole inside tiles. LevelSetMeasure is not used
// here: its 3-voxel Dirac delta needs a full outside band, which a fragment has only up to its
// d-ring. Summed over every value of the tree (voxels and tiles, active or not) in tree order:
// depth first, each node's children and tiles by offset, as OpenVDB's value iterator visits
// them, so a fragment's sums do not depend on the thread count. The nodes are walked directly,
// a leaf's values from its buffer. Polled every 4096 leaves.
class FragmentMeasure {
public:
    FragmentMeasure(double r_f, const CancelToken& cancel) : r_f_(r_f), cancel_(cancel) {}

    void visit(const FloatTree& tree) {
        const auto& root = tree.root();
        for (auto it = root.cbeginChildAll(); it; ++it) {
            float v = 0;
            if (const auto* child = it.probeChild(v)) node(*child);
            else tile(it.getCoord(), FloatTree::RootNodeType::ChildNodeType::DIM, v);
        }
    }
    void store(Fragment& f) const {
        f.volume = w_sum_ * r_f_ * r_f_ * r_f_;
        f.centroid = w_sum_ > 0 ? Vec3(wx_ / w_sum_) : Vec3::Zero();
        f.bbox = Box3{r_f_ * Vec3(lo_[0], lo_[1], lo_[2]), r_f_ * Vec3(hi_[0], hi_[1], hi_[2])};
    }

private:
    template <typename NodeT>
    void node(const NodeT& n) {
        for (auto it = n.cbeginChildAll(); it; ++it) {
            float v = 0;
            if (const auto* child = it.probeChild(v)) {
                if constexpr (std::is_same_v<std::decay_t<decltype(*child)>, LeafT>) leaf(*child);
                else node(*child);
            } else {
                tile(it.getCoord(), int(NodeT::ChildNodeType::DIM), v);
            }
        }
    }
    // One value over the box [lo, hi] (a voxel or a tile), as the sums of the value iterator.
    void add(float v, bool is_tile, const Coord& lo, const Coord& hi) {
        if (v >= 0.5f * float(r_f_)) return;
        const double w = is_tile ? 1.0 : std::clamp(0.5 - v / r_f_, 0.0, 1.0);
        if (w <= 0) return;
        const double vox = double(openvdb::CoordBBox(lo, hi).volume());
        const Vec3 centre = 0.5 * r_f_ * Vec3(lo[0] + hi[0], lo[1] + hi[1], lo[2] + hi[2]);
        w_sum_ += w * vox;
        wx_ += w * vox * centre;
        if (v < 0) {
            lo_ = Coord::minComponent(lo_, lo);
            hi_ = Coord::maxComponent(hi_, hi);
        }
    }
    void tile(const Coord& origin, int dim, float v) { add(v, true, origin, origin.offsetBy(dim - 1)); }
    void leaf(const LeafT& l) {
        if ((++leaves_ & 4095u) == 0) cancel_.poll();
        const float* values = l.buffer().data();
        const float cut = 0.5f * float(r_f_);
        for (int off = 0; off < kLeafSize; ++off) {
            if (values[off] >= cut) continue;  // the common case: outside, nothing added
            const Coord c = l.offsetToGlobalCoord(openvdb::Index(off));
            add(values[off], false, c, c);
        }
    }

    double r_f_;
    CancelToken cancel_;
    double w_sum_ = 0;
    Vec3 wx_ = Vec3::Zero();
    Coord lo_ = Coord(std::numeric_limits<int>::max()), hi_ = Coord(std::numeric_limits<int>::min());
    std::size_t leaves_ = 0;
};

void measure_fragment(const openvdb::FloatGrid& g, double r_f, Fragment& f, const CancelToken& cancel) {
    FragmentMeasure m(r_f, cancel);
    m.visit(g.tree());
    m.store(f);
}

// Fragments by decreasing volume (ties by bbox corner), named fragment0, fragment1, ... in that
// order (the names appear in .vdb files).
void order_fragments(Fragments& result) {
    std::stable_sort(result.fragments.begin(), result.fragments.end(), [](const Fragment& a, const Fragment& b) {
        if (a.volume != b.volume) return a.volume > b.volume;
        return std::lexicographical_compare(a.bbox.min.data(), a.bbox.min.data() + 3, b.bbox.min.data(),
                                            b.bbox.min.data() + 3);
    });
    for (std::size_t i = 0; i < result.fragments.size(); ++i)
        if (!result.fragments[i].grid.empty())  // a speck below SegmentOptions::min_volume has none
            std::const_pointer_cast<LevelSetGrid>(result.fragments[i].grid.grid)->grid->setName("fragment" + std::to_string(i));
}

}  // namespace

Fragments find_fragments(const LevelSet& broken, const SegmentOptions& options) {
    ensure_openvdb_initialized();
    const auto& in = grid_of(broken);
    const double r_f = broken.voxel_size;
    const double s = checked_threshold(r_f, options);
    const float sf = float(s);
    const int d = over_segmentation_ring(s, r_f);  // 1 or 2 for s in [0, r_f]
    const CancelToken cancel = CancelToken::current();  // polled per leaf, block and fragment
    const ItemIndex items(in, sf, options.use_tiles, cancel);
    const auto& leaves = items.leaves();
    cancel.poll();

    // The 27 blocks around every leaf, looked up once.
    tbb::enumerable_thread_specific<ConstAccessor> accs([&] { return items.accessor(); });
    std::vector<BlockNeighbourhood> nbhd(leaves.size());
    tbb::parallel_for(std::size_t(0), leaves.size(),
                      [&](std::size_t l) {
                          cancel.poll();
                          nbhd[l] = items.neighbourhood(accs.local(), leaves[l]->origin());
                      });

    // 1.-3. Connected components of the inside items: voxels with their 26 neighbours, tiles
    // with their 6 face neighbours; numbered in order of their smallest item (deterministic).
    const Labelling lab = label_components(items, nbhd, cancel);
    const int count = lab.count;
    cancel.poll();

    // 4. One grid per component: inside voxels with their values, the 26 neighbours with the
    // input values (any sign), then the d-ring (Chebyshev distance 2..d from an inside voxel
    // with an outside neighbour) only where the input is positive; shallow negative voxels there
    // (-s < value <= 0) get the over-segmented value value + s > 0, and voxels inside another
    // fragment get +r_f/2: never copy a neighbouring fragment. Every written voxel lies in a leaf
    // block or in a block next to one, and its value depends only on the labels and values
    // within 2 voxels, so each block is built on its own, in parallel.
    const std::vector<Coord> blocks = output_blocks(leaves, nbhd, cancel);
    const float bg = in.background();
    const FragmentBlockBuilder builder(items, lab, d, sf, bg, r_f);
    std::vector<BlockOutput> built(blocks.size());
    tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t b) {
        cancel.poll();
        built[b] = builder.build(blocks[b], b < leaves.size() ? nbhd[b] : items.neighbourhood(accs.local(), blocks[b]));
    });
    nbhd.clear();
    nbhd.shrink_to_fit();

    // 5. The blocks' leaves and the inside tiles gathered per fragment, each fragment's grid
    // assembled and measured in parallel, then the fragments ordered.
    std::vector<std::vector<std::unique_ptr<LeafT>>> leaves_of(count);
    cancel.poll();
    for (BlockOutput& b : built)
        for (auto& [k, leaf] : b.leaves) leaves_of[k].push_back(std::move(leaf));
    built.clear();
    std::vector<std::vector<std::size_t>> tiles_of(count);
    for (std::size_t t = 0; t < items.tiles().size(); ++t) tiles_of[std::size_t(lab.tile_label[t])].push_back(t);

    Fragments result;
    result.voxel_size = r_f;
    result.threshold = s;
    result.used_tiles = options.use_tiles;
    result.fragments.resize(count);
    // Largest first (by leaves and tiles), each free thread taking the next: components are numbered
    // by their smallest item, so the two halves of a cut object are often 0 and 1, which a split index
    // range hands to one thread in turn while the other measures specks (edge_crack_mode3: ~60 ms on
    // one core). Each fragment is built and measured on its own, so the order does not show.
    std::vector<int> order(static_cast<std::size_t>(count));
    for (int k = 0; k < count; ++k) order[std::size_t(k)] = k;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return leaves_of[std::size_t(a)].size() + tiles_of[std::size_t(a)].size() >
               leaves_of[std::size_t(b)].size() + tiles_of[std::size_t(b)].size();
    });
    std::atomic<std::size_t> next{0};
    const std::size_t workers =
        std::min<std::size_t>(order.size(), std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
    tbb::parallel_for(std::size_t(0), workers, [&](std::size_t) {
        for (std::size_t i = next++; i < order.size(); i = next++) {
            const int k = order[i];
            cancel.poll();
            const openvdb::FloatGrid::Ptr grid = fragment_grid(in, items, leaves_of[k], tiles_of[k], cancel);
            Fragment& f = result.fragments[k];
            f.active_voxels = grid->activeVoxelCount();
            measure_fragment(*grid, r_f, f, cancel);
            if (f.volume >= options.min_volume) f.grid = wrap_grid(grid, r_f, broken.half_width);
        }
    });
    order_fragments(result);
    return result;
}

}  // namespace cf
