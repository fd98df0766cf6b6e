// Test reference: the voxel-by-voxel fragment search that segmentation.cpp used until issue 17
// (crackflow dca2353), kept verbatim apart from this header and the names: every inside voxel is
// an item of the union-find, and each output block reads per-voxel labels. segmentation.cpp now
// works on pieces (26-connected parts of a leaf) and bit masks; segmentation_equivalence_test
// checks that both give bit-identical fragments.
#include "tests/segment/voxel_segmentation.hpp"

#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace cf::reference {

using openvdb::Coord;
using FloatTree = openvdb::FloatTree;
using LeafT = FloatTree::LeafNodeType;

namespace {

using ConstAccessor = openvdb::tree::ValueAccessor<const FloatTree, false>;  // unregistered, one per thread
constexpr int kLeafDim = int(LeafT::DIM);          // 8
constexpr int kLeafSize = int(LeafT::SIZE);        // 512
constexpr int kRegion = kLeafDim + 4;              // a block and the 2-voxel ring around it (d <= 2)

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

// What one leaf-sized (8^3, aligned) block of the input holds: a leaf, or a single value (a tile
// or the background), which is an inside item of the search when it is an indexed tile.
struct BlockRef {
    int leaf = -1;       // index into the leaf list, or -1
    int tile_item = -1;  // item of an inside tile (tiles used), or -1
    float value = 0;     // the block's value when it is not a leaf
};
using BlockNeighbourhood = std::array<BlockRef, 27>;  // (bx, by, bz) in {-1,0,1}^3, x slowest
int block_slot(int bx, int by, int bz) { return (bx + 1) * 9 + (by + 1) * 3 + (bz + 1); }

// The items of the search: voxels of leaf nodes (512 slots per leaf, in leaf iteration order)
// and tiles; "inside" means value + s <= 0 (tiles only when tiles are used). Read-only after
// construction, so any number of threads may query it, each with its own accessor.
class ItemIndex {
public:
    ItemIndex(const openvdb::FloatGrid& g, float s, bool use_tiles, const CancelToken& cancel) : tree_(g.tree()), s_(s) {
        for (auto it = g.tree().cbeginLeaf(); it; ++it) {
            if ((leaves_.size() & 4095) == 0) cancel.poll();  // a million leaves take about a second
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
        if (tile_base_ + tiles_.size() >= std::size_t(std::numeric_limits<int>::max()))
            throw std::invalid_argument("broken object has " + std::to_string(leaves_.size()) +
                                        " leaf nodes, too many for the fragment search (at most " +
                                        std::to_string(std::numeric_limits<int>::max() / LeafT::SIZE) +
                                        "); use a larger voxel size r_f");
    }
    ConstAccessor accessor() const { return ConstAccessor(tree_); }
    std::size_t size() const { return tile_base_ + tiles_.size(); }
    const std::vector<const LeafT*>& leaves() const { return leaves_; }
    const std::vector<openvdb::CoordBBox>& tiles() const { return tiles_; }
    std::size_t tile_base() const { return tile_base_; }
    float tile_value(std::size_t t) const { return tile_values_[t]; }
    int tile_level(std::size_t t) const { return tile_levels_[t]; }
    bool voxel_inside(float v) const { return v + s_ <= 0; }

    // Inside tile item holding c (c not in a leaf), else -1.
    int tile_item(const Coord& c, int depth) const {
        if (depth < 0 || tile_index_.empty()) return -1;  // background: outside
        const int dim = tile_dim_at_depth(depth);
        const Coord origin(c[0] & ~(dim - 1), c[1] & ~(dim - 1), c[2] & ~(dim - 1));
        auto it = tile_index_.find(origin);
        return it == tile_index_.end() ? -1 : int(tile_base_ + it->second);
    }

    // Item holding coordinate c if it is inside, else -1.
    long long inside_item(ConstAccessor& acc, const Coord& c) const {
        const int depth = acc.getValueDepth(c);
        if (depth == int(FloatTree::DEPTH) - 1) {
            const LeafT* leaf = acc.probeConstLeaf(c);
            const openvdb::Index off = LeafT::coordToOffset(c);
            if (!voxel_inside(leaf->getValue(off))) return -1;
            return (long long)(leaf_index_.at(leaf)) * LeafT::SIZE + off;
        }
        return tile_item(c, depth);
    }

    // The block with origin o (a multiple of 8).
    BlockRef block_at(ConstAccessor& acc, const Coord& o) const {
        BlockRef b;
        const int depth = acc.getValueDepth(o);
        if (depth == int(FloatTree::DEPTH) - 1) {
            b.leaf = leaf_index_.at(acc.probeConstLeaf(o));
            return b;
        }
        b.value = acc.getValue(o);
        b.tile_item = tile_item(o, depth);
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
    std::unordered_map<const LeafT*, int> leaf_index_;
    std::size_t tile_base_ = 0;
    std::vector<openvdb::CoordBBox> tiles_;
    std::vector<float> tile_values_;
    std::vector<int> tile_levels_;
    std::unordered_map<Coord, int, CoordHash> tile_index_;
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
    void set_parent(int x, int p) { parent_[x].store(p, std::memory_order_relaxed); }
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

// 26-neighbourhood dilation within the leaf.
LeafMask dilate26(const LeafMask& f) {
    constexpr std::uint64_t z0 = 0x0101010101010101ull, z7 = 0x8080808080808080ull;  // z = 0, z = 7
    LeafMask yz, out;
    for (int x = 0; x < kLeafDim; ++x) {
        const std::uint64_t w = f[std::size_t(x)];
        const std::uint64_t d = w | ((w << 1) & ~z0) | ((w >> 1) & ~z7);  // z +- 1 within each row
        yz[std::size_t(x)] = d | (d << 8) | (d >> 8);                       // y +- 1
    }
    for (int x = 0; x < kLeafDim; ++x)
        out[std::size_t(x)] = yz[std::size_t(x)] | (x > 0 ? yz[std::size_t(x - 1)] : 0) |
                              (x + 1 < kLeafDim ? yz[std::size_t(x + 1)] : 0);
    return out;
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

// Labels per item (-1: outside) and per-leaf-voxel boundary flags (an inside voxel with an
// outside 26-neighbour), from the parallel connected-component search.
struct Labelling {
    std::vector<int> label;
    std::vector<std::uint8_t> boundary;
    int count = 0;
};

// The parallel connected-component search of find_fragments (its steps 1-3): inside items are
// united in a ConcurrentForest, voxels with their 26 neighbours, tiles with their 6 face
// neighbours, then numbered in order of their smallest item (deterministic).
class ComponentSearch {
public:
    // Polls `cancel` per leaf, tile and chunk of items: each is well under a millisecond.
    ComponentSearch(const ItemIndex& items, const std::vector<BlockNeighbourhood>& nbhd, const CancelToken& cancel)
        : items_(items), nbhd_(nbhd), leaves_(items.leaves()), n_(items.size()), forest_(n_), cancel_(cancel) {}

    Labelling run() {
        mark_inside();
        out_.boundary.assign(leaves_.size() * LeafT::SIZE, 0);
        // 1a. Within each leaf, and its boundary voxels. 1b. Across leaf faces.
        tbb::parallel_for(std::size_t(0), leaves_.size(), [&](std::size_t l) {
            cancel_.poll();
            link_within_leaf(l);
            mark_boundary(l);
        });
        tbb::parallel_for(std::size_t(0), leaves_.size(), [&](std::size_t l) {
            cancel_.poll();
            link_across_faces(l);
        });
        // 2. Tiles with their face neighbours. 3. Components numbered.
        link_tiles();
        number_components();
        return std::move(out_);
    }

private:
    // Inside flags per item and inside bits per leaf; inside tiles are inside by construction.
    void mark_inside() {
        inside_.assign(n_, 0);
        tbb::parallel_for(std::size_t(0), leaves_.size(), [&](std::size_t l) {
            cancel_.poll();
            const LeafT& leaf = *leaves_[l];
            const std::size_t base = l * LeafT::SIZE;
            for (int off = 0; off < kLeafSize; ++off)
                if (items_.voxel_inside(leaf.getValue(openvdb::Index(off)))) inside_[base + off] = 1;
        });
        std::fill(inside_.begin() + std::ptrdiff_t(items_.tile_base()), inside_.end(), std::uint8_t(1));  // inside tiles only
        masks_.assign(leaves_.size(), LeafMask{});
        tbb::parallel_for(std::size_t(0), leaves_.size(), [&](std::size_t l) {
            cancel_.poll();
            for (int off = 0; off < kLeafSize; ++off)
                if (inside_[l * LeafT::SIZE + std::size_t(off)]) masks_[l][std::size_t(off >> 6)] |= std::uint64_t(1) << (off & 63);
        });
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
                                bits = b.tile_item >= 0 ? 0xFFu : 0u;
                            }
                            // Block z in [first, first + count) goes to region z from kPart[bz][0].
                            const int first = kPart[bz][2], count = kPart[bz][1] - kPart[bz][0];
                            const unsigned part = (bits >> first) & ((1u << count) - 1u);
                            rows[std::size_t(x)][std::size_t(y)] |= std::uint16_t(part << kPart[bz][0]);
                        }
                }
        return rows;
    }

    // Is the voxel at local coordinate (x, y, z) of leaf l's block neighbourhood (each in
    // [-8, 16)) inside? Returns its item, or -1.
    long long neighbour_item(std::size_t l, int x, int y, int z) const {
        const int bx = x < 0 ? -1 : (x >= kLeafDim ? 1 : 0), by = y < 0 ? -1 : (y >= kLeafDim ? 1 : 0),
                  bz = z < 0 ? -1 : (z >= kLeafDim ? 1 : 0);
        const BlockRef& b = nbhd_[l][block_slot(bx, by, bz)];
        if (b.leaf < 0) return b.tile_item;
        const long long item = (long long)b.leaf * kLeafSize +
                               LeafT::coordToOffset(Coord(x - bx * kLeafDim, y - by * kLeafDim, z - bz * kLeafDim));
        return inside_[item] ? item : -1;
    }

    // 1a. Within leaf l (26-neighbourhood), on bit masks (word x, bit 8 y + z = offset): each
    // piece is flooded from its smallest offset, to which all its voxels then point.
    void link_within_leaf(std::size_t l) {
        const LeafMask& m = masks_[l];
        LeafMask remaining = m;
        const std::size_t base = l * LeafT::SIZE;
        for (int x = 0; x < kLeafDim; ++x) {
            while (remaining[std::size_t(x)]) {
                LeafMask piece{};
                piece[std::size_t(x)] = remaining[std::size_t(x)] & (~remaining[std::size_t(x)] + 1);  // lowest bit
                const int root = x * 64 + __builtin_ctzll(piece[std::size_t(x)]);
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
                for (int w = 0; w < kLeafDim; ++w) {
                    remaining[std::size_t(w)] &= ~piece[std::size_t(w)];
                    for (std::uint64_t bits = piece[std::size_t(w)]; bits; bits &= bits - 1)
                        forest_.set_parent(int(base + std::size_t(w * 64 + __builtin_ctzll(bits))), int(base + std::size_t(root)));
                }
            }
        }
    }

    // Boundary voxels of leaf l: inside with an outside 26-neighbour, in this leaf or beyond its
    // faces (the outside voxels of the leaf and its 1-voxel ring, dilated by one onto the leaf).
    void mark_boundary(std::size_t l) {
        const LeafMask& m = masks_[l];
        const std::size_t base = l * LeafT::SIZE;
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
            std::uint64_t b = near_outside & m[std::size_t(x)];
            for (; b; b &= b - 1) out_.boundary[base + std::size_t(x * 64 + __builtin_ctzll(b))] = 1;
        }
    }

    // 1b. Across the faces of leaf l: inside voxels with their inside neighbours in other leaves
    // and in inside tiles.
    void link_across_faces(std::size_t l) {
        const std::size_t base = l * LeafT::SIZE;
        int last_a = -1, last_b = -1;
        for (int x = 0; x < kLeafDim; ++x)
            for (int y = 0; y < kLeafDim; ++y)
                for (int z = 0; z < kLeafDim; ++z) {
                    const bool face = x == 0 || y == 0 || z == 0 || x == kLeafDim - 1 || y == kLeafDim - 1 ||
                                      z == kLeafDim - 1;
                    const int off = (x * kLeafDim + y) * kLeafDim + z;
                    if (!face || !inside_[base + off]) continue;
                    for (int dx = -1; dx <= 1; ++dx)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dz = -1; dz <= 1; ++dz) {
                                const int nx = x + dx, ny = y + dy, nz = z + dz;
                                if (nx >= 0 && nx < kLeafDim && ny >= 0 && ny < kLeafDim && nz >= 0 && nz < kLeafDim)
                                    continue;
                                const long long other = neighbour_item(l, nx, ny, nz);
                                // A voxel-voxel edge is seen from both ends: take it from the
                                // smaller item only. Tiles do not look back at voxels.
                                if (other < 0 || (other < (long long)items_.tile_base() && other < (long long)(base + off)))
                                    continue;
                                // Uniting ancestors is the same as uniting the items; runs of
                                // face voxels mostly repeat the previous pair of pieces.
                                const int a = forest_.parent(int(base + off)), b = forest_.parent(int(other));
                                if (a == last_a && b == last_b) continue;
                                last_a = a;
                                last_b = b;
                                forest_.unite(a, b);
                            }
                }
    }

    // 2. Tiles: one probe just beyond each face (ch. 6.3). A neighbour at least as large as
    // the tile covers the whole face, so this probe finds it; smaller neighbours (voxels,
    // smaller tiles) find the tile from their own side.
    void link_tiles() {
        tbb::enumerable_thread_specific<ConstAccessor> accs([&] { return items_.accessor(); });
        tbb::parallel_for(std::size_t(0), items_.tiles().size(), [&](std::size_t t) {
            cancel_.poll();
            ConstAccessor& acc = accs.local();
            const int item = int(items_.tile_base() + t);
            const openvdb::CoordBBox& b = items_.tiles()[t];
            const Coord probes[6] = {b.min().offsetBy(-1, 0, 0), b.min().offsetBy(0, -1, 0), b.min().offsetBy(0, 0, -1),
                                     b.max().offsetBy(1, 0, 0),  b.max().offsetBy(0, 1, 0),  b.max().offsetBy(0, 0, 1)};
            for (const Coord& p : probes) {
                const long long other = items_.inside_item(acc, p);
                if (other >= 0) forest_.unite(item, int(other));
            }
        });
    }

    // 3. Components numbered in order of their smallest item, which is their root.
    void number_components() {
        const std::size_t n = n_;
        out_.label.assign(n, -1);
        constexpr std::size_t kChunk = 1 << 16;  // fixed chunks: the numbering is a plain prefix count
        const std::size_t chunks = (n + kChunk - 1) / kChunk;
        std::vector<int> roots_in_chunk(chunks, 0);
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            cancel_.poll();
            int roots = 0;
            for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
                if (!inside_[i]) continue;
                const int r = forest_.find(int(i));
                if (r == int(i)) ++roots;
            }
            roots_in_chunk[c] = roots;
        });
        std::vector<int> first_label(chunks, 0);
        for (std::size_t c = 1; c < chunks; ++c) first_label[c] = first_label[c - 1] + roots_in_chunk[c - 1];
        out_.count = chunks ? first_label.back() + roots_in_chunk.back() : 0;
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            cancel_.poll();
            int next = first_label[c];
            for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i)
                if (inside_[i] && forest_.parent(int(i)) == int(i)) out_.label[i] = next++;
        });
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            cancel_.poll();
            for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) {
                if (!inside_[i]) continue;
                const int r = forest_.find(int(i));
                if (r != int(i)) out_.label[i] = out_.label[r];
            }
        });
    }

    const ItemIndex& items_;
    const std::vector<BlockNeighbourhood>& nbhd_;
    const std::vector<const LeafT*>& leaves_;
    const std::size_t n_;
    ConcurrentForest forest_;
    const CancelToken cancel_;
    std::vector<std::uint8_t> inside_;  // per item
    std::vector<LeafMask> masks_;       // per leaf
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
        const Region region = gather_region(nb);
        BlockOutput out;
        if (region.hi_label < 0) return out;  // no inside voxel reaches this block
        const bool one_label = region.lo_label == region.hi_label;
        const std::vector<int> frags = candidate_fragments(region, one_label);
        const std::array<float, kLeafSize> value = block_values(nb);
        for (const int k : frags) {
            std::unique_ptr<LeafT> leaf = fragment_leaf(origin, region, k, one_label, value);
            if (leaf) out.leaves.emplace_back(k, std::move(leaf));
        }
        return out;
    }

private:
    static constexpr int R = kRegion;

    // Item labels and flags (bit 0: inside leaf voxel, bit 1: boundary voxel) over the block and
    // its 2-voxel ring (region index = block coordinate + 2), with the same as row bit masks and
    // the range of labels over inside leaf voxels.
    struct Region {
        std::array<int, R * R * R> label;
        std::array<std::uint8_t, R * R * R> flags;
        RegionRows inside_rows{}, boundary_rows{};
        int lo_label = std::numeric_limits<int>::max(), hi_label = -1;
    };

    // The region filled block by block: for each axis, the region part [begin, end) of the lower,
    // central and upper block and the block coordinate where it starts.
    Region gather_region(const BlockNeighbourhood& nb) const {
        static constexpr int kPart[3][3] = {{0, 2, kLeafDim - 2}, {2, 2 + kLeafDim, 0}, {2 + kLeafDim, R, 0}};
        Region g;
        for (int bx = 0; bx < 3; ++bx)
            for (int by = 0; by < 3; ++by)
                for (int bz = 0; bz < 3; ++bz) {
                    const BlockRef& b = nb[std::size_t(bx * 9 + by * 3 + bz)];
                    const int tile_label = b.tile_item >= 0 ? lab_.label[std::size_t(b.tile_item)] : -1;
                    for (int x = kPart[bx][0]; x < kPart[bx][1]; ++x)
                        for (int y = kPart[by][0]; y < kPart[by][1]; ++y) {
                            const int q0 = (x * R + y) * R;
                            if (b.leaf < 0) {
                                for (int z = kPart[bz][0]; z < kPart[bz][1]; ++z) {
                                    g.label[q0 + z] = tile_label;
                                    g.flags[q0 + z] = 0;
                                }
                                continue;
                            }
                            const std::size_t row = std::size_t(b.leaf) * LeafT::SIZE +
                                                    std::size_t(((x - kPart[bx][0] + kPart[bx][2]) << 6) |
                                                                ((y - kPart[by][0] + kPart[by][2]) << 3));
                            unsigned in_bits = 0, bd_bits = 0;
                            for (int z = kPart[bz][0]; z < kPart[bz][1]; ++z) {
                                const std::size_t item = row + std::size_t(z - kPart[bz][0] + kPart[bz][2]);
                                const int l = lab_.label[item];
                                g.label[q0 + z] = l;
                                const unsigned in = l >= 0, bd = lab_.boundary[item];
                                g.flags[q0 + z] = std::uint8_t(in | (bd << 1));
                                in_bits |= in << z;
                                bd_bits |= bd << z;
                                if (in) {
                                    g.lo_label = std::min(g.lo_label, l);
                                    g.hi_label = std::max(g.hi_label, l);
                                }
                            }
                            g.inside_rows[std::size_t(x)][std::size_t(y)] |= std::uint16_t(in_bits);
                            g.boundary_rows[std::size_t(x)][std::size_t(y)] |= std::uint16_t(bd_bits);
                        }
                }
        return g;
    }

    // Fragments that can write here: inside voxels within 1 (own voxels and their neighbours),
    // boundary voxels within d (the d-ring). Usually one or two; sorted.
    std::vector<int> candidate_fragments(const Region& g, bool one_label) const {
        std::vector<int> frags;
        if (one_label) frags.push_back(g.lo_label);  // then the candidates are just that label
        int last = -1;
        for (int x = 0; x < R && !one_label; ++x)
            for (int y = 0; y < R; ++y)
                for (int z = 0; z < R; ++z) {
                    const int q = (x * R + y) * R + z;
                    const bool near = x >= 1 && x <= R - 2 && y >= 1 && y <= R - 2 && z >= 1 && z <= R - 2;
                    if (!(((g.flags[q] & 1) && near) || ((g.flags[q] & 2) && d_ >= 2))) continue;
                    if (g.label[q] == last) continue;
                    last = g.label[q];
                    if (std::find(frags.begin(), frags.end(), last) == frags.end()) frags.push_back(last);
                }
        std::sort(frags.begin(), frags.end());
        return frags;
    }

    // The input's values over the central block (a leaf's voxels or its tile's value).
    std::array<float, kLeafSize> block_values(const BlockNeighbourhood& nb) const {
        std::array<float, kLeafSize> value;
        const BlockRef& centre = nb[13];
        for (int off = 0; off < kLeafSize; ++off)
            value[std::size_t(off)] = centre.leaf >= 0 ? items_.leaves()[std::size_t(centre.leaf)]->getValue(openvdb::Index(off))
                                                       : centre.value;
        return value;
    }

    // Fragment k's leaf over the central block (null when it writes nothing there): its own
    // voxels, their outside 26-neighbours with the input value, and the d-ring.
    std::unique_ptr<LeafT> fragment_leaf(const Coord& origin, const Region& g, int k, bool one_label,
                                         const std::array<float, kLeafSize>& value) const {
        RegionRows inside_k = g.inside_rows, boundary_k = g.boundary_rows;
        for (int x = 0; x < R && !one_label; ++x)
            for (int y = 0; y < R; ++y) {
                unsigned mi = 0, mb = 0;
                for (int z = 0; z < R; ++z) {
                    const int q = (x * R + y) * R + z;
                    if (g.label[q] != k) continue;
                    mi |= unsigned(g.flags[q] & 1) << z;
                    mb |= unsigned((g.flags[q] >> 1) & 1) << z;
                }
                inside_k[x][y] = std::uint16_t(mi);
                boundary_k[x][y] = std::uint16_t(mb);
            }
        const BlockRows copied = dilate_to_block(inside_k, 1);
        BlockRows ring{};
        if (d_ >= 2) ring = dilate_to_block(boundary_k, 2);
        std::unique_ptr<LeafT> leaf;
        for (int x = 0; x < kLeafDim; ++x)
            for (int y = 0; y < kLeafDim; ++y)
                for (int z = 0; z < kLeafDim; ++z) {
                    const int q = ((x + 2) * R + y + 2) * R + z + 2;
                    const bool in_copy = (copied[x][y] >> (z + 2)) & 1, in_ring = (ring[x][y] >> (z + 2)) & 1;
                    const openvdb::Index off = openvdb::Index((x << 6) | (y << 3) | z);
                    float w;
                    if (!voxel_value(g, q, k, in_copy, in_ring, value[off], w)) continue;
                    if (!leaf) leaf = std::make_unique<LeafT>(origin, bg_, false);
                    leaf->setValueOn(off, w);
                }
        return leaf;
    }

    // Fragment k's value w at region voxel q with input value v; false: fragment k writes nothing.
    bool voxel_value(const Region& g, int q, int k, bool in_copy, bool in_ring, float v, float& w) const {
        if (g.label[q] >= 0) {
            // Inside: the fragment's own voxels; another fragment's voxels and tiles within the
            // d-ring get +r_f/2 (never copy a neighbour).
            if (g.label[q] == k) {
                if (!(g.flags[q] & 1)) return false;  // own tile: added as a tile
                w = v;
            } else if (in_ring) {
                w = half_voxel_;
            } else {
                return false;
            }
        } else if (in_copy) {
            w = v;  // outside 26-neighbour: the input value, any sign
        } else if (in_ring) {
            w = v > 0 ? v : v + sf_;  // d-ring: shallow negatives over-segmented
        } else {
            return false;
        }
        return true;
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
    std::sort(extra.begin(), extra.end());
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
// d-ring. Summed in tree order within a fragment (reproducible).
// Polled every 65536 values.
void measure_fragment(const openvdb::FloatGrid& g, double r_f, Fragment& f, const CancelToken& cancel) {
    double w_sum = 0;
    Vec3 wx = Vec3::Zero();
    Coord lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
    std::size_t visited = 0;
    for (auto it = g.tree().cbeginValueAll(); it; ++it) {
        if ((++visited & 65535u) == 0) cancel.poll();
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
        std::const_pointer_cast<LevelSetGrid>(result.fragments[i].grid.grid)->grid->setName("fragment" + std::to_string(i));
}

}  // namespace

Fragments find_fragments_voxelwise(const LevelSet& broken, const SegmentOptions& options) {
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
    for (std::size_t t = 0; t < items.tiles().size(); ++t) tiles_of[lab.label[items.tile_base() + t]].push_back(t);

    Fragments result;
    result.voxel_size = r_f;
    result.threshold = s;
    result.used_tiles = options.use_tiles;
    result.fragments.resize(count);
    tbb::parallel_for(0, count, [&](int k) {
        cancel.poll();
        const openvdb::FloatGrid::Ptr grid = fragment_grid(in, items, leaves_of[k], tiles_of[k], cancel);
        Fragment& f = result.fragments[k];
        f.active_voxels = grid->activeVoxelCount();
        measure_fragment(*grid, r_f, f, cancel);
        f.grid = wrap_grid(grid, r_f, broken.half_width);
    });
    order_fragments(result);
    return result;
}

}  // namespace cf::reference
