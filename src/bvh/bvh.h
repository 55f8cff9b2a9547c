// A bounding volume hierarchy that knows nothing about what it bounds: it is built from boxes
// (build_bvh.h) and traversed with a callback that intersects the primitives of a leaf.
// Entry points: Bvh, BoxRay, intersect_box, traverse_bvh.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "base/check.h"
#include "base/large_allocator.h"
#include "math/bounds.h"
#include "math/ray.h"

namespace raycast {

/// 32 bytes. A leaf (count > 0) holds primitives [first, first + count) of Bvh::prim_order; an
/// inner node (count == 0) has its two children side by side at `first` and `first + 1`.
struct BvhNode {
    Bounds3f bounds;
    uint32_t first = 0;
    uint32_t count = 0;

    bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhNode) == 32, "a node should fill half a cache line");

struct Bvh {
    LargeVector<BvhNode> nodes;        ///< nodes[0] is the root; empty when there is nothing
    std::vector<uint32_t> prim_order;  ///< the primitives' ids in leaf order

    bool empty() const { return nodes.empty(); }
};

/// Deepest tree the builder makes (it switches to median splits before) and so the traversal
/// stack size. Median splits below depth kMaxSahDepth add at most 32 more levels.
constexpr int kMaxBvhDepth = 128;
constexpr int kMaxSahDepth = 64;

/// How far past the current closest hit a box may start and still be visited. A little slack
/// keeps near-ties (two triangles meeting at an edge, in different leaves) from depending on the
/// order of traversal, so every traversal path finds the same closest hit.
inline float cull_distance(float t_best) { return t_best + std::fabs(t_best) * (1.0f / 1024); }

/// The nearest a hit may lie, in a BVH leaf whose box the ray enters at `leaf_entry`: a little
/// before the entry (half the cull slack, so that cull_distance of a hit there still reaches the
/// entry). A hit reported nearer could be found or not depending on the order of traversal: a
/// hit found first elsewhere, between the two, culls the leaf. So every path moves such a hit up
/// to the floor (at_leaf_floor). A true hit lies inside its leaf's box, and its computed t comes
/// that near only by rounding: a triangle 2000 wide seen from 0.1 above its plane (the t of its
/// watertight test, a weighted sum of corner distances near 1000, is then off by a few parts in
/// 10^4), or a triangle 1e18 long seen from near one end, whose test can report a hit well
/// before its box (docs/reliability.md, finding 11). Moving the hit keeps it, where dropping it
/// would leave holes in the first.
inline float leaf_floor(float leaf_entry) { return leaf_entry - std::fabs(leaf_entry) * (1.0f / 2048); }

/// A hit at `t` in a leaf whose box the ray enters at `leaf_entry`, moved up to leaf_floor.
inline float at_leaf_floor(float t, float leaf_entry) {
    const float floor = leaf_floor(leaf_entry);
    return t < floor ? floor : t;
}

/// A ray prepared for box tests: 1/direction with zero components replaced by tiny ones, so that
/// no 0·∞ makes a NaN.
struct BoxRay {
    Vec3f origin;
    Vec3f inv_direction;
    float t_min = 0;
};

inline float safe_inverse(float d) {
    constexpr float kTiny = 1e-30f;
    return 1.0f / (std::fabs(d) < kTiny ? std::copysign(kTiny, d) : d);
}

inline BoxRay make_box_ray(const Ray& ray, float t_min) {
    return {ray.origin,
            {safe_inverse(ray.direction.x), safe_inverse(ray.direction.y), safe_inverse(ray.direction.z)},
            t_min};
}

/// Slab test. The interval is widened by a few float roundings on each side (pbrt-v4's
/// 1 + 2γ₃), so a box is never missed by a ray that really meets it. Widening the largest entry
/// and the smallest exit is the same as widening every slab's (x − |x|·w only grows with x), and
/// takes two operations instead of six. Returns the entry t.
inline bool intersect_box(const Bounds3f& box, const BoxRay& ray, float t_cull, float& t_entry) {
    constexpr float kWiden = 4 * 5.96046448e-08f;  // a little more than 2γ₃ for float
    float entry = -INFINITY, exit = INFINITY;
    for (int axis = 0; axis < 3; ++axis) {
        float near = (box.lower[axis] - ray.origin[axis]) * ray.inv_direction[axis];
        float far = (box.upper[axis] - ray.origin[axis]) * ray.inv_direction[axis];
        if (near > far) std::swap(near, far);
        entry = near > entry ? near : entry;
        exit = far < exit ? far : exit;
    }
    entry -= std::fabs(entry) * kWiden;
    exit += std::fabs(exit) * kWiden;
    const float t0 = entry > ray.t_min ? entry : ray.t_min;
    const float t1 = exit < t_cull ? exit : t_cull;
    t_entry = t0;
    return t0 <= t1;
}

/// Visits the leaves whose boxes the ray meets, nearer child first, skipping boxes that start
/// beyond cull_distance(t_best()). For each leaf calls visit_leaf(first, count, t_entry), t_entry
/// being where the ray enters the leaf's box (for at_leaf_floor), which returns true to stop (an
/// any-hit query that found a hit). Returns true if it was stopped.
/// `t_best` is re-read after every leaf, so the leaf callback may shrink it. If `nodes_visited`
/// is given, every node whose box is tested adds one to it.
template <typename TBestFn, typename LeafFn>
bool traverse_bvh(const Bvh& bvh, const BoxRay& ray, TBestFn&& t_best, LeafFn&& visit_leaf,
                  uint64_t* nodes_visited = nullptr) {
    if (bvh.empty()) return false;
    if (nodes_visited) ++*nodes_visited;
    const BvhNode* nodes = bvh.nodes.data();
    float t_entry;
    if (!intersect_box(nodes[0].bounds, ray, cull_distance(t_best()), t_entry)) return false;
    struct Pending {
        uint32_t node;
        float t_entry;
    };
    Pending stack[kMaxBvhDepth];
    int stack_size = 0;
    uint32_t current = 0;
    float current_entry = t_entry;  // where the ray enters nodes[current]'s box
    for (;;) {
        RAYCAST_DCHECK(current < bvh.nodes.size());
        const BvhNode& node = nodes[current];
        if (node.is_leaf()) {
            RAYCAST_DCHECK(uint64_t{node.first} + node.count <= bvh.prim_order.size());
            if (visit_leaf(node.first, node.count, current_entry)) return true;
        } else {
            RAYCAST_DCHECK(uint64_t{node.first} + 1 < bvh.nodes.size());
            const float t_cull = cull_distance(t_best());
            if (nodes_visited) *nodes_visited += 2;
            float t_left, t_right;
            const bool hit_left = intersect_box(nodes[node.first].bounds, ray, t_cull, t_left);
            const bool hit_right = intersect_box(nodes[node.first + 1].bounds, ray, t_cull, t_right);
            if (hit_left && hit_right) {
                const bool left_first = t_left <= t_right;
                RAYCAST_DCHECK(stack_size < kMaxBvhDepth);
                stack[stack_size++] = left_first ? Pending{node.first + 1, t_right} : Pending{node.first, t_left};
                current = left_first ? node.first : node.first + 1;
                current_entry = left_first ? t_left : t_right;
                continue;
            }
            if (hit_left || hit_right) {
                current = hit_left ? node.first : node.first + 1;
                current_entry = hit_left ? t_left : t_right;
                continue;
            }
        }
        // Pop the next subtree that may still hold something nearer than the best hit.
        for (;;) {
            if (stack_size == 0) return false;
            const Pending next = stack[--stack_size];
            if (next.t_entry <= cull_distance(t_best())) {
                current = next.node;
                current_entry = next.t_entry;
                break;
            }
        }
    }
}

}  // namespace raycast
