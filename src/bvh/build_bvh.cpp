#include "bvh/build_bvh.h"

#include "bvh/wide_bvh.h"

#ifdef __GLIBC__
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

#include "base/parallel.h"

namespace raycast {

namespace {

// Subtrees smaller than this are built as one piece, serially; the nodes above them (the "top")
// are split with the binning spread over threads. The choice depends on the sizes alone, so the
// tree is the same for any thread count.
constexpr uint32_t kPieceSize = 16384;
// Primitives per task when binning a top node in parallel.
constexpr uint32_t kBinningChunk = 32768;
constexpr int kMaxBins = 32;

Vec3f centroid(const Bounds3f& b) { return (b.lower + b.upper) * 0.5f; }

#if defined(__SSE2__)
// The box whose corners are the first three lanes of `lower` and `upper`.
Bounds3f box_of_lanes(__m128 lower, __m128 upper) {
    alignas(16) float lo[4], hi[4];
    _mm_store_ps(lo, lower);
    _mm_store_ps(hi, upper);
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}
#endif

// What a leaf of `count` primitives costs in the SAH: one test per `test_width` of them.
float leaf_test_cost(uint32_t count, int test_width) {
    const uint32_t width = static_cast<uint32_t>(std::max(1, test_width));
    return static_cast<float>(width == 1 ? count : (count + width - 1) / width);
}

// Boxes are stored a little larger than their contents: one float step outwards on every side,
// and at least kMinPad. A ray whose direction component is 0 gets 1/1e-30 = 1e30 as its inverse
// (bvh.h, safe_inverse); if its origin lay exactly in a face plane, (face - origin)·1e30 would be
// 0 and the slab would close at t = 0, losing the box. With the face moved past every vertex it
// bounds by at least kMinPad, that product is at least 1e10, beyond any t a scene produces. The
// absolute minimum matters only for coordinates within about 1e-13 of zero.
constexpr float kMinPad = 1e-20f;

Bounds3f pad_box(Bounds3f b) {
    for (int axis = 0; axis < 3; ++axis) {
        b.lower[axis] = std::min(std::nextafter(b.lower[axis], -INFINITY), b.lower[axis] - kMinPad);
        b.upper[axis] = std::max(std::nextafter(b.upper[axis], INFINITY), b.upper[axis] + kMinPad);
    }
    return b;
}

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

struct Bin {
    Bounds3f bounds;
    uint32_t count = 0;
};

// Bins of all three axes, filled in one pass over the primitives.
struct Bins {
    Bin axis[3][kMaxBins];

    void merge(const Bins& other, int bin_count) {
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < bin_count; ++b) {
                axis[a][b].bounds.grow(other.axis[a][b].bounds);
                axis[a][b].count += other.axis[a][b].count;
            }
    }
};

// Where a centroid falls among `bin_count` bins that span the centroid box.
struct Binning {
    Vec3f lower;
    Vec3f scale;  // bins per unit length; 0 on an axis with no extent
    int bin_count;

    int bin_of(float c, int axis) const {
        const float f = (c - lower[axis]) * scale[axis];
        // Written so that a NaN or an overflow lands in a valid bin instead of an invalid int.
        if (!(f > 0)) return 0;
        if (f >= static_cast<float>(bin_count - 1)) return bin_count - 1;
        return static_cast<int>(f);
    }
};


WideBvhNode empty_wide_node() {
    WideBvhNode node;
    for (int axis = 0; axis < 3; ++axis)
        for (int slot = 0; slot < kWideBvhWidth; ++slot) {
            node.bounds[axis][0][slot] = INFINITY;
            node.bounds[axis][1][slot] = -INFINITY;
        }
    for (int slot = 0; slot < kWideBvhWidth; ++slot) {
        node.child[slot] = 0;
        node.prim_count[slot] = 0;
    }
    node.child_count = 0;
    return node;
}

void set_child_box(WideBvhNode& node, int slot, const Bounds3f& box) {
    for (int axis = 0; axis < 3; ++axis) {
        node.bounds[axis][0][slot] = box.lower[axis];
        node.bounds[axis][1][slot] = box.upper[axis];
    }
}

// A leaf as a wide node's child: its primitive range.
void set_leaf_child(WideBvhNode& node, int slot, uint32_t first, uint32_t count) {
    node.child[slot] = kWideLeafFlag | first;
    node.prim_count[slot] = static_cast<uint16_t>(count);
}

// Turns a binary tree into wide nodes. Each wide node takes the two children of a binary inner
// node and keeps opening the one with the largest surface area (the likeliest to be entered)
// until it has kWideBvhWidth children or only unopenable ones. Nodes are written depth first,
// each before its subtrees. `Tree` says what may be opened (Tree::Ref, openable, children, box)
// and writes the children that are not (terminal: a leaf, or a piece built elsewhere).
template <typename Tree, typename Nodes>
class Collapser {
public:
    using Ref = typename Tree::Ref;

    Collapser(const Tree& tree, Nodes& out) : tree_(tree), out_(out) {}

    // Writes the wide node for the openable `ref` and everything below it; returns its index.
    uint32_t emit(Ref ref) {
        Ref slots[kWideBvhWidth];
        int count = 2;
        tree_.children(ref, slots[0], slots[1]);
        while (count < kWideBvhWidth) {
            int widest = -1;
            float widest_area = -1;
            for (int i = 0; i < count; ++i) {
                if (!tree_.openable(slots[i])) continue;
                const float area = tree_.box(slots[i]).half_area();
                if (widest < 0 || area > widest_area) {
                    widest = i;
                    widest_area = area;
                }
            }
            if (widest < 0) break;
            // Its two children take its place, in order, so leaves keep their binary order.
            for (int i = count; i > widest + 1; --i) slots[i] = slots[i - 1];
            tree_.children(slots[widest], slots[widest], slots[widest + 1]);
            ++count;
        }
        const uint32_t index = static_cast<uint32_t>(out_.size());
        out_.push_back(empty_wide_node());
        for (int i = 0; i < count; ++i) {
            set_child_box(out_[index], i, tree_.box(slots[i]));
            if (!tree_.openable(slots[i])) tree_.terminal(slots[i], index, i, out_[index]);
        }
        out_[index].child_count = static_cast<uint32_t>(count);
        for (int i = 0; i < count; ++i)
            if (tree_.openable(slots[i])) {
                const uint32_t child = emit(slots[i]);  // may move out_: index, not a reference
                out_[index].child[i] = child;
            }
        return index;
    }

private:
    const Tree& tree_;
    Nodes& out_;
};

// A binary node array (one piece, or a whole Bvh) as the collapse sees it. Inner nodes'
// `first` is relative to `nodes`; leaves' `first` indexes prim_order.
struct BinaryTree {
    using Ref = uint32_t;
    const BvhNode* nodes;

    bool openable(Ref ref) const { return !nodes[ref].is_leaf(); }
    void children(Ref ref, Ref& left, Ref& right) const {
        left = nodes[ref].first;
        right = left + 1;
    }
    const Bounds3f& box(Ref ref) const { return nodes[ref].bounds; }
    void terminal(Ref ref, uint32_t, int slot, WideBvhNode& node) const {
        set_leaf_child(node, slot, nodes[ref].first, nodes[ref].count);
    }
};

// A tree of a single leaf still gets a root node, so that traversal always starts at one.
WideBvhNode root_of_one_leaf(const BvhNode& leaf) {
    WideBvhNode node = empty_wide_node();
    set_child_box(node, 0, leaf.bounds);
    set_leaf_child(node, 0, leaf.first, leaf.count);
    node.child_count = 1;
    return node;
}

class Builder {
public:
    Builder(BvhPrimitive* primitives, const BvhBuildOptions& options)
        : primitives_(primitives),
          options_(options),
          bin_count_(std::clamp(options.bin_count, 2, kMaxBins)),
          max_leaf_(std::max(1, options.max_leaf_size)),
          test_width_(std::max(1, options.leaf_test_width)),
          threads_(std::max(1, options.threads)) {}

    Range make_range(uint32_t begin, uint32_t end) const {
        Range range{begin, end, {}, {}};
        for (uint32_t i = begin; i < end; ++i) {
            range.bounds.grow(primitives_[i].bounds);
            range.centroid_bounds.grow(centroid(primitives_[i].bounds));
        }
        return range;
    }

    // 1. Splits the top of the tree, down to ranges smaller than kPieceSize (the pieces), then
    // 2. builds the pieces, each serially, as many at once as there are threads. After this the
    // primitives are in their final order and no longer needed.
    void build_pieces(const Range& all) {
        split_top_into_pieces(all);
        // Every piece gets room for its largest possible tree (2n - 1 nodes for n primitives) in
        // one pool. Only the pages a piece fills are ever touched, so the pool costs about what the
        // nodes do; and being one allocation, it goes back to the system when freed.
        piece_offset_.resize(pieces_.size() + 1);
        for (size_t i = 0; i < pieces_.size(); ++i)
            piece_offset_[i + 1] = piece_offset_[i] + 2 * size_t{pieces_[i].range.size()};
        // malloc, not new[]: BvhNode's initialisers would write (and so commit) every page.
        pool_.reset(static_cast<BvhNode*>(std::malloc(piece_offset_.back() * sizeof(BvhNode))));
        if (!pool_) throw std::bad_alloc();
        piece_size_.assign(pieces_.size(), 0);
        parallel_for(pieces_.size(), threads_, [&](size_t i, int) {
            NodeSink sink{pool_.get() + piece_offset_[i], 1};
            build(pieces_[i].range, sink, 0, pieces_[i].depth);
            piece_size_[i] = sink.size;
        });
    }

    // 3. Lays everything out in one array and frees the pool.
    LargeVector<BvhNode> assemble() {
        size_t total = 2 * top_.size() + 1;
        for (uint32_t size : piece_size_) total += size - 1;
        LargeVector<BvhNode> nodes;
        nodes.reserve(total);
        nodes.resize(1);
        emit(root_, nodes, 0);
        pool_.reset();
        return nodes;
    }


    // The wide build, steps 2 and 3: each piece is built as a binary tree in its thread's scratch
    // space and collapsed at once, so only the wide nodes are kept (about a quarter of the
    // binary tree's bytes). After this the primitives are in their final order.
    void build_wide_pieces(const Range& all) {
        split_top_into_pieces(all);
        wide_pieces_.resize(pieces_.size());
        // Each thread reuses its own room for a piece's binary and wide nodes; a piece keeps an
        // exact-size copy of its wide nodes, so that no slack of a growing vector (half as much
        // again) stays resident beside the primitives at the build's peak.
        struct Scratch {
            std::vector<BvhNode> binary;
            std::vector<WideBvhNode> wide;
        };
        std::vector<Scratch> scratch(static_cast<size_t>(threads_));
        parallel_for(pieces_.size(), threads_, [&](size_t i, int worker) {
            Scratch& room = scratch[static_cast<size_t>(worker)];
            room.binary.resize(2 * size_t{pieces_[i].range.size()});
            NodeSink sink{room.binary.data(), 1};
            build(pieces_[i].range, sink, 0, pieces_[i].depth);
            WidePiece& piece = wide_pieces_[i];
            piece.root = room.binary[0];
            const BinaryTree tree{room.binary.data()};
            if (!tree.openable(0)) return;
            room.wide.clear();
            Collapser<BinaryTree, std::vector<WideBvhNode>>(tree, room.wide).emit(0);
            piece.nodes.assign(room.wide.begin(), room.wide.end());
        });
    }

    // The wide build, step 4: the top of the tree is collapsed too, then everything is laid out
    // in one array: the top's nodes, then each piece's, in piece order (as in assemble()).
    LargeVector<WideBvhNode> assemble_wide() {
        LargeVector<WideBvhNode> nodes;
        if (root_ < 0) {  // one piece is the whole tree
            WidePiece& piece = wide_pieces_[static_cast<size_t>(~root_)];
            if (piece.nodes.empty()) {
                nodes.push_back(root_of_one_leaf(piece.root));
            } else {
                nodes.assign(piece.nodes.begin(), piece.nodes.end());
            }
            return nodes;
        }
        std::vector<WideBvhNode> top;
        TopTree tree{this, {}};
        Collapser<TopTree, std::vector<WideBvhNode>>(tree, top).emit(root_);
        std::vector<uint32_t> base(wide_pieces_.size());
        size_t total = top.size();
        for (size_t i = 0; i < wide_pieces_.size(); ++i) {
            base[i] = static_cast<uint32_t>(total);
            total += wide_pieces_[i].nodes.size();
        }
        nodes.reserve(total);
        nodes.assign(top.begin(), top.end());
        for (const PieceLink& link : tree.links) {
            const WidePiece& piece = wide_pieces_[link.piece];
            if (piece.nodes.empty())
                set_leaf_child(nodes[link.node], link.slot, piece.root.first, piece.root.count);
            else
                nodes[link.node].child[link.slot] = base[link.piece];
        }
        for (size_t i = 0; i < wide_pieces_.size(); ++i) {
            for (WideBvhNode node : wide_pieces_[i].nodes) {
                for (uint32_t slot = 0; slot < node.child_count; ++slot)
                    if (!is_wide_leaf(node.child[slot])) node.child[slot] += base[i];
                nodes.push_back(node);
            }
            std::vector<WideBvhNode>().swap(wide_pieces_[i].nodes);
        }
        return nodes;
    }

private:
    // A child of a top node: another top node (>= 0) or a piece (~index, < 0).
    using ChildRef = int64_t;
    struct TopNode {
        Bounds3f bounds;
        ChildRef child[2];
    };
    struct Piece {
        Range range;
        int depth;
    };
    // A piece of the wide build: its binary root, and its wide nodes unless that root is a leaf
    // (local indices: node 0 is the piece's root).
    struct WidePiece {
        BvhNode root;
        std::vector<WideBvhNode> nodes;
    };
    // Where a collapsed top node refers to a piece, to be filled once the pieces are placed.
    struct PieceLink {
        uint32_t node;
        int slot;
        size_t piece;
    };
    // The top of the tree as the collapse sees it: pieces cannot be opened (they are collapsed
    // already); each reference to one is noted in `links`.
    struct TopTree {
        using Ref = ChildRef;
        const Builder* builder;
        mutable std::vector<PieceLink> links;

        bool openable(Ref ref) const { return ref >= 0; }
        void children(Ref ref, Ref& left, Ref& right) const {
            const TopNode& node = builder->top_[static_cast<size_t>(ref)];
            left = node.child[0];
            right = node.child[1];
        }
        Bounds3f box(Ref ref) const {
            if (ref >= 0) return pad_box(builder->top_[static_cast<size_t>(ref)].bounds);
            return builder->wide_pieces_[static_cast<size_t>(~ref)].root.bounds;
        }
        void terminal(Ref ref, uint32_t node, int slot, WideBvhNode&) const {
            links.push_back({node, slot, static_cast<size_t>(~ref)});
        }
    };

    // The top of a subtree: its top nodes and pieces in the order a serial split makes them (a
    // node, then its left subtree's, then its right subtree's), referring to each other by their
    // indices here.
    struct TopPart {
        std::vector<TopNode> nodes;
        std::vector<Piece> pieces;
    };

    // Splits `range` down to pieces into `part` with `threads` threads; returns its root. Where
    // both sides of a split will be split again, they are split at once, half the threads each,
    // each into a part of its own, appended afterwards in the serial order: the top is the same
    // for any number of threads. (Serially, the top of a 5M-triangle build ran on one thread for
    // a quarter of the build's time: its partitions, and the binning of ranges too small to bin
    // in parallel.)
    ChildRef split_top(const Range& range, int depth, int threads, TopPart& part) {
        if (range.size() < kPieceSize) {
            part.pieces.push_back({range, depth});
            return ~static_cast<ChildRef>(part.pieces.size() - 1);
        }
        Split split;
        if (depth < kMaxSahDepth) split = find_sah_split(range, threads);
        if (split.axis >= 0)
            partition(range, split);
        else
            split = median_split(range);
        const size_t index = part.nodes.size();
        part.nodes.push_back({range.bounds, {0, 0}});
        ChildRef left, right;
        if (threads > 1 && split.left.size() >= kPieceSize && split.right.size() >= kPieceSize) {
            TopPart sides[2];
            ChildRef roots[2];
            const int side_threads[2] = {threads - threads / 2, threads / 2};
            parallel_for(2, 2, [&](size_t side, int) {
                roots[side] = split_top(side == 0 ? split.left : split.right, depth + 1, side_threads[side], sides[side]);
            });
            left = append_top_part(part, sides[0], roots[0]);
            right = append_top_part(part, sides[1], roots[1]);
        } else {
            left = split_top(split.left, depth + 1, threads, part);
            right = split_top(split.right, depth + 1, threads, part);
        }
        part.nodes[index].child[0] = left;
        part.nodes[index].child[1] = right;
        return static_cast<ChildRef>(index);
    }

    // Moves `side` to the end of `part`, its references shifted to their new places; returns
    // where its root went.
    static ChildRef append_top_part(TopPart& part, TopPart& side, ChildRef root) {
        const ChildRef node_base = static_cast<ChildRef>(part.nodes.size());
        const ChildRef piece_base = static_cast<ChildRef>(part.pieces.size());
        auto moved = [&](ChildRef ref) { return ref >= 0 ? ref + node_base : ~(~ref + piece_base); };
        for (TopNode& node : side.nodes) {
            node.child[0] = moved(node.child[0]);
            node.child[1] = moved(node.child[1]);
            part.nodes.push_back(node);
        }
        part.pieces.insert(part.pieces.end(), side.pieces.begin(), side.pieces.end());
        return moved(root);
    }

    void split_top_into_pieces(const Range& all) {
        TopPart part;
        root_ = split_top(all, 0, threads_, part);
        top_ = std::move(part.nodes);
        pieces_ = std::move(part.pieces);
    }

    // Writes the subtree `ref` with its root at nodes[slot]; children are appended.
    void emit(ChildRef ref, LargeVector<BvhNode>& nodes, size_t slot) {
        if (ref < 0) {
            const size_t piece = static_cast<size_t>(~ref);
            const BvhNode* piece_nodes = pool_.get() + piece_offset_[piece];
            // In a piece node 0 is its root and the other nodes follow; inner nodes point within it.
            const uint32_t base = static_cast<uint32_t>(nodes.size());
            auto relocate = [base](BvhNode node) {
                if (!node.is_leaf()) node.first = base + node.first - 1;
                return node;
            };
            nodes[slot] = relocate(piece_nodes[0]);
            for (uint32_t i = 1; i < piece_size_[piece]; ++i) nodes.push_back(relocate(piece_nodes[i]));
            return;
        }
        const TopNode& top = top_[static_cast<size_t>(ref)];
        const uint32_t first = static_cast<uint32_t>(nodes.size());
        nodes[slot].bounds = pad_box(top.bounds);
        nodes[slot].first = first;
        nodes[slot].count = 0;
        nodes.resize(nodes.size() + 2);
        emit(top.child[0], nodes, first);
        emit(top.child[1], nodes, first + 1);
    }

    // Where a piece's nodes go: node i at nodes[i], `size` of them so far.
    struct NodeSink {
        BvhNode* nodes;
        uint32_t size;
    };

    // Builds the subtree for `range` with its root at sink.nodes[root] (already allocated).
    void build(const Range& range, NodeSink& sink, uint32_t root, int depth) const {
        // Traversal keeps one stack entry per level (bvh.h, packet_kernel.inl).
        RAYCAST_DCHECK(depth < kMaxBvhDepth);
        BvhNode& node = sink.nodes[root];
        node.bounds = pad_box(range.bounds);
        const uint32_t count = range.size();
        // A split costs the traversal plus terms that are never negative, so a leaf that costs no
        // more than the traversal beats every split, and such a range needs no SAH: with leaves of
        // up to 8 triangles tested 8 at a time, every mesh leaf, about half the nodes.
        const bool fits_leaf = count <= static_cast<uint32_t>(max_leaf_);
        const bool leaf_beats_any_split = fits_leaf && leaf_tests(count) <= options_.traversal_cost;
        Split split;
        if (count > 1 && depth < kMaxSahDepth && !leaf_beats_any_split) split = find_sah_split(range);
        if (leaf_beats_any_split || (fits_leaf && (split.axis < 0 || leaf_tests(count) <= split.cost))) {
            node.first = range.begin;
            node.count = count;
            return;
        }
        if (split.axis >= 0)
            partition(range, split);
        else
            split = median_split(range);  // no useful SAH plane, or the tree is already deep
        const uint32_t first_child = sink.size;
        sink.size += 2;
        node.first = first_child;
        node.count = 0;
        build(split.left, sink, first_child, depth + 1);
        build(split.right, sink, first_child + 1, depth + 1);
    }

    Binning binning_for(const Range& range) const {
        Binning binning{range.centroid_bounds.lower, {}, bin_count_};
        const Vec3f extent = range.centroid_bounds.extent();
        for (int axis = 0; axis < 3; ++axis)
            binning.scale[axis] = extent[axis] > 0 ? static_cast<float>(bin_count_) / extent[axis] : 0.0f;
        return binning;
    }

    void fill_bins(uint32_t begin, uint32_t end, const Binning& binning, Bins& bins) const {
#if defined(__SSE2__)
        // The build's hottest loop, with each box as two 4-wide registers. Every operation is the
        // scalar one lane by lane (IEEE single, no fused multiply-add), so the bins, and the tree,
        // are exactly those of the portable loop below. Arguments are ordered so that a NaN in the
        // primitive is ignored, as Bounds3f::grow does.
        __m128 lower[3][kMaxBins], upper[3][kMaxBins];
        uint32_t counts[3][kMaxBins] = {};
        for (int axis = 0; axis < 3; ++axis)
            for (int b = 0; b < bin_count_; ++b) {
                lower[axis][b] = _mm_set1_ps(INFINITY);
                upper[axis][b] = _mm_set1_ps(-INFINITY);
            }
        const __m128 origin = _mm_setr_ps(binning.lower.x, binning.lower.y, binning.lower.z, 0);
        const __m128 scale = _mm_setr_ps(binning.scale.x, binning.scale.y, binning.scale.z, 0);
        const __m128 last_bin = _mm_set1_ps(static_cast<float>(bin_count_ - 1));
        const __m128 half = _mm_set1_ps(0.5f);
        alignas(16) int32_t index[4];
        for (uint32_t i = begin; i < end; ++i) {
            // lower.xyz + upper.x, and upper.xyz + id: both loads stay inside the primitive.
            const float* box = &primitives_[i].bounds.lower.x;
            const __m128 box_lower = _mm_loadu_ps(box);
            const __m128 box_upper = _mm_loadu_ps(box + 3);
            const __m128 c = _mm_mul_ps(_mm_add_ps(box_lower, box_upper), half);
            __m128 f = _mm_mul_ps(_mm_sub_ps(c, origin), scale);
            f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), last_bin);  // NaN -> 0, as bin_of
            _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm_cvttps_epi32(f));
            for (int axis = 0; axis < 3; ++axis) {
                const int b = index[axis];
                lower[axis][b] = _mm_min_ps(box_lower, lower[axis][b]);
                upper[axis][b] = _mm_max_ps(box_upper, upper[axis][b]);
                ++counts[axis][b];
            }
        }
        for (int axis = 0; axis < 3; ++axis)
            for (int b = 0; b < bin_count_; ++b) {
                if (counts[axis][b] == 0) continue;
                Bin& bin = bins.axis[axis][b];
                bin.bounds.grow(box_of_lanes(lower[axis][b], upper[axis][b]));
                bin.count += counts[axis][b];
            }
#else
        for (uint32_t i = begin; i < end; ++i) {
            const Bounds3f& b = primitives_[i].bounds;
            const Vec3f c = centroid(b);
            for (int axis = 0; axis < 3; ++axis) {
                Bin& bin = bins.axis[axis][binning.bin_of(c[axis], axis)];
                bin.bounds.grow(b);
                ++bin.count;
            }
        }
#endif
    }

    // Sorts the primitives into bins along each axis and evaluates the SAH at every plane between
    // bins (Wald, "On fast construction of SAH-based bounding volume hierarchies", 2007). Large
    // ranges are binned in chunks on several threads; min, max and counts do not depend on the
    // order in which chunks are merged, so neither does the tree.
    // Bins on up to `threads` threads where the range is large enough to share.
    Split find_sah_split(const Range& range, int threads = 1) const {
        const Binning binning = binning_for(range);
        Bins bins_storage;  // 2.7 KB on the stack; freed before the caller recurses
        Bins* bins = &bins_storage;
        if (range.size() >= 2 * kBinningChunk && threads > 1) {
            const size_t chunks = (range.size() + kBinningChunk - 1) / kBinningChunk;
            std::vector<Bins> partial(chunks);
            parallel_for(chunks, threads, [&](size_t chunk, int) {
                const uint32_t begin = range.begin + static_cast<uint32_t>(chunk) * kBinningChunk;
                fill_bins(begin, std::min(range.end, begin + kBinningChunk), binning, partial[chunk]);
            });
            for (const Bins& p : partial) bins->merge(p, bin_count_);
        } else {
            fill_bins(range.begin, range.end, binning, *bins);
        }

        Split best;
        const float parent_area = range.bounds.half_area();
        for (int axis = 0; axis < 3; ++axis) {
            if (binning.scale[axis] == 0) continue;
            const Bin* axis_bins = bins->axis[axis];
            // Sweep from the right, remembering the right side's area·count at every plane.
            float right_cost[kMaxBins];
            Bounds3f accumulated;
            uint32_t accumulated_count = 0;
            // An empty bin changes neither side, so the planes at its edges cost the same: its
            // plane keeps the cost found beside it, and the left sweep passes over the plane
            // above it (a plane only wins at a strictly lower cost, so the first of equal ones
            // stays the choice). Most nodes are small, with more bins than primitives.
            for (int plane = bin_count_ - 1; plane > 0; --plane) {
                if (axis_bins[plane].count == 0 && plane + 1 < bin_count_) {
                    right_cost[plane] = right_cost[plane + 1];
                    continue;
                }
                accumulated.grow(axis_bins[plane].bounds);
                accumulated_count += axis_bins[plane].count;
                right_cost[plane] = accumulated.half_area() * leaf_tests(accumulated_count);
            }
            accumulated = Bounds3f{};
            accumulated_count = 0;
            for (int plane = 1; plane < bin_count_; ++plane) {
                if (axis_bins[plane - 1].count == 0) continue;
                accumulated.grow(axis_bins[plane - 1].bounds);
                accumulated_count += axis_bins[plane - 1].count;
                if (accumulated_count == 0 || accumulated_count == range.size()) continue;
                const float cost =
                    options_.traversal_cost +
                    (accumulated.half_area() * leaf_tests(accumulated_count) + right_cost[plane]) / parent_area;
                if (best.axis < 0 || cost < best.cost) {
                    best.axis = axis;
                    best.bin = plane;
                    best.cost = cost;
                }
            }
        }
        if (best.axis >= 0 && !(best.cost == best.cost)) best.axis = -1;  // NaN areas: give up on SAH
        if (best.axis >= 0) {
            // The children's boxes come from the bins; their centroid boxes from the partition.
            for (int b = 0; b < bin_count_; ++b)
                (b < best.bin ? best.left : best.right).bounds.grow(bins->axis[best.axis][b].bounds);
        }
        return best;
    }

    // Moves the primitives of the left bins before those of the right ones (Hoare's two-pointer
    // scheme, as std::partition does) and gathers each side's centroid box on the way.
    void partition(const Range& range, Split& split) const {
        const Binning binning = binning_for(range);
        const int axis = split.axis;
        BvhPrimitive* first = primitives_ + range.begin;
        BvhPrimitive* last = primitives_ + range.end;
        Bounds3f left_centroids, right_centroids;
#if defined(__SSE2__)
        // Each centroid made once, in one register (as fill_bins makes it, lane by lane the
        // scalar centroid()), and the centroid boxes grown with minps/maxps, whose rule for a NaN
        // is Bounds3f::grow's (min_ignoring_nan): the same boxes as the scalar loop below.
        const __m128 half = _mm_set1_ps(0.5f);
        auto centre = [half](const BvhPrimitive& p) {
            const float* box = &p.bounds.lower.x;  // lower.xyz + upper.x, upper.xyz + id
            return _mm_mul_ps(_mm_add_ps(_mm_loadu_ps(box), _mm_loadu_ps(box + 3)), half);
        };
        auto left_of = [&](__m128 c) {
            alignas(16) float lanes[4];
            _mm_store_ps(lanes, c);
            return binning.bin_of(lanes[axis], axis) < split.bin;
        };
        __m128 left_lower = _mm_set1_ps(INFINITY), left_upper = _mm_set1_ps(-INFINITY);
        __m128 right_lower = left_lower, right_upper = left_upper;
        for (;;) {
            for (; first != last; ++first) {
                const __m128 c = centre(*first);
                if (!left_of(c)) break;
                left_lower = _mm_min_ps(c, left_lower);
                left_upper = _mm_max_ps(c, left_upper);
            }
            for (; first != last; --last) {
                const __m128 c = centre(*(last - 1));
                if (left_of(c)) break;
                right_lower = _mm_min_ps(c, right_lower);
                right_upper = _mm_max_ps(c, right_upper);
            }
            if (first == last) break;
            std::swap(*first, *(last - 1));
        }
        left_centroids = box_of_lanes(left_lower, left_upper);
        right_centroids = box_of_lanes(right_lower, right_upper);
#else
        auto goes_left = [&](const BvhPrimitive& p) { return binning.bin_of(centroid(p.bounds)[axis], axis) < split.bin; };
        for (;;) {
            while (first != last && goes_left(*first)) left_centroids.grow(centroid((first++)->bounds));
            while (first != last && !goes_left(*(last - 1))) right_centroids.grow(centroid((--last)->bounds));
            if (first == last) break;
            std::swap(*first, *(last - 1));
        }
#endif
        const uint32_t mid = static_cast<uint32_t>(first - primitives_);
        split.left.begin = range.begin;
        split.left.end = mid;
        split.left.centroid_bounds = left_centroids;
        split.right.begin = mid;
        split.right.end = range.end;
        split.right.centroid_bounds = right_centroids;
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

    float leaf_tests(uint32_t count) const { return leaf_test_cost(count, test_width_); }

    BvhPrimitive* primitives_;
    const BvhBuildOptions& options_;
    int bin_count_;
    int max_leaf_;
    int test_width_;
    int threads_;
    std::vector<TopNode> top_;
    std::vector<Piece> pieces_;
    std::vector<size_t> piece_offset_;  // piece i's room in pool_ starts here
    std::vector<uint32_t> piece_size_;  // nodes piece i used
    std::vector<WidePiece> wide_pieces_;
    struct Free {
        void operator()(BvhNode* p) const { std::free(p); }
    };
    std::unique_ptr<BvhNode, Free> pool_;
    ChildRef root_ = 0;
};

// The primitives' ids in their order, and the primitives freed. The ids are first packed at the
// front of the primitives' own buffer (id i goes to bytes [4i, 4i + 4), which only overwrites
// primitives already read) and the rest of that buffer goes back to the system, so that the id
// array (4 bytes a primitive) is never allocated beside all the primitives (28 bytes each): at a
// mesh's peak of memory, the mesh and the finished subtrees are resident too.
std::vector<uint32_t> take_ids(std::vector<BvhPrimitive>& primitives) {
    const size_t count = primitives.size();
    unsigned char* bytes = reinterpret_cast<unsigned char*>(primitives.data());
    for (size_t i = 0; i < count; ++i) {
        const uint32_t id = primitives[i].id;
        std::memcpy(bytes + 4 * i, &id, 4);
    }
#if defined(__linux__)
    const uintptr_t page = 4096;
    const uintptr_t keep_end = (reinterpret_cast<uintptr_t>(bytes) + 4 * count + page - 1) & ~(page - 1);
    const uintptr_t end = reinterpret_cast<uintptr_t>(bytes + count * sizeof(BvhPrimitive)) & ~(page - 1);
    if (end > keep_end) madvise(reinterpret_cast<void*>(keep_end), end - keep_end, MADV_DONTNEED);
#endif
    std::vector<uint32_t> ids(count);
    if (count > 0) std::memcpy(ids.data(), bytes, 4 * count);
    std::vector<BvhPrimitive>().swap(primitives);
    return ids;
}

// Empty boxes can never be hit: those primitives stay out of the tree.
void drop_empty_boxes(std::vector<BvhPrimitive>& primitives) {
    primitives.erase(std::remove_if(primitives.begin(), primitives.end(),
                                    [](const BvhPrimitive& p) { return p.bounds.is_empty(); }),
                     primitives.end());
}

double sah_cost_of(const Bvh& bvh, uint32_t index, const BvhBuildOptions& options) {
    const BvhNode& node = bvh.nodes[index];
    const double area = node.bounds.half_area();
    if (node.is_leaf()) return area * leaf_test_cost(node.count, options.leaf_test_width);
    return area * options.traversal_cost + sah_cost_of(bvh, node.first, options) +
           sah_cost_of(bvh, node.first + 1, options);
}

}  // namespace

Bvh build_bvh(std::vector<BvhPrimitive> primitives, const BvhBuildOptions& options) {
    drop_empty_boxes(primitives);
    Bvh bvh;
    if (primitives.empty()) return bvh;
    Builder builder(primitives.data(), options);
    builder.build_pieces(builder.make_range(0, static_cast<uint32_t>(primitives.size())));
    bvh.prim_order.resize(primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) bvh.prim_order[i] = primitives[i].id;
    // The primitives (28 bytes each) go before the pieces are laid out, which briefly needs room
    // for the nodes twice: the build's peak memory is then no higher than the finished scene's.
    std::vector<BvhPrimitive>().swap(primitives);
    bvh.nodes = builder.assemble();
#ifdef __GLIBC__
    // The pieces were built on worker threads, in glibc's per-thread arenas; freed, they would stay
    // resident (and count towards peak memory) until reused. Hand those pages back now.
    malloc_trim(0);
#endif
    return bvh;
}

double sah_cost(const Bvh& bvh, const BvhBuildOptions& options) {
    if (bvh.empty()) return 0;
    const double root_area = bvh.nodes[0].bounds.half_area();
    const double total = sah_cost_of(bvh, 0, options);
    return root_area > 0 ? total / root_area : total;
}

}  // namespace raycast

namespace raycast {

WideBvh build_wide_bvh(std::vector<BvhPrimitive> primitives, const BvhBuildOptions& options) {
    drop_empty_boxes(primitives);
    WideBvh bvh;
    if (primitives.empty()) return bvh;
    // A leaf's first primitive must fit a child reference's 31 bits, and its count 16 bits.
    if (primitives.size() > kWidePayloadMask || options.max_leaf_size > 0xffff) throw std::bad_alloc();
    Builder builder(primitives.data(), options);
    const Range all = builder.make_range(0, static_cast<uint32_t>(primitives.size()));
    builder.build_wide_pieces(all);
    bvh.prim_order = take_ids(primitives);
    bvh.nodes = builder.assemble_wide();
    bvh.bounds = pad_box(all.bounds);
#ifdef __GLIBC__
    malloc_trim(0);  // as in build_bvh
#endif
    return bvh;
}

WideBvh collapse_bvh(const Bvh& binary) {
    WideBvh wide;
    if (binary.empty()) return wide;
    RAYCAST_CHECK(binary.prim_order.size() <= kWidePayloadMask);
    wide.prim_order = binary.prim_order;
    wide.bounds = binary.nodes[0].bounds;
    const BinaryTree tree{binary.nodes.data()};
    if (!tree.openable(0)) {
        wide.nodes.push_back(root_of_one_leaf(binary.nodes[0]));
        return wide;
    }
    Collapser<BinaryTree, LargeVector<WideBvhNode>>(tree, wide.nodes).emit(0);
    return wide;
}

float median_leaf_size(const WideBvh& bvh) {
    std::vector<float> sizes;
    for (const WideBvhNode& node : bvh.nodes)
        for (uint32_t slot = 0; slot < node.child_count; ++slot) {
            if (!is_wide_leaf(node.child[slot])) continue;
            const Vec3f extent = child_bounds(node, slot).extent();
            sizes.push_back(std::max(extent.x, std::max(extent.y, extent.z)));
        }
    if (sizes.empty()) return 0;
    const auto middle = sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2);
    std::nth_element(sizes.begin(), middle, sizes.end());
    return *middle;
}

}  // namespace raycast
