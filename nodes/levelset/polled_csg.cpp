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
// 1 mm box of the Ctrl-C test, over a second on a loaded machine). Here the leaves are copied in
// parallel, polled per leaf, then hung into an empty tree with the same background, followed by
// every tile of every level (active or not, inside or outside): the same tree, value for value.
openvdb::FloatGrid::Ptr deep_copy_polled(const openvdb::FloatGrid& in, const CancelToken& cancel) {
    using LeafT = FloatTree::LeafNodeType;
    cancel.poll();
    openvdb::FloatGrid::Ptr out = in.copyWithNewTree();  // metadata, class, background
    out->setTransform(in.transform().copy());             // not shared with `in`
    std::vector<const LeafT*> leaves;
    leaves.reserve(in.tree().leafCount());
    in.tree().getNodes(leaves);
    std::vector<std::unique_ptr<LeafT>> copies(leaves.size());
    tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t l) {
        cancel.poll();
        copies[l] = std::make_unique<LeafT>(*leaves[l]);
    });
    FloatTree& tree = out->tree();
    for (std::size_t l = 0; l < copies.size(); ++l) {
        if ((l & 4095u) == 0) cancel.poll();
        tree.addLeaf(copies[l].release());
    }
    auto it = in.tree().cbeginValueAll();
    it.setMaxDepth(FloatTree::ValueAllCIter::LEAF_DEPTH - 1);  // tiles only, not the voxels
    std::size_t tiles = 0;
    for (; it; ++it) {
        if ((++tiles & 4095u) == 0) cancel.poll();
        tree.addTile(it.getLevel(), it.getCoord(), *it, it.isValueOn());
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
