// OpenVDB translation unit: level-set CSG (eq. (6.1)) and level-set pruning that stop within
// milliseconds of Ctrl-C (issue 16). openvdb::tools::csgDifference / csgUnion / pruneLevelSet run
// one tree-wide parallel pass each with no interrupter: on a 1 mm box the CSG of the broken object
// went 0.5 s (loaded machine) without a check. These run OpenVDB's own node operators
// (CsgDifferenceOp, CsgUnionOp, LevelSetPruneOp) through the same node managers, in the same
// order, so the trees are bit-identical to the tools' (tests/levelset/polled_csg_test.cpp); the
// only change is a poll of the cancel token before every node, which throws Cancelled out of the
// parallel loop (oneTBB cancels the loop and rethrows on the caller). A cancelled call leaves its
// arguments half-combined: callers discard them.
#include "nodes/levelset/level_set_grid.hpp"

#include <openvdb/tools/Composite.h>
#include <openvdb/tools/Merge.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/NodeManager.h>

#include <tbb/parallel_for.h>

#include <memory>
#include <vector>

namespace cf {
namespace {

using FloatTree = openvdb::FloatTree;

// A node operator of either manager with a poll in front. Holds the operator by reference: the
// managers copy their functors into every task.
template <typename Op>
struct Polled {
    const Op& op;
    CancelToken cancel;
    // DynamicNodeManager (top-down, with the node's index; returns whether to descend).
    template <typename NodeT>
    bool operator()(NodeT& node, std::size_t index) const {
        cancel.poll();
        return op(node, index);
    }
    // NodeManager (bottom-up).
    template <typename NodeT>
    void operator()(NodeT& node) const {
        cancel.poll();
        op(node);
    }
};

// openvdb::tools::csgDifference / csgUnion with a node operator of theirs: a = op(a, b), b emptied
// (its nodes are moved into a), then the level-set prune.
template <template <typename> class CsgOp>
void csg_polled(openvdb::FloatGrid& a, openvdb::FloatGrid& b, const CancelToken& cancel) {
    cancel.poll();
    openvdb::tools::composite::validateLevelSet(a.tree(), "A");
    openvdb::tools::composite::validateLevelSet(b.tree(), "B");
    CsgOp<FloatTree> op(b.tree(), openvdb::Steal());
    op.setPruneCancelledTiles(false);  // the tools' default (prune, no cancelled-tile pruning)
    openvdb::tree::DynamicNodeManager<FloatTree> nodes(a.tree());
    nodes.foreachTopDown(Polled<CsgOp<FloatTree>>{op, cancel});
    prune_level_set_polled(a.tree(), cancel);
}

}  // namespace

// Grid::deepCopy copies the tree in one parallel pass with no interrupter (0.25 s idle for the
// 1 mm box of the Ctrl-C test, over a second on a loaded machine). Here the nodes one level above
// the leaves (128^3 voxels, at most 4096 leaves: a few milliseconds each) are copied on parallel
// tasks, polled per node, with OpenVDB's own copy constructor (masks, tiles and leaves as they
// are); the nodes above them are made anew with the input's tiles and the copies hung in: the same
// tree, node for node and value for value. (Adding every leaf copy to an empty tree one by one, as
// before, took 10-30 ms on one core per segmentation while the other idled.)
openvdb::FloatGrid::Ptr deep_copy_polled(const openvdb::FloatGrid& in, const CancelToken& cancel) {
    using RootT = FloatTree::RootNodeType;
    using UpperT = RootT::ChildNodeType;   // 4096^3 voxels
    using LowerT = UpperT::ChildNodeType;  // 128^3 voxels
    cancel.poll();
    openvdb::FloatGrid::Ptr out = in.copyWithNewTree();  // metadata, class, background
    out->setTransform(in.transform().copy());             // not shared with `in`
    std::vector<const LowerT*> lowers;
    in.tree().getNodes(lowers);
    std::vector<std::unique_ptr<LowerT>> copies(lowers.size());
    tbb::parallel_for(std::size_t(0), lowers.size(), [&](std::size_t l) {
        cancel.poll();
        copies[l] = std::make_unique<LowerT>(*lowers[l]);
    });
    cancel.poll();
    const float background = in.background();
    RootT& root = out->tree().root();
    std::size_t next = 0;  // getNodes lists the lower nodes in tree order, upper node by upper node
    for (auto it = in.tree().root().cbeginChildAll(); it; ++it) {
        float tile = 0;
        const UpperT* upper = it.probeChild(tile);
        if (!upper) {
            root.addTile(it.getCoord(), tile, it.isValueOn());
            continue;
        }
        auto copy = std::make_unique<UpperT>(upper->origin(), background, false);
        for (auto c = upper->cbeginChildAll(); c; ++c) {
            float v = 0;
            if (c.probeChild(v)) {
                if (next >= copies.size() || copies[next]->origin() != c.getCoord())
                    throw std::logic_error("deep_copy_polled: lower nodes out of tree order");
                copy->addChild(copies[next++].release());
            } else {
                copy->addTile(c.pos(), v, c.isValueOn());
            }
        }
        root.addChild(copy.release());
    }
    return out;
}

void prune_level_set_polled(FloatTree& tree, const CancelToken& cancel) {
    prune_level_set_polled(tree, tree.background(), openvdb::math::negative(tree.background()), cancel);
}

void prune_level_set_polled(FloatTree& tree, float outside, float inside, const CancelToken& cancel) {
    cancel.poll();
    openvdb::tree::NodeManager<FloatTree, FloatTree::DEPTH - 2> nodes(tree);
    const openvdb::tools::LevelSetPruneOp<FloatTree> op(tree, outside, inside);
    nodes.foreachBottomUp(Polled<openvdb::tools::LevelSetPruneOp<FloatTree>>{op, cancel});
}

// As openvdb::tools::csgDifference(a, b): a = max(a, -b).
void csg_difference_polled(openvdb::FloatGrid& a, openvdb::FloatGrid& b, const CancelToken& cancel) {
    csg_polled<openvdb::tools::CsgDifferenceOp>(a, b, cancel);
}

// As openvdb::tools::csgUnion(a, b): a = min(a, b).
void csg_union_polled(openvdb::FloatGrid& a, openvdb::FloatGrid& b, const CancelToken& cancel) {
    csg_polled<openvdb::tools::CsgUnionOp>(a, b, cancel);
}

}  // namespace cf
