// Tests for the wide BVH (bvh/wide_bvh.h): the collapsed tree must hold every primitive in exactly
// one leaf, keep every box inside its parent's, fill its nodes as the collapse promises, have the
// leaves of the binary tree it comes from, and not depend on the thread count. Traversal against
// brute force is tested at the scene level (bvh_test.cpp, scene/mesh_kernel_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

#include "bvh/build_bvh.h"
#include "bvh/wide_bvh.h"
#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // tests/trace_test_support.h

struct LeafRef {
    uint32_t first, count;
    bool operator<(const LeafRef& o) const { return std::tie(first, count) < std::tie(o.first, o.count); }
    bool operator==(const LeafRef& o) const { return first == o.first && count == o.count; }
};

// Checks the invariants of a wide tree over `prims` (ids = their index) and returns its leaves.
// With `full_nodes`, a node with free slots must have only leaves as children (the collapse of a
// whole binary tree stops opening children only when none is left to open).
std::vector<LeafRef> check_wide_tree(const WideBvh& bvh, const std::vector<BvhPrimitive>& prims, int max_leaf_size,
                                     bool full_nodes) {
    Bounds3f all;
    const std::vector<uint32_t> ids = ids_with_boxes(prims, all);
    std::vector<LeafRef> leaves;
    if (ids.empty()) {
        EXPECT_TRUE(bvh.empty());
        return leaves;
    }
    EXPECT_FALSE(bvh.empty());
    if (bvh.empty()) return leaves;
    std::vector<uint32_t> order = bvh.prim_order;
    std::sort(order.begin(), order.end());
    EXPECT_EQ(order, ids) << "prim_order is not a permutation of the non-empty primitives";
    EXPECT_TRUE(contains(bvh.bounds, all));

    std::vector<int> node_seen(bvh.nodes.size(), 0), slot_seen(bvh.prim_order.size(), 0);
    struct Item {
        uint32_t node;
        Bounds3f parent_box;
        int depth;
    };
    std::vector<Item> stack{{0, bvh.bounds, 0}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        if (item.node >= bvh.nodes.size() || node_seen[item.node]++ > 0) {
            ADD_FAILURE() << "node " << item.node << " out of range or reached twice";
            return leaves;
        }
        EXPECT_LE(item.depth, kMaxBvhDepth);
        const WideBvhNode& node = bvh.nodes[item.node];
        EXPECT_GE(node.child_count, 1u);
        EXPECT_LE(node.child_count, static_cast<uint32_t>(kWideBvhWidth));
        bool all_leaves = true;
        for (uint32_t slot = 0; slot < static_cast<uint32_t>(kWideBvhWidth); ++slot) {
            const Bounds3f b = child_bounds(node, slot);
            if (slot >= node.child_count) {
                EXPECT_TRUE(b.is_empty() && node.child[slot] == 0 && node.prim_count[slot] == 0)
                    << "node " << item.node << ": empty slot " << slot << " is not empty";
                continue;
            }
            EXPECT_TRUE(contains(item.parent_box, b)) << "node " << item.node << " slot " << slot << " leaves its parent";
            const uint32_t child = node.child[slot];
            if (!is_wide_leaf(child)) {
                all_leaves = false;
                EXPECT_EQ(node.prim_count[slot], 0u);
                stack.push_back({child, b, item.depth + 1});
                continue;
            }
            const LeafRef leaf{child & kWidePayloadMask, node.prim_count[slot]};
            leaves.push_back(leaf);
            EXPECT_GE(leaf.count, 1u);
            EXPECT_LE(leaf.count, static_cast<uint32_t>(max_leaf_size));
            if (size_t{leaf.first} + leaf.count > bvh.prim_order.size()) {
                ADD_FAILURE() << "leaf past prim_order";
                continue;
            }
            for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
                ++slot_seen[i];
                const uint32_t id = bvh.prim_order[i];
                if (id < prims.size()) {
                    EXPECT_TRUE(contains(b, prims[id].bounds)) << "prim " << id << " outside its leaf";
                }
            }
        }
        if (full_nodes && node.child_count < static_cast<uint32_t>(kWideBvhWidth)) {
            EXPECT_TRUE(all_leaves) << "node " << item.node << " has free slots and an inner child";
        }
    }
    for (size_t i = 0; i < slot_seen.size(); ++i)
        EXPECT_EQ(slot_seen[i], 1) << "prim_order slot " << i << " is in " << slot_seen[i] << " leaves";
    for (size_t i = 0; i < node_seen.size(); ++i) EXPECT_EQ(node_seen[i], 1) << "node " << i << " is unreachable";
    std::sort(leaves.begin(), leaves.end());
    return leaves;
}

// Field by field: the node's padding bytes are not part of it.
bool same_node(const WideBvhNode& a, const WideBvhNode& b) {
    return std::memcmp(a.bounds, b.bounds, sizeof a.bounds) == 0 &&
           std::memcmp(a.child, b.child, sizeof a.child) == 0 &&
           std::memcmp(a.prim_count, b.prim_count, sizeof a.prim_count) == 0 && a.child_count == b.child_count;
}

// The leaves of a binary tree, as (first, count).
std::vector<LeafRef> binary_leaves(const Bvh& bvh) {
    std::vector<LeafRef> leaves;
    for (const BvhNode& node : bvh.nodes)
        if (node.is_leaf()) leaves.push_back({node.first, node.count});
    std::sort(leaves.begin(), leaves.end());
    return leaves;
}

TEST(WideBvh, NothingToBuildGivesAnEmptyTree) {
    EXPECT_TRUE(build_wide_bvh({}, BvhBuildOptions{}).empty());
    std::vector<BvhPrimitive> only_empty(3);
    for (uint32_t i = 0; i < 3; ++i) only_empty[i].id = i;
    EXPECT_TRUE(build_wide_bvh(only_empty, BvhBuildOptions{}).empty());
    EXPECT_TRUE(collapse_bvh(Bvh{}).empty());
}

TEST(WideBvh, OneLeafGetsARootNodeWithOneChild) {
    const std::vector<BvhPrimitive> prims{{box({1, 2, 3}, {4, 5, 6}), 7}};
    const WideBvh bvh = build_wide_bvh(prims, BvhBuildOptions{});
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].child_count, 1u);
    EXPECT_EQ(bvh.nodes[0].child[0], kWideLeafFlag | 0u);
    EXPECT_EQ(bvh.nodes[0].prim_count[0], 1u);
    EXPECT_EQ(bvh.prim_order, std::vector<uint32_t>{7});
    check_wide_tree(bvh, prims, 4, true);
}

// Sets child `slot` of `node` to `child` with the box [lower, upper].
void set_child(WideBvhNode& node, uint32_t slot, uint32_t child, Vec3f lower, Vec3f upper) {
    node.child[slot] = child;
    for (int axis = 0; axis < 3; ++axis) {
        node.bounds[axis][0][slot] = lower[axis];
        node.bounds[axis][1][slot] = upper[axis];
    }
    node.child_count = std::max(node.child_count, slot + 1);
}

TEST(WideBvh, MedianLeafSizeIsTheMiddleOfTheLeavesLargestSides) {
    EXPECT_EQ(median_leaf_size(WideBvh{}), 0.0f);
    // Leaves of largest sides 1 (x), 2 (y) and 5 (z) under the root, 3 and 4 under an inner child;
    // the inner child's own box (side 9) is not a leaf's.
    WideBvh bvh;
    bvh.nodes.resize(2);
    set_child(bvh.nodes[0], 0, kWideLeafFlag | 0, {0, 0, 0}, {1, 0.5f, 0.25f});
    set_child(bvh.nodes[0], 1, kWideLeafFlag | 1, {-1, -1, -1}, {-0.5f, 1, -0.5f});
    set_child(bvh.nodes[0], 2, 1, {0, 0, 0}, {9, 9, 9});
    set_child(bvh.nodes[0], 3, kWideLeafFlag | 2, {2, 2, -3}, {2, 2, 2});
    set_child(bvh.nodes[1], 0, kWideLeafFlag | 3, {0, 0, 0}, {3, 1, 1});
    set_child(bvh.nodes[1], 1, kWideLeafFlag | 4, {4, 0, 0}, {5, 4, 0});
    EXPECT_EQ(median_leaf_size(bvh), 3.0f);
    // An even count: the upper of the two middle sizes (3 and 4 of 1, 2, 3, 4, 5, 6).
    set_child(bvh.nodes[1], 2, kWideLeafFlag | 5, {0, 0, 0}, {0, 6, 0});
    EXPECT_EQ(median_leaf_size(bvh), 4.0f);
}

TEST(WideBvh, InvariantsHoldAndTheLeavesAreTheBinaryTreesForManyInputs) {
    std::mt19937 rng(41);
    struct Config {
        int max_leaf;
        float traversal_cost;
        int test_width;
    };
    for (const Config& config : {Config{1, 1, 1}, Config{4, 2, 1}, Config{8, 1, 8}, Config{16, 1, 4}}) {
        BvhBuildOptions options;
        options.max_leaf_size = config.max_leaf;
        options.traversal_cost = config.traversal_cost;
        options.leaf_test_width = config.test_width;
        for (size_t count : {size_t{2}, size_t{9}, size_t{100}, size_t{5000}}) {
            SCOPED_TRACE("max leaf " + std::to_string(config.max_leaf) + ", " + std::to_string(count) + " boxes");
            std::vector<BvhPrimitive> prims = random_boxes(rng, count, 10, 2);
            if (count == 100)  // some empty boxes, which stay out of the tree
                for (size_t i = 0; i < count; i += 7) prims[i].bounds = Bounds3f{};
            if (count == 5000)  // many equal boxes: median splits
                for (size_t i = 0; i < 2000; ++i) prims[i].bounds = prims[i % 5].bounds;
            const Bvh binary = build_bvh(prims, options);
            const WideBvh wide = build_wide_bvh(prims, options);
            const WideBvh collapsed = collapse_bvh(binary);
            EXPECT_EQ(wide.prim_order, binary.prim_order);
            EXPECT_EQ(collapsed.prim_order, binary.prim_order);
            const std::vector<LeafRef> leaves = binary_leaves(binary);
            EXPECT_TRUE(check_wide_tree(wide, prims, config.max_leaf, true) == leaves);
            EXPECT_TRUE(check_wide_tree(collapsed, prims, config.max_leaf, true) == leaves);
            // Below the size of one build piece both are the same collapse of the same tree.
            ASSERT_EQ(wide.nodes.size(), collapsed.nodes.size());
            for (size_t i = 0; i < wide.nodes.size(); ++i)
                ASSERT_TRUE(same_node(wide.nodes[i], collapsed.nodes[i])) << "node " << i;
        }
    }
}

TEST(WideBvh, LargeInputsBuiltInPiecesKeepTheBinaryLeavesAndDoNotDependOnThreads) {
    // Above 16384 primitives the build splits the top of the tree and builds pieces on threads;
    // each piece is collapsed on its own, then the top.
    std::mt19937 rng(42);
    std::vector<BvhPrimitive> prims = random_boxes(rng, 70000, 50, 2);
    for (size_t i = 0; i < 20000; ++i) prims[i].bounds = prims[i % 7].bounds;
    BvhBuildOptions options;
    options.max_leaf_size = 8;
    options.leaf_test_width = 8;
    options.threads = 1;
    const Bvh binary = build_bvh(prims, options);
    const WideBvh one = build_wide_bvh(prims, options);
    EXPECT_EQ(one.prim_order, binary.prim_order);
    // Where the top meets a piece a node may keep free slots, so nodes need not be full here.
    EXPECT_TRUE(check_wide_tree(one, prims, options.max_leaf_size, false) == binary_leaves(binary));
    for (int threads : {2, 3}) {
        options.threads = threads;
        const WideBvh many = build_wide_bvh(prims, options);
        ASSERT_EQ(many.nodes.size(), one.nodes.size()) << threads << " threads";
        EXPECT_EQ(many.prim_order, one.prim_order);
        for (size_t i = 0; i < one.nodes.size(); ++i)
            ASSERT_TRUE(same_node(many.nodes[i], one.nodes[i])) << threads << " threads, node " << i;
    }
    // The collapse keeps nodes well filled: well over half the slots are used.
    size_t children = 0;
    for (const WideBvhNode& node : one.nodes) children += node.child_count;
    EXPECT_GT(static_cast<double>(children) / static_cast<double>(one.nodes.size()), kWideBvhWidth / 2.0);
}

TEST(WideBvh, LeafTestWidthMakesTheSahFillLeaves) {
    // Eight unit boxes in a row, apart: one primitive at a time, splitting pays; eight at a time
    // (one SIMD test for the whole row), a single leaf is cheapest.
    std::vector<BvhPrimitive> row;
    for (uint32_t i = 0; i < 8; ++i) {
        const float x = 3.0f * static_cast<float>(i);
        row.push_back({box({x, 0, 0}, {x + 1, 1, 1}), i});
    }
    BvhBuildOptions options;
    options.max_leaf_size = 8;
    EXPECT_FALSE(build_bvh(row, options).nodes[0].is_leaf());
    options.leaf_test_width = 8;
    const Bvh one_leaf = build_bvh(row, options);
    ASSERT_TRUE(one_leaf.nodes[0].is_leaf());
    EXPECT_EQ(one_leaf.nodes[0].count, 8u);
    EXPECT_DOUBLE_EQ(sah_cost(one_leaf, options), 1.0);  // one test of the root's whole area
}

}  // namespace
}  // namespace raycast
