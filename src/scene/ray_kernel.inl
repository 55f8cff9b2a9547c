// The single-ray kernel, written once over the 8-lane SIMD wrapper of the file that includes it
// (ray_<isa>.cpp, inside that instruction set's namespace, after the wrapper; no include guard).
// It defines that namespace's intersect, occluded and test_group (see packet_view.h).
//
// One ray walks a mesh's wide BVH: the 8 child boxes of a node are slab-tested at once, the
// children the ray enters are visited nearest first and the others kept on a stack with their
// entry distance, so that those starting beyond the best hit are dropped when popped. A leaf is a
// run of triangle groups (geometry/triangle_groups.h), each tested in one pass: the group's
// vertices are moved into the ray's watertight space once, then gathered into the triangles'
// lanes. Every lane computes what intersect_triangle (geometry/triangle.h) computes for its
// triangle, operation for operation (the build never fuses a*b+c), so the hits are those of the
// scalar test bit for bit, and ties go as is_closer() says.
//
// Only fields of the shared structs are read here, never their inline functions (see
// packet_view.h for why): the ray's preparation is repeated here, as bvh.h and triangle.h do it.

namespace {

#include "scene/kernel_common.inl"

// The ray as the box tests use it: origin and inverse direction in every lane, and where each
// axis's near and far bounds lie in a node (lower bounds are near when the ray goes up the axis).
// With kWidenInverse (t_min >= 0), near and far bounds have their own inverses (see
// kInverseShrink in kernel_common.inl).

struct BoxTraversal {
    NodeF ox, oy, oz, t_min;
    NodeF near_ix, near_iy, near_iz, far_ix, far_iy, far_iz;
    uint32_t near_offset[3];  // a far bound is at near_offset ^ kFarFromNear[axis]
};

// An axis's lower and upper bound arrays lie at offsets whose XOR is this (see WideBvhNode).
constexpr uint32_t kFarFromNear[3] = {
    static_cast<uint32_t>(offsetof(WideBvhNode, bounds[0][0]) ^ offsetof(WideBvhNode, bounds[0][1])),
    static_cast<uint32_t>(offsetof(WideBvhNode, bounds[1][0]) ^ offsetof(WideBvhNode, bounds[1][1])),
    static_cast<uint32_t>(offsetof(WideBvhNode, bounds[2][0]) ^ offsetof(WideBvhNode, bounds[2][1]))};
static_assert((offsetof(WideBvhNode, bounds[0][0]) ^ kFarFromNear[0]) == offsetof(WideBvhNode, bounds[0][1]) &&
                  (offsetof(WideBvhNode, bounds[1][0]) ^ kFarFromNear[1]) == offsetof(WideBvhNode, bounds[1][1]) &&
                  (offsetof(WideBvhNode, bounds[2][0]) ^ kFarFromNear[2]) == offsetof(WideBvhNode, bounds[2][1]),
              "the far bound must be found from the near one by XOR");

template <bool kWidenInverse>
inline BoxTraversal make_box_traversal(const Ray& ray, float t_min) {
    const float ones[3] = {1.0f, 1.0f, 1.0f};
    const float divisors[3] = {safe_divisor(ray.direction.x), safe_divisor(ray.direction.y),
                               safe_divisor(ray.direction.z)};
    float inverse[3];
    divide3(ones, divisors, inverse);
    const float shrink = kWidenInverse ? kInverseShrink : 1.0f, grow = kWidenInverse ? kInverseGrow : 1.0f;
    BoxTraversal b;
    b.ox = splat_node(ray.origin.x);
    b.oy = splat_node(ray.origin.y);
    b.oz = splat_node(ray.origin.z);
    b.near_ix = splat_node(inverse[0] * shrink);
    b.near_iy = splat_node(inverse[1] * shrink);
    b.near_iz = splat_node(inverse[2] * shrink);
    b.far_ix = splat_node(inverse[0] * grow);
    b.far_iy = splat_node(inverse[1] * grow);
    b.far_iz = splat_node(inverse[2] * grow);
    b.t_min = splat_node(t_min + 0.0f);  // -0 becomes +0, for hit_children's integer order
    const uint32_t lower[3] = {offsetof(WideBvhNode, bounds[0][0]), offsetof(WideBvhNode, bounds[1][0]),
                               offsetof(WideBvhNode, bounds[2][0])};
    // Where inverse[axis] < 0, found from the direction itself, so that the node test's loads
    // need not wait for the division: measured 1.01-1.04x for single rays (docs/performance.md).
    const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    for (uint32_t axis = 0; axis < 3; ++axis)
        b.near_offset[axis] = inverse_is_negative(d[axis]) ? lower[axis] ^ kFarFromNear[axis] : lower[axis];
    return b;
}

// The slab test of every child (see BoxTraversal for why it never misses). Returns the children
// hit (bit per slot) and their entry distances. Empty slots need no mask: their entry is +inf and
// their exit -inf; where those are widened (kWidenInverse false) they become NaN, which vmax and
// vmin keep when it is their second operand (SSE's rule, and the portable one's), so no
// comparison passes. The same happens to a real slab that begins at +inf or ends at -inf, which
// no ray reaches.
template <bool kWidenInverse>
inline unsigned hit_children(const WideBvhNode& node, const BoxTraversal& r, const NodeF& t_cull, NodeF& t_entry) {
    const char* base = reinterpret_cast<const char*>(&node);
    auto bound = [base](uint32_t offset) { return load_node(reinterpret_cast<const float*>(base + offset)); };
    const NodeF near_x = (bound(r.near_offset[0]) - r.ox) * r.near_ix;
    const NodeF near_y = (bound(r.near_offset[1]) - r.oy) * r.near_iy;
    const NodeF near_z = (bound(r.near_offset[2]) - r.oz) * r.near_iz;
    const NodeF far_x = (bound(r.near_offset[0] ^ kFarFromNear[0]) - r.ox) * r.far_ix;
    const NodeF far_y = (bound(r.near_offset[1] ^ kFarFromNear[1]) - r.oy) * r.far_iy;
    const NodeF far_z = (bound(r.near_offset[2] ^ kFarFromNear[2]) - r.oz) * r.far_iz;
    if (kWidenInverse) {
        // The floats compared as the signed integers their bits spell: a shorter chain (integer
        // max, min and compare have one cycle of latency on current x86 cores, the float ones
        // more). For floats that are not NaN, the integer order is the float order among values
        // >= +0, and every negative value (-0 included) lies below +0 in both. Here t_min is +0
        // or more, so t0 is the same value either way (but for -0 against +0, which order
        // nothing), and a negative t1 fails t0 <= t1 either way; +0 <= -0 holds for floats only,
        // where a box is met at t = 0 alone and holds nothing beyond t_min = 0 (boxes are a float
        // step larger than what they hold). A NaN direction gives a NaN of one sign in both a near
        // and a far distance of an axis: positive, it is the greatest entry; negative, the least
        // exit; either way no child is entered.
        const NodeF t0 = max_by_bits(max_by_bits(near_x, near_y), max_by_bits(near_z, r.t_min));
        const NodeF t1 = min_by_bits(min_by_bits(far_x, far_y), min_by_bits(far_z, t_cull));
        t_entry = t0;
        return not_greater_by_bits(t0, t1);
    }
    NodeF entry = vmax(vmax(near_x, near_y), near_z);
    NodeF exit = vmin(vmin(far_x, far_y), far_z);
    const NodeF widen = splat_node(kBoxWiden);
    entry = entry - vabs(entry) * widen;
    exit = exit + vabs(exit) * widen;
    const NodeF t0 = vmax(r.t_min, entry);
    const NodeF t1 = vmin(t_cull, exit);
    t_entry = t0;
    return bits(t0 <= t1);
}

// Visits the leaves whose boxes the ray enters, nearest child first, skipping subtrees that start
// beyond t_cull() (read again after every leaf, which may bring it nearer). visit_leaf(payload,
// t_entry), t_entry being where the ray enters the leaf's box (for the closest-hit query's
// leaf_floor, bvh.h), returns true to stop (an any-hit query that has its answer); then so does
// this. With kCount, every child box tested adds one to *nodes_visited. kWidenInverse needs
// t_min >= 0. Without kNearFirst, children are visited in slot order: for an any-hit query,
// whose cull distance never changes, sorting cost more (its branches mispredict) than finding a
// blocker sooner saved.
// skipped(node, hits) gives the slots of `hits` not to enter however their box tests went (an
// any-hit query passing over back faces, scene/back_faces.h; none for the others).
template <bool kCount, bool kWidenInverse, bool kNearFirst = true, typename CullFn, typename LeafFn,
          typename SkipFn>
[[gnu::always_inline]] inline bool traverse_wide(const WideBvhNode* nodes, const Ray& ray, float t_min, CullFn&& t_cull,
                                                LeafFn&& visit_leaf, uint64_t* nodes_visited, SkipFn&& skipped) {
    const BoxTraversal r = make_box_traversal<kWidenInverse>(ray, t_min);
    struct Pending {
        uint32_t ref;
        float t_entry;
    };
    Pending stack[kWideStackSize];
    int stack_size = 0;
    uint32_t ref = 0;  // the root node
    float ref_entry = -INFINITY;  // where the ray enters ref's box (the root's is not tested)
    float cull = t_cull();
    NodeF cull_v = splat_node(cull);
    for (;;) {
        if ((ref & kWideLeafFlag) == 0) {
            const WideBvhNode& node = nodes[ref];
            if (kCount) *nodes_visited += node.child_count;
            NodeF t_entry;
            unsigned hits = hit_children<kWidenInverse>(node, r, cull_v, t_entry);
            if (hits != 0) hits &= ~skipped(ref, hits);
            if (hits != 0) {
                float t[kWideBvhWidth];
                store(t, t_entry);
                const unsigned first = lowest_bit(hits);
                hits &= hits - 1;
                if (hits == 0) {  // one child: no ordering, no stack
                    ref = node.child[first];
                    ref_entry = t[first];
                    continue;
                }
                // At most kWideBvhWidth - 1 entries per level above the node (kWideStackSize).
                RAYCAST_DCHECK(stack_size + kWideBvhWidth - 1 <= kWideStackSize);
                if (!kNearFirst) {  // any order will do: the cull distance cannot change
                    for (; hits; hits &= hits - 1) stack[stack_size++] = Pending{node.child[lowest_bit(hits)], -INFINITY};
                    ref = node.child[first];
                    continue;
                }
                const unsigned second = lowest_bit(hits);
                hits &= hits - 1;
                if (hits == 0) {  // two children, the commonest case after one
                    const bool first_nearer = t[first] <= t[second];
                    stack[stack_size++] = first_nearer ? Pending{node.child[second], t[second]}
                                                       : Pending{node.child[first], t[first]};
                    ref = node.child[first_nearer ? first : second];
                    ref_entry = t[first_nearer ? first : second];
                    continue;
                }
                // More: all but the nearest wait on the stack, the farthest deepest.
                hits |= (1u << first) | (1u << second);
                Pending entered[kWideBvhWidth];
                int count = 0;
                for (; hits; hits &= hits - 1) {
                    const unsigned slot = lowest_bit(hits);
                    const Pending child{node.child[slot], t[slot]};
                    int i = count++;
                    for (; i > 0 && entered[i - 1].t_entry < child.t_entry; --i) entered[i] = entered[i - 1];
                    entered[i] = child;
                }
                for (int i = 0; i + 1 < count; ++i) stack[stack_size++] = entered[i];
                ref = entered[count - 1].ref;
                ref_entry = entered[count - 1].t_entry;
                continue;
            }
        } else {
            if (visit_leaf(ref & kWidePayloadMask, ref_entry)) return true;
            cull = t_cull();
            cull_v = splat_node(cull);
        }
        // Pop the next subtree that may still hold something nearer than the best hit.
        for (;;) {
            if (stack_size == 0) return false;
            const Pending next = stack[--stack_size];
            if (next.t_entry <= cull) {
                ref = next.ref;
                ref_entry = next.t_entry;
                break;
            }
        }
    }
}

// The ray as the triangle tests use it: make_watertight_ray's permutation and shear, every lane.
struct GroupRay {
    uint32_t kx, ky, kz;
    F8 okx, oky, okz;  // origin components along kx, ky, kz
    F8 sx, sy, sz;
    F8 t_min;
};

inline GroupRay make_group_ray(const Ray& ray, float t_min) {
    const WatertightAxes axes = watertight_axes(ray.direction.x, ray.direction.y, ray.direction.z);
    const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    GroupRay g;
    g.kx = static_cast<uint32_t>(axes.kx);
    g.ky = static_cast<uint32_t>(axes.ky);
    g.kz = static_cast<uint32_t>(axes.kz);
    g.okx = splat8(o[axes.kx]);
    g.oky = splat8(o[axes.ky]);
    g.okz = splat8(o[axes.kz]);
    const float dividends[3] = {d[axes.kx], d[axes.ky], 1.0f};
    const float divisors[3] = {d[axes.kz], d[axes.kz], d[axes.kz]};
    float shear[3];
    divide3(dividends, divisors, shear);
    g.sx = splat8(shear[0]);
    g.sy = splat8(shear[1]);
    g.sz = splat8(shear[2]);
    g.t_min = splat8(t_min);
    return g;
}

// Vertices [first, first + 8) of a group in the ray's sheared space: the values
// intersect_triangle computes for each corner (ax, ay, az and so on). Lanes past the last vertex
// are zeroed before any arithmetic, so that what lies beyond the plane (the next plane, the ids)
// never reaches the FPU as a NaN or a denormal.
struct Sheared {
    F8 x, y, z;
};

inline Sheared shear(const unsigned char* planes, uint32_t vertices, uint32_t first, const GroupRay& r) {
    const M8 real = first_lanes(vertices - first < 8 ? vertices - first : 8);
    const unsigned char* from = planes + 4 * first;
    const uint32_t stride = 4 * vertices;  // bytes from one coordinate's plane to the next
    const F8 a_kx = keep(real, load8(reinterpret_cast<const float*>(from + r.kx * stride))) - r.okx;
    const F8 a_ky = keep(real, load8(reinterpret_cast<const float*>(from + r.ky * stride))) - r.oky;
    const F8 a_kz = keep(real, load8(reinterpret_cast<const float*>(from + r.kz * stride))) - r.okz;
    return {a_kx - r.sx * a_kz, a_ky - r.sy * a_kz, r.sz * a_kz};
}

// What a group test leaves for the caller: per lane, the numerators of u and v and the
// determinant (the divisions are done only for a hit that is kept) and t. Only `hits` is set
// when it is 0.
struct GroupHits {
    unsigned hits;
    F8 t, u1, u2, det;
};

// The watertight test of intersect_triangle for the group's triangles, one per lane. With
// kPositiveOnly (t_min >= 0), t is divided out only where it can exceed t_min (see below).
template <bool kPositiveOnly = false>
inline GroupHits test_group_lanes(const unsigned char* group, const GroupRay& r) {
    const uint32_t triangles = group[0], vertices = group[1];
    const unsigned char* corners = group + group_corners_offset();
    const unsigned char* planes = group + group_vertices_offset(triangles);
    const I8 c0 = load_bytes(corners), c1 = load_bytes(corners + triangles), c2 = load_bytes(corners + 2 * triangles);
    const Sheared low = shear(planes, vertices, 0, r);
    F8 ax, ay, az, bx, by, bz, cx, cy, cz;
    if (vertices <= 8) {
        ax = lookup(low.x, c0), ay = lookup(low.y, c0), az = lookup(low.z, c0);
        bx = lookup(low.x, c1), by = lookup(low.y, c1), bz = lookup(low.z, c1);
        cx = lookup(low.x, c2), cy = lookup(low.y, c2), cz = lookup(low.z, c2);
    } else {
        const Sheared high = shear(planes, vertices, 8, r);
        ax = lookup(low.x, high.x, c0), ay = lookup(low.y, high.y, c0), az = lookup(low.z, high.z, c0);
        bx = lookup(low.x, high.x, c1), by = lookup(low.y, high.y, c1), bz = lookup(low.z, high.z, c1);
        cx = lookup(low.x, high.x, c2), cy = lookup(low.y, high.y, c2), cz = lookup(low.z, high.z, c2);
    }
    GroupHits h;
    // Edge functions: u0 belongs to the edge opposite the first corner, and so on.
    const F8 u0 = cx * by - cy * bx;
    h.u1 = ax * cy - ay * cx;
    h.u2 = bx * ay - by * ax;
    const F8 zero = splat8(0.0f);
    const M8 negative = (u0 < zero) | (h.u1 < zero) | (h.u2 < zero);
    const M8 positive = (u0 > zero) | (h.u1 > zero) | (h.u2 > zero);
    M8 valid = andnot(first_lanes(triangles), negative & positive);
    if (kPositiveOnly) {
        // t = num / det > t_min >= 0 needs num and det nonzero and of one sign: a lane without
        // that is no hit however the division rounds (NaN fails it too), and the lanes with it
        // take the test below as they are. Most rays passing the edge tests of a group meet the
        // triangle they leave from, behind them, so nearly every group stops here, without the
        // division, and without a branch on the edge tests (whose outcome is no better than a
        // coin toss: on the bench meshes' AO rays, 69% of the leaves tested at 1k triangles pass
        // them and 54% at 1M).
        h.det = u0 + h.u1 + h.u2;
        const F8 num = u0 * az + h.u1 * bz + h.u2 * cz;
        valid = valid & (((num > zero) & (h.det > zero)) | ((num < zero) & (h.det < zero)));
        h.hits = bits(valid);
        if (h.hits == 0) return h;
        h.t = num / h.det;
    } else {
        h.hits = bits(valid);
        if (h.hits == 0) return h;
        h.det = u0 + h.u1 + h.u2;
        h.t = (u0 * az + h.u1 * bz + h.u2 * cz) / h.det;
    }
    valid = valid & (h.det != zero) & (h.t > r.t_min);
    h.hits = bits(valid);
    return h;
}

// The ordering of is_closer (geometry/hit.h).
inline bool closer(float t, uint32_t object, uint32_t prim, const Hit& best) {
    if (t != best.t) return t < best.t;
    return object != best.object ? object < best.object : prim < best.prim;
}

// Merges the hits of one leaf's groups into `best`, each at t moved up to t_floor where it lies
// nearer (t_floor: the leaf_floor of where the ray enters the leaf's box, bvh.h).
inline void intersect_leaf(const GroupBlock* groups, uint32_t first_block, float t_floor, const GroupRay& r,
                           uint32_t object, Hit& best) {
    uint32_t block = first_block;
    for (;;) {
        // A compiler barrier, no instruction: without it GCC loads the ray's seven registers
        // before the loop, has too few left, and copies them to this call's stack frame on every
        // call; with it the loop reads them from the caller's copy as memory operands. Measured
        // 1.01-1.03x at 1k, 1.02x at 1M, level at 100k and 5M (--no-packets, in turn).
        asm volatile("" ::: "memory");
        const unsigned char* group = groups[block].bytes;
        const GroupHits h = test_group_lanes(group, r);
        unsigned hits = h.hits;
        F8 t_hit;  // t, moved up to t_floor where it lies nearer (bvh.h's at_leaf_floor)
        if (hits != 0) {
            t_hit = vmax(h.t, splat8(t_floor));
            hits &= bits(t_hit <= splat8(best.t));
        }
        if (hits != 0) {
            float t[8];
            store(t, t_hit);
            int winner = -1;
            for (; hits; hits &= hits - 1) {
                const unsigned lane = lowest_bit(hits);
                const uint32_t id = group_id(group, lane);
                if (!closer(t[lane], object, id, best)) continue;
                best.t = t[lane];
                best.object = object;
                best.prim = id;
                best.leaf = block;
                best.lane = lane;
                winner = static_cast<int>(lane);
            }
            if (winner >= 0) {  // its barycentrics, as intersect_triangle divides them
                float u1[8], u2[8], det[8];
                store(u1, h.u1);
                store(u2, h.u2);
                store(det, h.det);
                best.u = u1[winner] / det[winner];
                best.v = u2[winner] / det[winner];
            }
        }
        if (group[2] & kGroupEndsLeaf) return;
        block += group_blocks(group[0], group[1]);
    }
}

// Whether one leaf's groups have a hit nearer than t_max (kPositiveOnly: t_min >= 0).
template <bool kPositiveOnly>
inline bool occluded_leaf(const GroupBlock* groups, uint32_t first_block, const GroupRay& r, const F8& t_max) {
    uint32_t block = first_block;
    for (;;) {
        const unsigned char* group = groups[block].bytes;
        const GroupHits h = test_group_lanes<kPositiveOnly>(group, r);
        if (h.hits != 0 && (h.hits & bits(h.t < t_max)) != 0) return true;
        if (group[2] & kGroupEndsLeaf) return false;
        block += group_blocks(group[0], group[1]);
    }
}

// For walks that skip no child (traverse_wide's `skipped`).
inline unsigned no_slots(uint32_t, unsigned) { return 0; }

}  // namespace

void intersect(const MeshView& mesh, const Ray& ray, float t_min, uint32_t object, Hit& best, uint64_t* nodes_visited) {
    GroupRay r;  // made at the first leaf: most rays that miss never reach one
    bool have_group_ray = false;
    auto t_cull = [&] { return cull_distance_scalar(best.t); };
    auto visit_leaf = [&](uint32_t first_block, float leaf_entry) {
        if (!have_group_ray) {
            r = make_group_ray(ray, t_min);
            have_group_ray = true;
        }
        intersect_leaf(mesh.groups, first_block, leaf_floor_scalar(leaf_entry), r, object, best);
        return false;
    };
    // Counting or not, the same slab test, so that every leaf's entry (and so leaf_floor) is the
    // same: the cost mode's hits are the other modes'.
    if (nodes_visited && t_min >= 0)
        traverse_wide<true, true>(mesh.nodes, ray, t_min, t_cull, visit_leaf, nodes_visited, no_slots);
    else if (nodes_visited)
        traverse_wide<true, false>(mesh.nodes, ray, t_min, t_cull, visit_leaf, nodes_visited, no_slots);
    else if (t_min >= 0)
        traverse_wide<false, true>(mesh.nodes, ray, t_min, t_cull, visit_leaf, nullptr, no_slots);
    else
        traverse_wide<false, false>(mesh.nodes, ray, t_min, t_cull, visit_leaf, nullptr, no_slots);
}

bool occluded(const MeshView& mesh, const Ray& ray, float t_min, float t_max) {
    GroupRay r;  // made at the first leaf, as in intersect
    bool have_group_ray = false;
    const float t_cull = cull_distance_scalar(t_max);  // as traverse_bvh culls an any-hit query
    auto cull = [t_cull] { return t_cull; };
    auto visit_leaf = [&](uint32_t first_block, float) {
        if (!have_group_ray) {
            r = make_group_ray(ray, t_min);
            have_group_ray = true;
        }
        if (t_min >= 0) return occluded_leaf<true>(mesh.groups, first_block, r, splat8(t_max));
        return occluded_leaf<false>(mesh.groups, first_block, r, splat8(t_max));
    };
    auto walk = [&](auto&& skipped) {
        if (t_min >= 0) return traverse_wide<false, true, false>(mesh.nodes, ray, t_min, cull, visit_leaf, nullptr, skipped);
        return traverse_wide<false, false, false>(mesh.nodes, ray, t_min, cull, visit_leaf, nullptr, skipped);
    };
    const Vec3f d = ray.direction;
    const float length = mesh.cones ? __builtin_sqrtf(d.x * d.x + d.y * d.y + d.z * d.z) : 0.0f;
    if (length >= 1e-15f && length <= 1e15f) {
        // The children whose triangles all face away from the ray (scene/back_faces.h's
        // faces_away, and the packet kernel's, operation for operation).
        auto faces_away = [&](uint32_t node, unsigned hits) {
            const NodeCones& cones = mesh.cones[node];
            unsigned away = 0;
            for (; hits; hits &= hits - 1) {
                const unsigned slot = lowest_bit(hits);
                const float dot = static_cast<float>(cones.axis[0][slot]) * d.x +
                                  static_cast<float>(cones.axis[1][slot]) * d.y +
                                  static_cast<float>(cones.axis[2][slot]) * d.z;
                if (static_cast<float>(cones.reach[slot]) * length < dot) away |= 1u << slot;
            }
            return away;
        };
        return walk(faces_away);
    }
    return walk(no_slots);
}

void test_group(const GroupBlock* group, const Ray& ray, float t_min, GroupLanes& lanes) {
    const GroupHits h = test_group_lanes(group->bytes, make_group_ray(ray, t_min));
    lanes.hits = h.hits;
    float t[8] = {}, u1[8] = {}, u2[8] = {}, det[8] = {};
    if (h.hits != 0) {
        store(t, h.t);
        store(u1, h.u1);
        store(u2, h.u2);
        store(det, h.det);
    }
    for (unsigned lane = 0; lane < 8; ++lane) {
        const bool hit = (h.hits >> lane) & 1u;
        lanes.t[lane] = hit ? t[lane] : 0.0f;
        lanes.u[lane] = hit ? u1[lane] / det[lane] : 0.0f;
        lanes.v[lane] = hit ? u2[lane] / det[lane] : 0.0f;
    }
}
