// Binned surface-area-heuristic (SAH) BVH construction over primitive boxes, with the top of the
// tree built on several threads. The tree depends only on the boxes, never on the thread count.
#pragma once

#include <vector>

#include "bvh/bvh.h"

namespace raycast {

/// One primitive to build over: its box and the id that Bvh::prim_order will report.
struct BvhPrimitive {
    Bounds3f bounds;
    uint32_t id = 0;
};

struct BvhBuildOptions {
    int max_leaf_size = 4;       ///< a leaf never holds more primitives than this
    int bin_count = 16;          ///< SAH candidate planes per axis and node
    float traversal_cost = 1.0f; ///< cost of an inner node relative to one leaf test
    /// Primitives one leaf test handles at once (a SIMD width): the SAH counts a leaf of n
    /// primitives as ceil(n / leaf_test_width) tests, so it prefers leaves that fill them.
    int leaf_test_width = 1;
    int threads = 1;             ///< threads that may build subtrees at once
};

/// Builds the tree; consumes (reorders) `primitives`. Empty boxes are allowed: those primitives
/// are kept out of the tree (they can never be hit).
Bvh build_bvh(std::vector<BvhPrimitive> primitives, const BvhBuildOptions& options);

/// The sum of SAH costs, for tests and benchmarks: the expected cost of a random ray relative to
/// one primitive test, normalised by the root's area.
double sah_cost(const Bvh& bvh, const BvhBuildOptions& options);

}  // namespace raycast
