// A BVH with up to kWideBvhWidth children per node, collapsed from the binned-SAH binary tree of
// build_bvh.h. A node keeps its children's boxes side by side (one array per bound), so one SIMD
// slab test checks every child of a node at once. Like Bvh it knows boxes and primitive ranges
// only: what a leaf holds is up to its user, who may replace the leaves' payloads with its own.
// Entry points: WideBvh, WideBvhNode, build_wide_bvh, collapse_bvh.
#pragma once

#include <cstdint>
#include <vector>

#include "base/large_allocator.h"
#include "bvh/build_bvh.h"
#include "math/bounds.h"

namespace raycast {

/// Children per node: 8 boxes are one AVX register per bound, and the tree has half the levels
/// of a 4-wide one; measured 13-18% fewer cycles per ray than 4 (docs/performance.md). The
/// builder and the kernels also work for 4.
constexpr int kWideBvhWidth = 8;

/// A child reference whose top bit is set is a leaf (the other 31 bits are its payload);
/// otherwise it is the index of an inner node.
constexpr uint32_t kWideLeafFlag = 0x80000000u;
constexpr uint32_t kWidePayloadMask = 0x7fffffffu;

/// 256 bytes (8 children), four cache lines. Children fill slots [0, child_count); the other
/// slots hold empty boxes (lower +inf, upper -inf) that no ray enters. The child references come
/// first, so that the four lines a box test reads also hold the child it picks (no second,
/// dependent miss), and each axis's lower and upper bounds are 32 bytes apart, so that a
/// traversal finds an axis's far bound from its near one with one XOR.
struct alignas(64) WideBvhNode {
    uint32_t child[kWideBvhWidth];  ///< an inner node's index, or kWideLeafFlag | payload
    /// bounds[axis][0][slot] is child slot's lower bound on the axis, bounds[axis][1][slot] its
    /// upper one: the children's boxes, one bound of every child side by side.
    float bounds[3][2][kWideBvhWidth];
    /// A leaf's primitives are prim_order[payload, payload + prim_count) as built; 0 for inner
    /// children and empty slots.
    uint16_t prim_count[kWideBvhWidth];
    uint32_t child_count = 0;
};
static_assert(sizeof(WideBvhNode) == 32 * kWideBvhWidth, "a wide node should fill whole cache lines exactly");

struct WideBvh {
    LargeVector<WideBvhNode> nodes;    ///< nodes[0] is the root; empty when there is nothing
    std::vector<uint32_t> prim_order;  ///< the primitives' ids in leaf order
    Bounds3f bounds;                   ///< the root's box: every child box lies inside it

    bool empty() const { return nodes.empty(); }
};

inline bool is_wide_leaf(uint32_t child) { return (child & kWideLeafFlag) != 0; }

/// The box of a node's child slot.
inline Bounds3f child_bounds(const WideBvhNode& node, uint32_t slot) {
    return {{node.bounds[0][0][slot], node.bounds[1][0][slot], node.bounds[2][0][slot]},
            {node.bounds[0][1][slot], node.bounds[1][1][slot], node.bounds[2][1][slot]}};
}

/// Builds the binary SAH tree of build_bvh() (same options, same leaves, same prim_order) and
/// collapses it as it goes: each subtree built on a thread is collapsed at once and its binary
/// nodes dropped, so the whole binary tree never exists. Consumes `primitives`.
WideBvh build_wide_bvh(std::vector<BvhPrimitive> primitives, const BvhBuildOptions& options);

/// Collapses a binary tree: each wide node takes the frontier of a binary node, opening the child
/// with the largest surface area until kWideBvhWidth children are reached or only leaves are left.
WideBvh collapse_bvh(const Bvh& binary);

/// The median of the leaves' sizes, a leaf's size being its box's largest side (of an even
/// count, the upper of the two middle ones); 0 for an empty tree. How big a typical leaf is: a
/// packet tracer compares it with how far apart its rays lie.
float median_leaf_size(const WideBvh& bvh);

}  // namespace raycast
