#include "bvh/build_bvh.h"

#include <algorithm>
#include <atomic>
#include <thread>

namespace raycast {

namespace {

// Subtrees at least this large are built as separate pieces that may run on their own thread.
// The choice depends on the size alone, so the tree is the same for any thread count.
constexpr uint32_t kParallelSubtreeSize = 16384;
constexpr int kMaxBins = 32;

Vec3f centroid(const Bounds3f& b) { return b.lower * 0.5f + b.upper * 0.5f; }

struct Range {
    uint32_t begin = 0, end = 0;
    Bounds3f bounds;           // of the primitives
    Bounds3f centroid_bounds;  // of their centres, which decide the split
    uint32_t size() const { return end - begin; }
};

struct Split {
    int axis = -1;
    int bin = 0;  // primitives in bins [0, bin) go left
    float cost = 0;
    Range left, right;
};

class Builder {
public:
    Builder(BvhPrimitive* primitives, const BvhBuildOptions& options)
        : primitives_(primitives),
          options_(options),
          bin_count_(std::clamp(options.bin_count, 2, kMaxBins)),
          max_leaf_(std::max(1, options.max_leaf_size)),
          spare_threads_(std::max(0, options.threads - 1)) {}

    Range make_range(uint32_t begin, uint32_t end) const {
        Range range{begin, end, {}, {}};
        for (uint32_t i = begin; i < end; ++i) {
            range.bounds.grow(primitives_[i].bounds);
            range.centroid_bounds.grow(centroid(primitives_[i].bounds));
        }
        return range;
    }

    // Builds the subtree for `range` with its root at nodes[root] (already allocated).
    void build(const Range& range, std::vector<BvhNode>& nodes, uint32_t root, int depth) {
        nodes[root].bounds = range.bounds;
        const uint32_t count = range.size();
        Split split;
        if (count > 1 && depth < kMaxSahDepth) split = find_sah_split(range);
        const float leaf_cost = static_cast<float>(count);
        if (count <= static_cast<uint32_t>(max_leaf_) && (split.axis < 0 || leaf_cost <= split.cost)) {
            make_leaf(nodes[root], range);
            return;
        }
        if (split.axis >= 0) {
            partition(range, split);
        } else {
            split = median_split(range);  // no useful SAH plane, or the tree is already deep
        }

        if (count >= kParallelSubtreeSize) {
            build_children_as_pieces(split, nodes, root, depth);
            return;
        }
        const uint32_t first_child = static_cast<uint32_t>(nodes.size());
        nodes[root].first = first_child;
        nodes[root].count = 0;
        nodes.resize(nodes.size() + 2);
        build(split.left, nodes, first_child, depth + 1);
        build(split.right, nodes, first_child + 1, depth + 1);
    }

private:
    void make_leaf(BvhNode& node, const Range& range) const {
        node.first = range.begin;
        node.count = range.size();
    }

    int bin_of(float c, float lower, float scale) const {
        const float f = (c - lower) * scale;
        // Written so that a NaN or an overflow lands in a valid bin instead of an invalid int.
        if (!(f > 0)) return 0;
        if (f >= static_cast<float>(bin_count_ - 1)) return bin_count_ - 1;
        return static_cast<int>(f);
    }

    // Sorts the primitives into bin_count_ bins along each axis and evaluates the SAH at every
    // plane between bins (Wald, "On fast construction of SAH-based bounding volume hierarchies").
    Split find_sah_split(const Range& range) const {
        struct Bin {
            Bounds3f bounds, centroid_bounds;
            uint32_t count = 0;
        };
        Split best;
        const float parent_area = range.bounds.half_area();
        const Vec3f lower = range.centroid_bounds.lower;
        const Vec3f extent = range.centroid_bounds.extent();
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0)) continue;
            const float scale = static_cast<float>(bin_count_) / extent[axis];
            Bin bins[kMaxBins];
            for (uint32_t i = range.begin; i < range.end; ++i) {
                const Bounds3f& b = primitives_[i].bounds;
                const Vec3f c = centroid(b);
                Bin& bin = bins[bin_of(c[axis], lower[axis], scale)];
                bin.bounds.grow(b);
                bin.centroid_bounds.grow(c);
                ++bin.count;
            }
            // Sweep from the right, remembering the right side's area·count at every plane.
            float right_cost[kMaxBins];
            Bounds3f accumulated;
            uint32_t accumulated_count = 0;
            for (int plane = bin_count_ - 1; plane > 0; --plane) {
                accumulated.grow(bins[plane].bounds);
                accumulated_count += bins[plane].count;
                right_cost[plane] = accumulated.half_area() * static_cast<float>(accumulated_count);
            }
            accumulated = Bounds3f{};
            accumulated_count = 0;
            for (int plane = 1; plane < bin_count_; ++plane) {
                accumulated.grow(bins[plane - 1].bounds);
                accumulated_count += bins[plane - 1].count;
                if (accumulated_count == 0 || accumulated_count == range.size()) continue;
                const float cost = options_.traversal_cost +
                                   (accumulated.half_area() * static_cast<float>(accumulated_count) +
                                    right_cost[plane]) /
                                       parent_area;
                if (best.axis < 0 || cost < best.cost) {
                    best.axis = axis;
                    best.bin = plane;
                    best.cost = cost;
                }
            }
            if (best.axis == axis) {
                // Keep the children's boxes, so the recursion need not scan them again.
                Range left, right;
                for (int b = 0; b < bin_count_; ++b) {
                    Range& side = b < best.bin ? left : right;
                    side.bounds.grow(bins[b].bounds);
                    side.centroid_bounds.grow(bins[b].centroid_bounds);
                }
                best.left = left;
                best.right = right;
            }
        }
        if (best.axis >= 0 && !(best.cost == best.cost)) best.axis = -1;  // NaN areas: give up on SAH
        return best;
    }

    void partition(const Range& range, Split& split) const {
        const int axis = split.axis;
        const float lower = range.centroid_bounds.lower[axis];
        const float scale = static_cast<float>(bin_count_) / range.centroid_bounds.extent()[axis];
        BvhPrimitive* middle =
            std::partition(primitives_ + range.begin, primitives_ + range.end, [&](const BvhPrimitive& p) {
                return bin_of(centroid(p.bounds)[axis], lower, scale) < split.bin;
            });
        const uint32_t mid = static_cast<uint32_t>(middle - primitives_);
        split.left.begin = range.begin;
        split.left.end = mid;
        split.right.begin = mid;
        split.right.end = range.end;
    }

    // Halves the primitives by centroid along the widest axis: always makes progress, so the
    // depth stays logarithmic below kMaxSahDepth and for primitives that share one centroid.
    Split median_split(const Range& range) const {
        const int axis = max_axis(range.centroid_bounds.extent());
        const uint32_t mid = range.begin + range.size() / 2;
        std::nth_element(primitives_ + range.begin, primitives_ + mid, primitives_ + range.end,
                         [axis](const BvhPrimitive& a, const BvhPrimitive& b) {
                             const float ca = centroid(a.bounds)[axis], cb = centroid(b.bounds)[axis];
                             return ca < cb || (ca == cb && a.id < b.id);
                         });
        Split split;
        split.axis = axis;
        split.left = make_range(range.begin, mid);
        split.right = make_range(mid, range.end);
        return split;
    }

    // Builds both children into vectors of their own (in parallel when a thread is free) and
    // appends them. In a piece, node 0 is the child itself and its other nodes follow.
    void build_children_as_pieces(const Split& split, std::vector<BvhNode>& nodes, uint32_t root, int depth) {
        std::vector<BvhNode> left(1), right(1);
        auto build_left = [&] { build(split.left, left, 0, depth + 1); };
        if (take_spare_thread()) {
            std::thread worker(build_left);
            build(split.right, right, 0, depth + 1);
            worker.join();
            spare_threads_.fetch_add(1);
        } else {
            build_left();
            build(split.right, right, 0, depth + 1);
        }
        const uint32_t first_child = static_cast<uint32_t>(nodes.size());
        nodes[root].first = first_child;
        nodes[root].count = 0;
        nodes.resize(nodes.size() + 2);
        append_piece(left, nodes, first_child);
        left = {};
        append_piece(right, nodes, first_child + 1);
    }

    static void append_piece(const std::vector<BvhNode>& piece, std::vector<BvhNode>& nodes, uint32_t slot) {
        const uint32_t base = static_cast<uint32_t>(nodes.size());
        auto relocate = [base](BvhNode node) {
            if (!node.is_leaf()) node.first = base + node.first - 1;
            return node;
        };
        nodes[slot] = relocate(piece[0]);
        nodes.reserve(nodes.size() + piece.size() - 1);
        for (size_t i = 1; i < piece.size(); ++i) nodes.push_back(relocate(piece[i]));
    }

    bool take_spare_thread() {
        int available = spare_threads_.load();
        while (available > 0)
            if (spare_threads_.compare_exchange_weak(available, available - 1)) return true;
        return false;
    }

    BvhPrimitive* primitives_;
    const BvhBuildOptions& options_;
    int bin_count_;
    int max_leaf_;
    std::atomic<int> spare_threads_;
};

double sah_cost_of(const Bvh& bvh, uint32_t index, const BvhBuildOptions& options) {
    const BvhNode& node = bvh.nodes[index];
    const double area = node.bounds.half_area();
    if (node.is_leaf()) return area * node.count;
    return area * options.traversal_cost + sah_cost_of(bvh, node.first, options) +
           sah_cost_of(bvh, node.first + 1, options);
}

}  // namespace

Bvh build_bvh(std::vector<BvhPrimitive> primitives, const BvhBuildOptions& options) {
    primitives.erase(std::remove_if(primitives.begin(), primitives.end(),
                                    [](const BvhPrimitive& p) { return p.bounds.is_empty(); }),
                     primitives.end());
    Bvh bvh;
    if (primitives.empty()) return bvh;
    Builder builder(primitives.data(), options);
    const Range all = builder.make_range(0, static_cast<uint32_t>(primitives.size()));
    // A tree has at most 2n - 1 nodes; about n / 2 is typical with leaves of four.
    bvh.nodes.reserve(primitives.size() < kParallelSubtreeSize ? 2 * primitives.size() : 8);
    bvh.nodes.resize(1);
    builder.build(all, bvh.nodes, 0, 0);
    bvh.nodes.shrink_to_fit();
    bvh.prim_order.resize(primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) bvh.prim_order[i] = primitives[i].id;
    return bvh;
}

double sah_cost(const Bvh& bvh, const BvhBuildOptions& options) {
    if (bvh.empty()) return 0;
    const double root_area = bvh.nodes[0].bounds.half_area();
    const double total = sah_cost_of(bvh, 0, options);
    return root_area > 0 ? total / root_area : total;
}

}  // namespace raycast
