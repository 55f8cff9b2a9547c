// The packet tracer, written once over the SIMD wrapper of the file that includes it
// (packet_<isa>.cpp, inside that instruction set's anonymous namespace, after the wrapper; no
// include guard).
//
// A packet is kLanes rays, from neighbouring pixels or from a packet's hits towards one light. It
// walks each BVH together: a node is entered when any ray's slab test passes, so one box test in
// SIMD serves every ray; for pinhole camera rays, where the kernel has 8-lane registers, one
// frustum test serves all eight children of a node (PacketFrustum). Meshes have wide BVHs and
// triangle groups (geometry/triangle_groups.h): a group's vertices are moved into every ray's
// watertight space once, and each triangle is then tested in every lane with exactly the
// floating-point operations of intersect_triangle (geometry/triangle.h), in the same order, so
// each lane finds bit for bit the hit the single-ray path finds (the results never depend on the
// path; tests check it).
//
// Only fields of the shared structs are read here, never their inline functions (see
// packet_view.h for why).

#include "scene/kernel_common.inl"

constexpr uint32_t kNoTransformIndex = 0xffffffffu;

struct PacketRays {
    VF ox, oy, oz;
    VF dx, dy, dz;
    VF ix, iy, iz;  // safe inverses of the direction, for slab tests
    VM live;        // lanes that hold a ray still being traced
    // For the slab test of lanes that all go the same way along each axis, with t_min >= 0:
    // the inverses for near and far bounds (kernel_common.inl's kInverseShrink), and the lanes
    // whose inverse is negative, per axis.
    VF near_ix, near_iy, near_iz, far_ix, far_iy, far_iz;
    unsigned negative[3];
    // The same inverses by bound, lane by lane: for the lower bound, near_ix where the ray goes
    // up the axis and far_ix where it goes down; for the upper, the other (SlabTest::AnyOctant).
    VF lower_ix, lower_iy, lower_iz, upper_ix, upper_iy, upper_iz;
};

// The watertight test's per-ray constants (see make_watertight_ray) for the lanes `lanes`, which
// share one axis permutation.
struct WatertightPacket {
    int kx = 0, ky = 1, kz = 2;
    VM lanes;
    VF sx, sy, sz;
    VF okx, oky, okz;  // origin components along kx, ky, kz
};

struct PacketState {
    const PacketSceneView& view;
    const Ray* rays;
    Hit* hits;
    int count;
    float t_min;
    VF t_min_v;
    VF best_t;  // hits[lane].t in every lane (+inf in dead lanes)
};

inline VF pick(const VF& x, const VF& y, const VF& z, int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }

inline float lane_value(VF v, unsigned lane) {
    float values[kLanes];
    store(values, v);
    return values[lane];
}

// bvh.h's safe_inverse in every lane (a SIMD division rounds as the scalar one does).
inline VF safe_inverse_v(VF d) {
    const VF signed_tiny = select(mask_from_bits(sign_bits(d)), splat(-kTiny), splat(kTiny));
    return splat(1.0f) / select(vabs(d) < splat(kTiny), signed_tiny, d);
}

// Fills the inverse directions from the ray components.
inline void prepare_inverses(PacketRays& r) {
    r.ix = safe_inverse_v(r.dx);
    r.iy = safe_inverse_v(r.dy);
    r.iz = safe_inverse_v(r.dz);
    const VF zero = splat(0.0f);
    r.negative[0] = bits(r.ix < zero);
    r.negative[1] = bits(r.iy < zero);
    r.negative[2] = bits(r.iz < zero);
    const VF shrink = splat(kInverseShrink), grow = splat(kInverseGrow);
    r.near_ix = r.ix * shrink;
    r.near_iy = r.iy * shrink;
    r.near_iz = r.iz * shrink;
    r.far_ix = r.ix * grow;
    r.far_iy = r.iy * grow;
    r.far_iz = r.iz * grow;
    const VM down_x = r.ix < zero, down_y = r.iy < zero, down_z = r.iz < zero;
    r.lower_ix = select(down_x, r.far_ix, r.near_ix);
    r.lower_iy = select(down_y, r.far_iy, r.near_iy);
    r.lower_iz = select(down_z, r.far_iz, r.near_iz);
    r.upper_ix = select(down_x, r.near_ix, r.far_ix);
    r.upper_iy = select(down_y, r.near_iy, r.far_iy);
    r.upper_iz = select(down_z, r.near_iz, r.far_iz);
}

// Rays [0, count) as a packet (structure of arrays); dead lanes repeat lane 0 so that they hold no
// garbage.
inline PacketRays load_packet(const Ray* rays, int count) {
    static_assert(sizeof(Ray) == 6 * sizeof(float), "a ray is six floats");
    VF fields[6];
    load_six_fields(&rays[0].origin.x, count, fields);
    PacketRays r;
    r.ox = fields[0];
    r.oy = fields[1];
    r.oz = fields[2];
    r.dx = fields[3];
    r.dy = fields[4];
    r.dz = fields[5];
    r.live = mask_from_bits((1u << count) - 1);
    prepare_inverses(r);
    return r;
}

// watertight_axes's choice for every lane at once, as masks: the live lanes fall into at most
// six sets (the dominant axis kz, and whether the ray goes down it), each with its kx, ky, kz.
// The same comparisons as watertight_axes, so each lane lands where that function puts it.
struct AxisSet {
    VM lanes;
    int kx, ky, kz;
};

inline int axis_sets(const PacketRays& r, AxisSet* sets) {
    const VF ax = vabs(r.dx), ay = vabs(r.dy), az = vabs(r.dz), zero = splat(0.0f);
    const VM x_ge_y = ay <= ax;
    const VM kz_x = x_ge_y & (az <= ax), kz_y = andnot(az <= ay, x_ge_y);
    const VM dominant[3] = {kz_x, kz_y, andnot(andnot(r.live, kz_x), kz_y)};
    const VM down[3] = {r.dx < zero, r.dy < zero, r.dz < zero};
    int count = 0;
    for (int kz = 0; kz < 3; ++kz) {
        const VM lanes = dominant[kz] & r.live;
        if (!any(lanes)) continue;
        const int kx = kz == 2 ? 0 : kz + 1;
        const int ky = kx == 2 ? 0 : kx + 1;
        const VM up_lanes = andnot(lanes, down[kz]), down_lanes = lanes & down[kz];
        if (any(up_lanes)) sets[count++] = {up_lanes, kx, ky, kz};
        if (any(down_lanes)) sets[count++] = {down_lanes, ky, kx, kz};  // swapped: keeps the winding
    }
    return count;
}

// The watertight test's constants for the lanes of one axis set, computed (in SIMD, as
// make_watertight_ray computes them) in every lane.
inline WatertightPacket make_watertight_packet(const PacketRays& r, const AxisSet& set) {
    WatertightPacket w;
    w.kx = set.kx;
    w.ky = set.ky;
    w.kz = set.kz;
    w.lanes = set.lanes;
    const VF dkz = pick(r.dx, r.dy, r.dz, w.kz);
    w.sx = pick(r.dx, r.dy, r.dz, w.kx) / dkz;
    w.sy = pick(r.dx, r.dy, r.dz, w.ky) / dkz;
    w.sz = splat(1.0f) / dkz;
    w.okx = pick(r.ox, r.oy, r.oz, w.kx);
    w.oky = pick(r.ox, r.oy, r.oz, w.ky);
    w.okz = pick(r.ox, r.oy, r.oz, w.kz);
    return w;
}

// The watertight test's constants lane by lane, for rays whose permutations differ (a hit's
// ambient-occlusion rays leave one point in every direction): each lane's kx, ky and kz as the
// masks of the lanes where that axis is y or z, and each lane's values from its own set's
// make_watertight_packet. A group's vertices are then sheared once for all the lanes
// (shear_vertices_lanes) rather than once per set, and its triangles tested once: a lane selects
// its own coordinates, which is exact, so every value is the one its set's shear gives.
struct WatertightLanes {
    VM kx_y, kx_z, ky_y, ky_z, kz_y, kz_z;
    VF sx, sy, sz;
    VF okx, oky, okz;
};

// Each lane's x, y or z: z where is_z, y where is_y, else x.
inline VF pick_lanes(VF x, VF y, VF z, VM is_y, VM is_z) { return select(is_z, z, select(is_y, y, x)); }

inline WatertightLanes make_watertight_lanes(const PacketRays& r, const AxisSet* sets, int count) {
    const VM none = mask_from_bits(0);
    const VF zero = splat(0.0f);
    WatertightLanes w{none, none, none, none, none, none, zero, zero, zero, zero, zero, zero};
    for (int i = 0; i < count; ++i) {
        const WatertightPacket set = make_watertight_packet(r, sets[i]);
        const VM m = set.lanes;
        if (set.kx == 1) w.kx_y = w.kx_y | m;
        if (set.kx == 2) w.kx_z = w.kx_z | m;
        if (set.ky == 1) w.ky_y = w.ky_y | m;
        if (set.ky == 2) w.ky_z = w.ky_z | m;
        if (set.kz == 1) w.kz_y = w.kz_y | m;
        if (set.kz == 2) w.kz_z = w.kz_z | m;
        w.sx = select(m, set.sx, w.sx);
        w.sy = select(m, set.sy, w.sy);
        w.sz = select(m, set.sz, w.sz);
        w.okx = select(m, set.okx, w.okx);
        w.oky = select(m, set.oky, w.oky);
        w.okz = select(m, set.okz, w.okz);
    }
    return w;
}

inline VF cull_distance_v(VF t_best) { return t_best + vabs(t_best) * splat(1.0f / 1024); }

// The slab test in every lane, widened like intersect_box so that it never misses.
inline VM box_hits(float lx, float ly, float lz, float ux, float uy, float uz, const PacketRays& r, VF t_min,
                   VF t_cull, VF& t_entry) {
    const VF n0 = (splat(lx) - r.ox) * r.ix, f0 = (splat(ux) - r.ox) * r.ix;
    const VF n1 = (splat(ly) - r.oy) * r.iy, f1 = (splat(uy) - r.oy) * r.iy;
    const VF n2 = (splat(lz) - r.oz) * r.iz, f2 = (splat(uz) - r.oz) * r.iz;
    const VF near = vmax(vmax(vmin(n0, f0), vmin(n1, f1)), vmin(n2, f2));
    const VF far = vmin(vmin(vmax(n0, f0), vmax(n1, f1)), vmax(n2, f2));
    const VF widen = splat(kBoxWiden);
    const VF t0 = vmax(near - vabs(near) * widen, t_min);
    const VF t1 = vmin(far + vabs(far) * widen, t_cull);
    t_entry = t0;
    return (t0 <= t1) & r.live;
}

inline VM node_hits(const BvhNode& node, const PacketRays& r, VF t_min, VF t_cull, VF& t_entry) {
    const Bounds3f& b = node.bounds;
    return box_hits(b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z, r, t_min, t_cull, t_entry);
}

// Which bound of each axis is near for every live lane (0: lower, 1: upper), when the lanes agree.
struct SameOctant {
    int near[3];
};

// Whether the live lanes all go the same way along each axis (so do coherent rays, nearly always).
inline bool same_octant(const PacketRays& r, SameOctant& octant) {
    const unsigned live = bits(r.live);
    for (int axis = 0; axis < 3; ++axis) {
        const unsigned negative = r.negative[axis] & live;
        if (negative != 0 && negative != live) return false;
        octant.near[axis] = negative != 0 ? 1 : 0;
    }
    return true;
}

// How a child's box is slab-tested: box_hits (widened, any t_min), or with t_min >= 0 the single-
// ray kernel's test, whose near and far bounds have their own inverses (kInverseShrink), with
// the near bound of each axis picked once for every lane (SameOctant) or found lane by lane
// (AnyOctant).
enum class SlabTest { Widened, SameOctant, AnyOctant };

// The AnyOctant test: each bound's distance with the inverse its role needs in that lane (the
// lower bound is near where the ray goes up the axis), so that the near one is what the
// single-ray kernel computes, and so is the far one; the nearer of the two is taken as the entry
// and the farther as the exit, which is that test's slab or a wider one, and needs no choosing
// of bounds per lane. Only for a node's real children (slot < child_count): an empty slot's
// inverted bounds would pass.
inline VM child_hits_any_octant(const WideBvhNode& node, uint32_t slot, const PacketRays& r, VF t_min, VF t_cull,
                                VF& t_entry) {
    const VF ax = (splat(node.bounds[0][0][slot]) - r.ox) * r.lower_ix;
    const VF bx = (splat(node.bounds[0][1][slot]) - r.ox) * r.upper_ix;
    const VF ay = (splat(node.bounds[1][0][slot]) - r.oy) * r.lower_iy;
    const VF by = (splat(node.bounds[1][1][slot]) - r.oy) * r.upper_iy;
    const VF az = (splat(node.bounds[2][0][slot]) - r.oz) * r.lower_iz;
    const VF bz = (splat(node.bounds[2][1][slot]) - r.oz) * r.upper_iz;
    const VF t0 = vmax(t_min, vmax(vmax(vmin(ax, bx), vmin(ay, by)), vmin(az, bz)));
    const VF t1 = vmin(t_cull, vmin(vmin(vmax(ax, bx), vmax(ay, by)), vmax(az, bz)));
    t_entry = t0;
    return (t0 <= t1) & r.live;
}

// The slab test of a child, as `kTest` says.
template <SlabTest kTest>
inline VM child_hits(const WideBvhNode& node, uint32_t slot, const PacketRays& r, const SameOctant& octant, VF t_min,
                     VF t_cull, VF& t_entry) {
    if (kTest == SlabTest::Widened)
        return box_hits(node.bounds[0][0][slot], node.bounds[1][0][slot], node.bounds[2][0][slot], node.bounds[0][1][slot],
                        node.bounds[1][1][slot], node.bounds[2][1][slot], r, t_min, t_cull, t_entry);
    if (kTest == SlabTest::AnyOctant) return child_hits_any_octant(node, slot, r, t_min, t_cull, t_entry);
    const int nx = octant.near[0], ny = octant.near[1], nz = octant.near[2];
    const VF near_x = (splat(node.bounds[0][nx][slot]) - r.ox) * r.near_ix;
    const VF near_y = (splat(node.bounds[1][ny][slot]) - r.oy) * r.near_iy;
    const VF near_z = (splat(node.bounds[2][nz][slot]) - r.oz) * r.near_iz;
    const VF far_x = (splat(node.bounds[0][1 - nx][slot]) - r.ox) * r.far_ix;
    const VF far_y = (splat(node.bounds[1][1 - ny][slot]) - r.oy) * r.far_iy;
    const VF far_z = (splat(node.bounds[2][1 - nz][slot]) - r.oz) * r.far_iz;
    const VF t0 = vmax(t_min, vmax(vmax(near_x, near_y), near_z));
    const VF t1 = vmin(t_cull, vmin(vmin(far_x, far_y), far_z));
    t_entry = t0;
    return (t0 <= t1) & r.live;
}

// Each lane's leaf_floor (bvh.h) in the lanes whose rays entered the leaf's box at t_entry; +inf
// in the others (no hit of theirs in that leaf is kept: a single ray would not have reached it).
inline VF leaf_floor_v(VM entered, VF t_entry) {
    return select(entered, t_entry - vabs(t_entry) * splat(1.0f / 2048), splat(__builtin_inff()));
}

// Each lane's leaf_floor_v for the instance BVH's leaf `leaf`, from its own box test of the leaf
// (the single-ray path's intersect_box); -inf in every lane where no box was tested (leaf null).
inline VF node_floor(const BvhNode* leaf, const PacketRays& r, VF t_min) {
    if (!leaf) return splat(-__builtin_inff());
    VF t_entry;
    const VM meets = node_hits(*leaf, r, t_min, splat(__builtin_inff()), t_entry);
    return leaf_floor_v(meets, t_entry);
}

// Walks the (binary) instance BVH with the packet; visit_leaf(first, count, lanes, leaf) is called
// for every leaf that some live ray's box test reaches, with the leaf's node (for node_floor:
// null where its box was not tested), and returns true to stop. t_cull() is re-read
// after every leaf, and so is r.live (a leaf may retire lanes).
template <typename CullFn, typename LeafFn>
inline void traverse_packet(const BvhNode* nodes, const PacketRays& r, const VF& t_min, CullFn&& t_cull,
                            LeafFn&& visit_leaf) {
    if (nodes[0].count != 0) {
        // One leaf: its instances are tested without its box, exactly as intersect() and
        // occluded() do, so the paths agree even where the box test's stand-in for 1/0 (bvh.h)
        // would miss a box too thin to see (fuzz/regressions/fuzz_render_pipeline-lone-tiny-sphere).
        visit_leaf(nodes[0].first, nodes[0].count, r.live, static_cast<const BvhNode*>(nullptr));
        return;
    }
    VF t_entry;
    VM mask = node_hits(nodes[0], r, t_min, t_cull(), t_entry);
    if (!any(mask)) return;
    uint32_t stack[kMaxBvhDepth];
    int stack_size = 0;
    uint32_t current = 0;
    for (;;) {
        const BvhNode& node = nodes[current];
        if (node.count != 0) {
            if (visit_leaf(node.first, node.count, mask, &node)) return;
        } else {
            const VF cull = t_cull();
            VF t_left, t_right;
            const VM hit_left = node_hits(nodes[node.first], r, t_min, cull, t_left);
            const VM hit_right = node_hits(nodes[node.first + 1], r, t_min, cull, t_right);
            const bool any_left = any(hit_left), any_right = any(hit_right);
            if (any_left && any_right) {
                // Nearer child first, as seen by the first ray that enters both.
                const VM both = hit_left & hit_right;
                const unsigned lane = lowest_bit(any(both) ? bits(both) : bits(hit_left));
                const bool left_first = lane_value(t_left, lane) <= lane_value(t_right, lane);
                // At most one entry per level above the node: the builder keeps trees within
                // kMaxBvhDepth levels (build_bvh.cpp), the size of this stack.
                RAYCAST_DCHECK(stack_size < static_cast<int>(sizeof stack / sizeof stack[0]));
                stack[stack_size++] = left_first ? node.first + 1 : node.first;
                current = left_first ? node.first : node.first + 1;
                mask = left_first ? hit_left : hit_right;
                continue;
            }
            if (any_left || any_right) {
                current = any_left ? node.first : node.first + 1;
                mask = any_left ? hit_left : hit_right;
                continue;
            }
        }
        // Pop a subtree that some ray may still need, testing its box again against the
        // (possibly nearer) best hits.
        for (;;) {
            if (stack_size == 0) return;
            current = stack[--stack_size];
            mask = node_hits(nodes[current], r, t_min, t_cull(), t_entry);
            if (any(mask)) break;
        }
    }
}

// Asks for a child's memory as soon as a packet's test enters it, before it is visited (the
// nearest child at once, the others when popped): an inner node's cache lines, or the first
// three of a leaf's groups (a leaf of 8 triangles is one group of about 180 bytes). At 1M
// triangles and more, most of what a packet reaches is not in the caches yet, and waiting for it
// one line at a time was the largest single cost of the leaf test (docs/performance.md). Forced
// inline: GCC finds a function that only prefetches free of side effects and drops its calls.
[[gnu::always_inline]] inline void prefetch_child(const MeshView& mesh, uint32_t ref) {
    if (ref & kWideLeafFlag) {
        const char* group = reinterpret_cast<const char*>(mesh.groups + (ref & kWidePayloadMask));
        __builtin_prefetch(group);
        __builtin_prefetch(group + 64);
        __builtin_prefetch(group + 128);
        return;
    }
    const char* node = reinterpret_cast<const char*>(mesh.nodes + ref);
    for (size_t line = 0; line < sizeof(WideBvhNode); line += 64) __builtin_prefetch(node + line);
}

#ifdef RAYCAST_PACKET_FRUSTUM
// A packet whose live rays go the same way along every axis (with t_min >= 0), as one frustum:
// each node's eight child boxes are tested at once, in one 8-lane register (wide8, the TU's
// 8-lane wrapper), against bounds on what every ray's own slab test (SlabTest::SameOctant)
// computes.
// The rays share one origin, and float multiplication is monotonic, so (bound - o) * inverse over
// the lanes' inverses is least and greatest at an end of their range, rounding included: the
// frustum's entry is at most any ray's, its exit at least any ray's, and a box that any ray
// enters passes (with a few that none enters; the triangles, tested in every lane, decide). For a
// block of pinhole camera rays (directions a pixel apart) the range is narrow and a node costs
// one test instead of eight. Only packets of one origin use it: where the origins spread too, the
// bounds (over the origins' range as well) reach far more than any ray does (a thin lens's rays
// at 1M triangles rendered 7x slower, shadow packets on bench/ray_tracing.sh's glass scene 3x),
// and the lanes' own tests win.
struct PacketFrustum {
    int near[3];                     // which bound is near, per axis (SameOctant)
    float origin[3];                 // every live lane's
    float near_lo[3], near_hi[3];    // the near bounds' inverses (near_ix and so on)
    float far_lo[3], far_hi[3];      // the far bounds'
    // How far apart the rays' directions lie: the widest range of a component over the live
    // lanes, divided by the length of one direction (rays a distance d from the origin lie
    // about d times this apart).
    float spread;
    float direction_lo[3], direction_hi[3];  // each component's range over the live lanes
    float length;                            // of one lane's direction
};

// The greatest of the live lanes of v, and the least.
inline float max_of_lanes(VF v, VM live) { return hmax(select(live, v, splat(-__builtin_inff()))); }
inline float min_of_lanes(VF v, VM live) { return hmin(select(live, v, splat(__builtin_inff()))); }

// Whether the live lanes share one origin (a pinhole camera's rays): each equals the first live
// lane's (a NaN equals nothing).
inline bool one_origin(const PacketRays& r) {
    const unsigned first = lowest_bit(bits(r.live));
    const VM differ = (r.ox != splat(lane_value(r.ox, first))) | (r.oy != splat(lane_value(r.oy, first))) |
                      (r.oz != splat(lane_value(r.oz, first)));
    return !any(differ & r.live);
}

// For a packet of one origin (one_origin). The near and far inverses are the inverse times
// kInverseShrink and kInverseGrow (prepare_inverses), and a product with a positive constant
// rounds monotonically, so their ranges are the inverse's range times those constants, exactly.
inline PacketFrustum make_frustum(const PacketRays& r, const SameOctant& octant) {
    const VM live = r.live;
    PacketFrustum f;
    const VF* origin[3] = {&r.ox, &r.oy, &r.oz};
    const VF* inverse[3] = {&r.ix, &r.iy, &r.iz};
    const VF* direction[3] = {&r.dx, &r.dy, &r.dz};
    const unsigned some_lane = lowest_bit(bits(live));
    float widest = 0, length_squared = 0;
    for (int axis = 0; axis < 3; ++axis) {
        f.direction_lo[axis] = min_of_lanes(*direction[axis], live);
        f.direction_hi[axis] = max_of_lanes(*direction[axis], live);
        const float range = f.direction_hi[axis] - f.direction_lo[axis];
        if (range > widest) widest = range;
        const float component = lane_value(*direction[axis], some_lane);
        length_squared += component * component;
    }
    f.length = __builtin_sqrtf(length_squared);
    f.spread = widest / f.length;
    for (int axis = 0; axis < 3; ++axis) {
        f.near[axis] = octant.near[axis];
        f.origin[axis] = lane_value(*origin[axis], some_lane);
        const float lo = min_of_lanes(*inverse[axis], live), hi = max_of_lanes(*inverse[axis], live);
        f.near_lo[axis] = lo * kInverseShrink;
        f.near_hi[axis] = hi * kInverseShrink;
        f.far_lo[axis] = lo * kInverseGrow;
        f.far_hi[axis] = hi * kInverseGrow;
    }
    return f;
}

// The children some ray may enter before `cull` (bit per slot), and the frustum's entry to each.
inline unsigned frustum_children(const WideBvhNode& node, const PacketFrustum& f, float t_min, float cull,
                                 wide8::VF& t_entry) {
    using wide8::splat;
    using wide8::vmax;
    using wide8::vmin;
    wide8::VF entry = splat(t_min), exit = splat(cull);
    for (int axis = 0; axis < 3; ++axis) {
        const wide8::VF o = splat(f.origin[axis]);
        const wide8::VF to_near = wide8::load(node.bounds[axis][f.near[axis]]) - o;
        const wide8::VF to_far = wide8::load(node.bounds[axis][1 - f.near[axis]]) - o;
        entry = vmax(entry, vmin(to_near * splat(f.near_lo[axis]), to_near * splat(f.near_hi[axis])));
        exit = vmin(exit, vmax(to_far * splat(f.far_lo[axis]), to_far * splat(f.far_hi[axis])));
    }
    t_entry = entry;
    return wide8::bits(entry <= exit);
}

// Whether a packet's rays lie so far apart where they reach the mesh that the frustum walk would
// pass many leaves that few of them enter (kFrustumMaxFootprint): the distance from the origin
// to the mesh's box times the rays' spread. That is so where the triangles are small against the
// pixels: a 64x64 image of a 1M-triangle mesh rendered in 6.0 ms through the frustum and 1.4 ms
// lane by lane; at 1024x1024, 5M triangles go as fast either way and fewer go faster through
// the frustum (docs/performance.md). The nearest point of the box makes the footprint no wider
// than where the rays hit; a camera inside the box (distance 0) keeps the frustum.
inline bool frustum_too_wide(const PacketFrustum& f, const MeshView& mesh) {
    float distance_squared = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const float o = f.origin[axis];
        const float outside = o < mesh.lower[axis] ? mesh.lower[axis] - o : (o > mesh.upper[axis] ? o - mesh.upper[axis] : 0);
        distance_squared += outside * outside;
    }
    return __builtin_sqrtf(distance_squared) * f.spread > kFrustumMaxFootprint * mesh.leaf_size;
}

// Walks a mesh's wide BVH with the packet as a frustum: the children it enters are visited
// nearest first by its entry, the others wait on the stack with their entry and are dropped when
// popped if they begin beyond max_cull() (the farthest of the live lanes' cull distances, read
// again after every leaf). visit_leaf(payload, parent, slot), the leaf being child `slot` of node
// `parent`, returns true to stop.
template <typename CullFn, typename LeafFn>
inline void traverse_frustum(const MeshView& mesh, const PacketFrustum& f, float t_min, CullFn&& max_cull,
                             LeafFn&& visit_leaf) {
    const WideBvhNode* nodes = mesh.nodes;
    struct Pending {
        uint32_t ref;
        float t_entry;
        uint32_t parent, slot;  // where the child's box is (a leaf's is tested again for each hit)
    };
    Pending stack[kWideStackSize];
    int stack_size = 0;
    Pending current{0, 0.0f, 0, 0};  // the root node
    float cull = max_cull();
    for (;;) {
        if ((current.ref & kWideLeafFlag) == 0) {
            const WideBvhNode& node = nodes[current.ref];
            wide8::VF t_entry;
            unsigned hits = frustum_children(node, f, t_min, cull, t_entry);
            if (hits != 0) {
                float t[kWideBvhWidth];
                wide8::store(t, t_entry);
                Pending entered[kWideBvhWidth];
                int count = 0;
                for (; hits; hits &= hits - 1) {
                    const unsigned slot = lowest_bit(hits);
                    const Pending child{node.child[slot], t[slot], current.ref, slot};
                    prefetch_child(mesh, child.ref);
                    int i = count++;
                    for (; i > 0 && entered[i - 1].t_entry < child.t_entry; --i) entered[i] = entered[i - 1];
                    entered[i] = child;
                }
                RAYCAST_DCHECK(stack_size + count - 1 <= kWideStackSize);
                for (int i = 0; i + 1 < count; ++i) stack[stack_size++] = entered[i];
                current = entered[count - 1];
                continue;
            }
        } else {
            if (visit_leaf(current.ref & kWidePayloadMask, nodes[current.parent], current.slot)) return;
            cull = max_cull();
        }
        for (;;) {
            if (stack_size == 0) return;
            const Pending next = stack[--stack_size];
            if (next.t_entry <= cull) {
                current = next;
                break;
            }
        }
    }
}
#endif

// A leaf of a mesh's wide BVH as a walk reached it: what leaf_floor_lanes needs. The walk that
// tests boxes lane by lane gives each lane's entry and the lanes that entered; a frustum walk
// (its rays all go one way, t_min >= 0) gives where the box is, to be tested lane by lane.
struct LeafBox {
    const VF* t_entry = nullptr;  // the lane-by-lane walk's entries (null: test the box)
    VM entered = {};              // with t_entry: the lanes whose tests entered the box
    const WideBvhNode* parent = nullptr;  // without: the node whose child the leaf is
    uint32_t slot = 0;
    const SameOctant* octant = nullptr;
};

// Each lane's leaf_floor_v for a leaf of a mesh's wide BVH, from the walk's own test of the
// leaf's box in that lane where it made one (LeafBox::t_entry), else from the SameOctant test made
// now (a frustum walk's rays go one way): either computes what the single-ray kernel's test does.
inline VF leaf_floor_lanes(const LeafBox& leaf, const PacketRays& r, VF t_min) {
    if (leaf.t_entry) return leaf_floor_v(leaf.entered, *leaf.t_entry);
    VF t_entry;
    const VM meets =
        child_hits<SlabTest::SameOctant>(*leaf.parent, leaf.slot, r, *leaf.octant, t_min, splat(__builtin_inff()), t_entry);
    return leaf_floor_v(meets, t_entry);
}

// Walks a mesh's wide BVH with the packet: every child box of a node is tested in every lane,
// the children some lane enters are visited nearest first (as the first lane that enters any of
// them sees it), and the others wait on the stack as (node, slot), their box tested again when
// popped. visit_leaf(payload, reached, leaf) is called with the live lanes whose box tests led to
// the leaf and, in a closest-hit walk, where those lanes enter its box (LeafBox; an any-hit walk
// does not keep the entries), and returns true to stop; t_cull() and r.live are re-read after it. Without kNearFirst,
// children are visited in slot order (for an any-hit query, whose cull distance never changes).
// skipped(node, slot) gives the lanes that need not enter that child however their box tests go
// (an any-hit query passing over back faces, scene/back_faces.h; no lanes for the others).
template <SlabTest kTest, bool kNearFirst, typename CullFn, typename LeafFn, typename SkipFn>
inline void traverse_packet_wide(const MeshView& mesh, const PacketRays& r, const SameOctant& octant, const VF& t_min,
                                 CullFn&& t_cull, LeafFn&& visit_leaf, SkipFn&& skipped) {
    const WideBvhNode* nodes = mesh.nodes;
    // A closest-hit walk keeps (node, slot) and tests the child's box again when it pops it,
    // against the nearer hits found meanwhile. An any-hit walk's cull distances never change, so
    // it keeps the child and the lanes that entered it, less those blocked since.
    struct Pending {
        uint32_t ref;   // closest-hit: the parent node; any-hit: the child itself
        uint32_t info;  // closest-hit: the child's slot in the parent; any-hit: the entered lanes' bits
    };
    Pending stack[kWideStackSize];
    int stack_size = 0;
    uint32_t ref = 0;  // the root node
    VM reached = r.live;  // the lanes whose box tests led to ref
    VF ref_entry = splat(-__builtin_inff());  // closest-hit: where the lanes enter ref's box
    LeafBox box{&ref_entry, r.live};
    for (;;) {
        if ((ref & kWideLeafFlag) == 0) {
            const WideBvhNode& node = nodes[ref];
            const VF cull = t_cull();
            VM entered[kWideBvhWidth];
            VF t_entry[kWideBvhWidth];
            unsigned slots = 0, lanes = 0;
            for (uint32_t slot = 0; slot < node.child_count; ++slot) {
                entered[slot] = child_hits<kTest>(node, slot, r, octant, t_min, cull, t_entry[slot]);
                if (!any(entered[slot])) continue;
                entered[slot] = andnot(entered[slot], skipped(ref, slot));
                if (!any(entered[slot])) continue;
                slots |= 1u << slot;
                lanes |= bits(entered[slot]);
            }
            for (unsigned b = slots; b; b &= b - 1) prefetch_child(mesh, node.child[lowest_bit(b)]);
            if (slots != 0 && !kNearFirst) {  // any order will do: the cull distance cannot change
                const unsigned first = lowest_bit(slots);
                for (unsigned b = slots & (slots - 1); b; b &= b - 1) {
                    const unsigned slot = lowest_bit(b);
                    stack[stack_size++] = {node.child[slot], bits(entered[slot])};
                }
                reached = entered[first];
                ref = node.child[first];
                continue;
            }
            if (slots != 0) {
                // Farthest first as the first entering lane sees them (children it misses last).
                const unsigned lane = lowest_bit(lanes);
                uint32_t order[kWideBvhWidth];
                float key[kWideBvhWidth];
                int count = 0;
                for (unsigned b = slots; b; b &= b - 1) {
                    const uint32_t slot = lowest_bit(b);
                    const float t = (bits(entered[slot]) >> lane) & 1u ? lane_value(t_entry[slot], lane) : __builtin_inff();
                    int i = count++;
                    for (; i > 0 && key[i - 1] < t; --i) {
                        key[i] = key[i - 1];
                        order[i] = order[i - 1];
                    }
                    key[i] = t;
                    order[i] = slot;
                }
                // At most kWideBvhWidth - 1 entries per level above the node (kWideStackSize).
                RAYCAST_DCHECK(stack_size + count - 1 <= kWideStackSize);
                for (int i = 0; i + 1 < count; ++i) stack[stack_size++] = {ref, order[i]};
                reached = entered[order[count - 1]];
                ref_entry = t_entry[order[count - 1]];
                ref = node.child[order[count - 1]];
                continue;
            }
        } else {
            box.entered = reached;
            if (visit_leaf(ref & kWidePayloadMask, reached & r.live, box)) return;
        }
        for (;;) {
            if (stack_size == 0) return;
            const Pending next = stack[--stack_size];
            if (!kNearFirst) {
                reached = mask_from_bits(next.info) & r.live;
                if (any(reached)) {
                    ref = next.ref;
                    break;
                }
                continue;
            }
            const WideBvhNode& parent = nodes[next.ref];
            VF t_entry;
            reached = andnot(child_hits<kTest>(parent, next.info, r, octant, t_min, t_cull(), t_entry),
                             skipped(next.ref, next.info));
            if (any(reached)) {
                ref_entry = t_entry;
                ref = parent.child[next.info];
                break;
            }
        }
    }
}

// traverse_packet_wide with the fastest slab test the packet allows (kNearFirst: for a closest-hit
// query; an any-hit query takes the children in slot order).
template <bool kNearFirst, typename CullFn, typename LeafFn, typename SkipFn>
inline void traverse_packet_wide(const MeshView& mesh, const PacketRays& r, float t_min, CullFn&& t_cull,
                                 LeafFn&& visit_leaf, SkipFn&& skipped) {
    SameOctant octant;
    const VF t_min_v = splat(t_min);
    if (t_min < 0)
        traverse_packet_wide<SlabTest::Widened, kNearFirst>(mesh, r, octant, t_min_v, t_cull, visit_leaf, skipped);
    else if (same_octant(r, octant))
        traverse_packet_wide<SlabTest::SameOctant, kNearFirst>(mesh, r, octant, t_min_v, t_cull, visit_leaf, skipped);
    else
        traverse_packet_wide<SlabTest::AnyOctant, kNearFirst>(mesh, r, octant, t_min_v, t_cull, visit_leaf, skipped);
}

// For traversals that skip nothing.
inline VM no_lanes(uint32_t, uint32_t) { return mask_from_bits(0); }

// Offers each lane in `candidates` the hit (t, u, v) on (object, prim); keeps the closer, with
// ties broken as is_closer() does.
inline void offer(PacketState& s, VM candidates, VF t, VF u, VF v, uint32_t object, uint32_t prim, uint32_t leaf,
                  uint32_t group_lane) {
    VM closer = candidates & (t < s.best_t);
    const VM ties = candidates & (t == s.best_t);
    if (any(ties)) {
        unsigned extra = 0;
        for (unsigned b = bits(ties); b; b &= b - 1) {
            const unsigned lane = lowest_bit(b);
            const Hit& best = s.hits[lane];
            if (object != best.object ? object < best.object : prim < best.prim) extra |= 1u << lane;
        }
        closer = closer | mask_from_bits(extra);
    }
    if (!any(closer)) return;
    RAYCAST_DCHECK((bits(closer) >> s.count) == 0);  // hits[] holds only the packet's rays
    float ts[kLanes], us[kLanes], vs[kLanes];
    store(ts, t);
    store(us, u);
    store(vs, v);
    for (unsigned b = bits(closer); b; b &= b - 1) {
        const unsigned lane = lowest_bit(b);
        Hit& hit = s.hits[lane];
        hit.t = ts[lane];
        hit.u = us[lane];
        hit.v = vs[lane];
        hit.object = object;
        hit.prim = prim;
        hit.leaf = leaf;
        hit.lane = group_lane;
    }
    s.best_t = select(closer, t, s.best_t);
}

// A group's vertices in every ray's sheared space: what intersect_triangle computes for each
// corner (ax, ay, az and so on), once per vertex instead of once per corner.
struct ShearedVertices {
    VF x[kGroupMaxVertices], y[kGroupMaxVertices], z[kGroupMaxVertices];
};

inline void shear_vertices(const unsigned char* group, const WatertightPacket& w, ShearedVertices& out) {
    const uint32_t k = group[0], v = group[1];
    const unsigned char* planes = group + group_vertices_offset(k);
    for (uint32_t j = 0; j < v; ++j) {
        const VF a_kx = splat(group_float(planes + 4 * (static_cast<uint32_t>(w.kx) * v + j))) - w.okx;
        const VF a_ky = splat(group_float(planes + 4 * (static_cast<uint32_t>(w.ky) * v + j))) - w.oky;
        const VF a_kz = splat(group_float(planes + 4 * (static_cast<uint32_t>(w.kz) * v + j))) - w.okz;
        out.x[j] = a_kx - w.sx * a_kz;
        out.y[j] = a_ky - w.sy * a_kz;
        out.z[j] = w.sz * a_kz;
    }
}

// shear_vertices with each lane's own permutation: the same values, lane by lane.
inline void shear_vertices_lanes(const unsigned char* group, const WatertightLanes& w, ShearedVertices& out) {
    const uint32_t k = group[0], v = group[1];
    const unsigned char* planes = group + group_vertices_offset(k);
    for (uint32_t j = 0; j < v; ++j) {
        const VF x = splat(group_float(planes + 4 * j)), y = splat(group_float(planes + 4 * (v + j))),
                 z = splat(group_float(planes + 4 * (2 * v + j)));
        const VF a_kx = pick_lanes(x, y, z, w.kx_y, w.kx_z) - w.okx;
        const VF a_ky = pick_lanes(x, y, z, w.ky_y, w.ky_z) - w.oky;
        const VF a_kz = pick_lanes(x, y, z, w.kz_y, w.kz_z) - w.okz;
        out.x[j] = a_kx - w.sx * a_kz;
        out.y[j] = a_ky - w.sy * a_kz;
        out.z[j] = w.sz * a_kz;
    }
}

// The watertight test of intersect_triangle, term for term, in every lane, for triangle `lane`
// of a group whose vertices are sheared. Returns the lanes (of `live`) that hit with t > t_min.
struct TriangleLanes {
    VM hit;
    VF t, u1, u2, det;
};

// Triangle `lane` of a group whose vertices are sheared: its corners' places among the group's
// vertices, and its edge functions in every lane (intersect_triangle's, u0 that of the edge
// opposite the first corner).
struct TriangleEdges {
    uint32_t i0, i1, i2;
    VF u0, u1, u2;
};

inline TriangleEdges triangle_edges(const unsigned char* group, uint32_t lane, const ShearedVertices& sv) {
    const uint32_t k = group[0];
    const unsigned char* corners = group + group_corners_offset();
    TriangleEdges e;
    e.i0 = corners[lane];
    e.i1 = corners[k + lane];
    e.i2 = corners[2 * k + lane];
    const VF ax = sv.x[e.i0], ay = sv.y[e.i0];
    const VF bx = sv.x[e.i1], by = sv.y[e.i1];
    const VF cx = sv.x[e.i2], cy = sv.y[e.i2];
    e.u0 = cx * by - cy * bx;
    e.u1 = ax * cy - ay * cx;
    e.u2 = bx * ay - by * ax;
    return e;
}

// The lanes (of `live`) whose rays pass inside the triangle. intersect_triangle misses where some
// edge function is below 0 and some above: here, where the least is below and the greatest above
// (four operations fewer than six comparisons; 1.03x on 1k-triangle packet renders, level at 100k
// and 1M). Only a lane with a NaN edge function can pass one form and fail the other, and such a
// lane never hits: its det is NaN, so is its t, and NaN > t_min is false.
inline VM inside_edges(const TriangleEdges& e, VM live) {
    const VF zero = splat(0.0f);
    const VF least = vmin(vmin(e.u0, e.u1), e.u2), greatest = vmax(vmax(e.u0, e.u1), e.u2);
    return andnot(live, (least < zero) & (greatest > zero));
}

// The group's triangles (a bit each) that some ray of `live` passes inside: test_triangle_packet's
// edge test alone, for every triangle, with no branch between them. A leaf finds these first and
// makes the whole test for them only (intersect_leaf_packet, occluded_mesh_packet).
inline unsigned triangles_inside(const unsigned char* group, const ShearedVertices& sv, VM live) {
    unsigned inside = 0;
    for (uint32_t lane = 0; lane < group[0]; ++lane)
        inside |= static_cast<unsigned>(any(inside_edges(triangle_edges(group, lane, sv), live))) << lane;
    return inside;
}

inline TriangleLanes test_triangle_packet(const unsigned char* group, uint32_t lane, const ShearedVertices& sv,
                                          VM live, VF t_min) {
    const TriangleEdges e = triangle_edges(group, lane, sv);
    TriangleLanes h;
    h.u1 = e.u1;
    h.u2 = e.u2;
    h.hit = inside_edges(e, live);
    if (!any(h.hit)) return h;
    const VF zero = splat(0.0f);
    h.det = e.u0 + e.u1 + e.u2;
    h.hit = h.hit & (h.det != zero);
    if (!any(h.hit)) return h;
    h.t = (e.u0 * sv.z[e.i0] + e.u1 * sv.z[e.i1] + e.u2 * sv.z[e.i2]) / h.det;
    h.hit = h.hit & (h.t > t_min);
    return h;
}

inline void refresh_best(PacketState& s) {
    static_assert(sizeof(Hit) % sizeof(float) == 0, "a hit is whole floats");
    const VF t = load_strided(&s.hits[0].t, static_cast<int>(sizeof(Hit) / sizeof(float)), s.count);
    s.best_t = select(mask_from_bits((1u << s.count) - 1), t, splat(__builtin_inff()));
}

// Hands the lanes to the scalar code, one ray at a time (exactly the single-ray path), with
// where each enters the box of the instance BVH's leaf `leaf` (null where none was tested).
inline void intersect_instance_lanes(PacketState& s, const PacketRays& r, uint32_t id, VM lanes, const BvhNode* leaf) {
    RAYCAST_DCHECK((bits(lanes) >> s.count) == 0);
    float entries[kLanes];
    if (leaf) {
        VF t_entry;
        node_hits(*leaf, r, s.t_min_v, splat(__builtin_inff()), t_entry);
        store(entries, t_entry);
    }
    for (unsigned b = bits(lanes); b; b &= b - 1) {
        const unsigned lane = lowest_bit(b);
        intersect_instance(*s.view.scene, id, s.rays[lane], s.t_min, leaf ? entries[lane] : -__builtin_inff(), s.hits[lane]);
    }
    refresh_best(s);
}

// Closest hits of the rays of r.live, which share w's permutation, with one leaf's triangles,
// each moved up to its lane's leaf_floor (leaf_floor_lanes); none in the lanes whose rays did not
// enter the leaf's box (a packet tests a leaf in every lane; a single ray would not reach it).
inline void intersect_leaf_packet(PacketState& s, const PacketRays& r, const WatertightPacket& w, const MeshView& mesh,
                                  uint32_t object, uint32_t first_block, const LeafBox& leaf, ShearedVertices& sheared) {
    VF t_floor;  // found at the first hit (most leaves have none)
    bool have_floor = false;
    for (uint32_t block = first_block;;) {
        const unsigned char* group = mesh.groups[block].bytes;
        shear_vertices(group, w, sheared);
        // The whole test only for the triangles some ray passes inside (rarely more than one or two).
        for (unsigned inside = triangles_inside(group, sheared, r.live); inside; inside &= inside - 1) {
            const uint32_t lane = lowest_bit(inside);
            const TriangleLanes h = test_triangle_packet(group, lane, sheared, r.live, s.t_min_v);
            if (!any(h.hit)) continue;
            if (!have_floor) {
                t_floor = leaf_floor_lanes(leaf, r, s.t_min_v);
                have_floor = true;
            }
            const VM counted = h.hit & (t_floor < splat(__builtin_inff()));
            // The triangle's id is read only for a hit: the last part of the group.
            if (any(counted))
                offer(s, counted, vmax(h.t, t_floor), h.u1 / h.det, h.u2 / h.det, object, group_id(group, lane), block, lane);
        }
        if (group[2] & kGroupEndsLeaf) return;
        block += group_blocks(group[0], group[1]);
    }
}

struct PacketFrustum;  // defined where the kernel has a frustum walk (RAYCAST_PACKET_FRUSTUM)

// Closest hits of the rays of r.live, which share w's permutation, with one mesh: walked as
// `frustum` (the packet's, when its rays share an origin and go one way; else null) unless that
// is too wide for the mesh's leaves, else lane by lane.
inline void walk_mesh_packet(PacketState& s, const PacketRays& r, const WatertightPacket& w, const MeshView& mesh,
                             uint32_t object, const PacketFrustum* frustum, const SameOctant* octant) {
    ShearedVertices sheared;
#ifdef RAYCAST_PACKET_FRUSTUM
    if (frustum && !frustum_too_wide(*frustum, mesh)) {
        traverse_frustum(mesh, *frustum, s.t_min, [&] { return max_of_lanes(cull_distance_v(s.best_t), r.live); },
                         [&](uint32_t first_block, const WideBvhNode& parent, uint32_t slot) {
                             const LeafBox leaf{nullptr, {}, &parent, slot, octant};
                             intersect_leaf_packet(s, r, w, mesh, object, first_block, leaf, sheared);
                             return false;
                         });
        return;
    }
#else
    (void)frustum;
    (void)octant;
#endif
    traverse_packet_wide<true>(
        mesh, r, s.t_min, [&] { return cull_distance_v(s.best_t); },
        [&](uint32_t first_block, VM, const LeafBox& leaf) {
            intersect_leaf_packet(s, r, w, mesh, object, first_block, leaf, sheared);
            return false;
        },
        no_lanes);
}

// walk_mesh_packet with the packet's frustum where it has one.
inline void intersect_mesh_packet(PacketState& s, const PacketRays& r, const WatertightPacket& w, const MeshView& mesh,
                                  uint32_t object) {
#ifdef RAYCAST_PACKET_FRUSTUM
    SameOctant octant;
    if (s.t_min >= 0 && same_octant(r, octant) && one_origin(r)) {
        const PacketFrustum frustum = make_frustum(r, octant);
        walk_mesh_packet(s, r, w, mesh, object, &frustum, &octant);
        return;
    }
#endif
    walk_mesh_packet(s, r, w, mesh, object, nullptr, nullptr);
}

// Marks the lanes of now_blocked in blocked[] and takes them out of r.live.
inline void mark_blocked(PacketRays& r, VM now_blocked, bool* blocked) {
    for (unsigned b = bits(now_blocked); b; b &= b - 1) blocked[lowest_bit(b)] = true;
    r.live = andnot(r.live, now_blocked);
}

// Any hits nearer than t_max of the rays of r.live with one mesh, each blocked ray marked and
// taken out of r.live. The rays walk the BVH together with the fastest slab test they allow,
// children in slot order (an any-hit query), so a node's box tests serve every ray that goes near
// it; at a leaf, the rays that reached it are tested against its triangles together, each lane
// with its own watertight permutation. Rays that go one way (shadow rays towards one light) share
// one; a hit's ambient-occlusion rays, which leave one point in every direction, have up to six,
// and each lane selects its own (WatertightLanes). The lanes of `skip_back_faces` pass over the children whose triangles all
// face away from them (mesh.cones, scene/back_faces.h), with faces_away's arithmetic.
inline void occluded_mesh_packet(PacketRays& r, const MeshView& mesh, float t_min, VF t_max, VF t_cull,
                                 bool* blocked, VM skip_back_faces) {
    AxisSet axes[6];
    const int set_count = axis_sets(r, axes);
    // One set (shadow rays towards a light): its shear, with one permutation for every lane.
    // Several (a hit's AO rays): each lane's own, so that a leaf's groups are sheared and tested
    // once for all the rays that reached it.
    WatertightPacket one_set;
    WatertightLanes per_lane;
    if (set_count == 1)
        one_set = make_watertight_packet(r, axes[0]);
    else
        per_lane = make_watertight_lanes(r, axes, set_count);
    ShearedVertices sheared;
    const VF t_min_v = splat(t_min);
    auto visit_leaf = [&](uint32_t first_block, VM reached, const LeafBox&) {
        VM lanes = reached & r.live;
        for (uint32_t block = first_block; any(lanes);) {
            const unsigned char* group = mesh.groups[block].bytes;
            if (set_count == 1)
                shear_vertices(group, one_set, sheared);
            else
                shear_vertices_lanes(group, per_lane, sheared);
            for (unsigned inside = triangles_inside(group, sheared, lanes); inside; inside &= inside - 1) {
                const uint32_t lane = lowest_bit(inside);
                const TriangleLanes h = test_triangle_packet(group, lane, sheared, lanes, t_min_v);
                if (!any(h.hit)) continue;
                const VM now_blocked = h.hit & (h.t < t_max);
                if (!any(now_blocked)) continue;
                mark_blocked(r, now_blocked, blocked);
                lanes = andnot(lanes, now_blocked);
                if (!any(lanes)) break;
            }
            if (group[2] & kGroupEndsLeaf) break;
            block += group_blocks(group[0], group[1]);
        }
        return !any(r.live);
    };
    if (mesh.cones && any(skip_back_faces)) {
        const VF length = vsqrt(r.dx * r.dx + r.dy * r.dy + r.dz * r.dz);
        const VM skipping = skip_back_faces & (splat(1e-15f) <= length) & (length <= splat(1e15f));
        auto faces_away = [&](uint32_t node, uint32_t slot) {
            const NodeCones& cones = mesh.cones[node];
            const VF dot = splat(static_cast<float>(cones.axis[0][slot])) * r.dx +
                           splat(static_cast<float>(cones.axis[1][slot])) * r.dy +
                           splat(static_cast<float>(cones.axis[2][slot])) * r.dz;
            return skipping & (splat(static_cast<float>(cones.reach[slot])) * length < dot);
        };
        traverse_packet_wide<false>(mesh, r, t_min, [&] { return t_cull; }, visit_leaf, faces_away);
        return;
    }
    traverse_packet_wide<false>(mesh, r, t_min, [&] { return t_cull; }, visit_leaf, no_lanes);
}

// intersect_sphere (geometry/sphere.h) in every lane of `lanes`, operation for operation (the
// quadratic in the form of Haines et al.): the lanes that hit with t > t_min, and their t.
inline VM sphere_hits(const Sphere& sphere, const PacketRays& r, VM lanes, VF t_min, VF& t_hit) {
    const VF fx = r.ox - splat(sphere.center.x), fy = r.oy - splat(sphere.center.y), fz = r.oz - splat(sphere.center.z);
    const VF a = r.dx * r.dx + r.dy * r.dy + r.dz * r.dz;
    const VF half_b = fx * r.dx + fy * r.dy + fz * r.dz;
    const VF radius_squared = splat(sphere.radius * sphere.radius);
    const VF c = (fx * fx + fy * fy + fz * fz) - radius_squared;
    const VF k = half_b / a;
    const VF cx = fx - r.dx * k, cy = fy - r.dy * k, cz = fz - r.dz * k;
    const VF discriminant = radius_squared - (cx * cx + cy * cy + cz * cz);
    VM hit = lanes & (splat(0.0f) <= discriminant);
    if (!any(hit)) {
        t_hit = splat(__builtin_inff());
        return hit;
    }
    // root_of_product (geometry/sphere.h), lane by lane: √a·√b where the product leaves float's range.
    const VF product = a * discriminant;
    VF root = vsqrt(product);
    const VM ordinary = ((product < splat(__builtin_inff())) & (product > splat(0.0f))) |
                        (discriminant == splat(0.0f)) | (a == splat(0.0f));
    const VM unusual = andnot(hit, ordinary);
    if (any(unusual)) root = select(unusual, vsqrt(a) * vsqrt(discriminant), root);
    const VF q = splat(-0.0f) - (half_b + vcopysign(root, half_b));  // -(...), exactly
    hit = hit & (q != splat(0.0f));
    const VF t0 = q / a, t1 = c / q;
    const VM swap = t0 > t1;
    const VF near = select(swap, t1, t0), far = select(swap, t0, t1);
    const VM near_counts = near > t_min;
    t_hit = select(near_counts, near, far);
    return hit & (near_counts | (far > t_min));
}

// intersect_plane (geometry/plane.h) in every lane of `lanes`, operation for operation.
inline VM plane_hits(const Plane& plane, const PacketRays& r, VM lanes, VF t_min, VF& t_hit) {
    const VF nx = splat(plane.normal.x), ny = splat(plane.normal.y), nz = splat(plane.normal.z);
    const VF denominator = nx * r.dx + ny * r.dy + nz * r.dz;
    t_hit = (splat(plane.offset) - (nx * r.ox + ny * r.oy + nz * r.oz)) / denominator;
    return lanes & (denominator != splat(0.0f)) & (t_hit > t_min);  // != is true for NaN, as == 0 is false
}

// Moves the packet into an instance's object space as to_object_space does, operation for
// operation.
inline PacketRays transform_packet(const PacketRays& r, const Mat4& m, bool with_inverses = true) {
    PacketRays o;
    o.ox = splat(m.m[0][0]) * r.ox + splat(m.m[0][1]) * r.oy + splat(m.m[0][2]) * r.oz + splat(m.m[0][3]);
    o.oy = splat(m.m[1][0]) * r.ox + splat(m.m[1][1]) * r.oy + splat(m.m[1][2]) * r.oz + splat(m.m[1][3]);
    o.oz = splat(m.m[2][0]) * r.ox + splat(m.m[2][1]) * r.oy + splat(m.m[2][2]) * r.oz + splat(m.m[2][3]);
    o.dx = splat(m.m[0][0]) * r.dx + splat(m.m[0][1]) * r.dy + splat(m.m[0][2]) * r.dz;
    o.dy = splat(m.m[1][0]) * r.dx + splat(m.m[1][1]) * r.dy + splat(m.m[1][2]) * r.dz;
    o.dz = splat(m.m[2][0]) * r.dx + splat(m.m[2][1]) * r.dy + splat(m.m[2][2]) * r.dz;
    o.live = r.live;
    if (with_inverses) prepare_inverses(o);
    return o;
}

// Spheres and planes are tested in SIMD, each with its scalar test's arithmetic.
inline bool has_simd_test(ShapeKind kind) { return kind == ShapeKind::Sphere || kind == ShapeKind::Plane; }

// The lanes of `lanes` that hit a sphere or plane instance with t > t_min, and their t, found in
// its object space (the packet moved there without the inverse directions, which neither test
// uses).
inline VM shape_hits(const PacketSceneView& view, const Instance& instance, const PacketRays& r, VM lanes, VF t_min,
                     VF& t) {
    RAYCAST_DCHECK(has_simd_test(instance.kind));
    if (instance.transform != kNoTransformIndex) {
        const PacketRays local = transform_packet(r, view.object_from_world[instance.transform], false);
        return instance.kind == ShapeKind::Sphere ? sphere_hits(view.spheres[instance.shape], local, lanes, t_min, t)
                                                  : plane_hits(view.planes[instance.shape], local, lanes, t_min, t);
    }
    return instance.kind == ShapeKind::Sphere ? sphere_hits(view.spheres[instance.shape], r, lanes, t_min, t)
                                              : plane_hits(view.planes[instance.shape], r, lanes, t_min, t);
}

// The closest hits of the lanes `lanes` with a sphere or plane instance, offered as
// intersect_instance offers them (u = v = 0, primitive 0), moved up to each lane's floor in the
// instance BVH's leaf `leaf` (node_floor), none in the lanes whose rays miss its box.
inline void intersect_shape_lanes(PacketState& s, const PacketRays& r, uint32_t id, VM lanes, const BvhNode* leaf) {
    VF t;
    VM hit = shape_hits(s.view, s.view.instances[id], r, lanes, s.t_min_v, t);
    if (!any(hit)) return;
    const VF t_floor = node_floor(leaf, r, s.t_min_v);
    hit = hit & (t_floor < splat(__builtin_inff()));
    if (any(hit)) offer(s, hit, vmax(t, t_floor), splat(0.0f), splat(0.0f), id, 0, 0, 0);
}

// The any hits nearer than t_max of the live lanes with a sphere or plane instance.
inline void occluded_shape_lanes(const PacketSceneView& view, uint32_t id, PacketRays& r, VF t_min, VF t_max,
                                 bool* blocked) {
    VF t;
    const VM hit = shape_hits(view, view.instances[id], r, r.live, t_min, t);
    mark_blocked(r, hit & (t < t_max), blocked);
}

// Whether a packet's live rays go the same way along every axis. Such rays (primary rays, shadow
// rays towards one light) share most of their way through a BVH. For the closest hit, rays that
// scatter (from many surfaces) part at once, and each is faster alone, through the single-ray
// kernel, than in a packet that tests every box for every lane; for any hits, they stay in the
// packet (occluded_mesh_packet): the rays that ask (ambient occlusion) leave one point.
inline bool coherent(const PacketRays& r) {
    SameOctant octant;
    return same_octant(r, octant);
}

// Calls trace(r, w) for each set of the live rays that share a watertight axis permutation
// (usually one set: the rays of a packet point the same way), with r.live narrowed to it (and
// left so: r is the caller's copy).
template <typename TraceFn>
inline void for_each_permutation(PacketRays& r, TraceFn&& trace) {
    AxisSet sets[6];
    const int count = axis_sets(r, sets);
    for (int i = 0; i < count; ++i) {
        r.live = sets[i].lanes;
        trace(r, make_watertight_packet(r, sets[i]));
    }
}

// The closest hits of the lanes `lanes` of r (the packet of s) with one instance, found in the
// instance BVH's leaf `leaf` (null where its box was not tested).
inline void intersect_instance_packet(PacketState& s, const PacketRays& r, uint32_t id, VM lanes, const BvhNode* leaf) {
    const PacketSceneView& view = s.view;
    const Instance& instance = view.instances[id];
    if (has_simd_test(instance.kind)) {
        intersect_shape_lanes(s, r, id, lanes, leaf);
        return;
    }
    if (instance.kind != ShapeKind::Mesh) {
        intersect_instance_lanes(s, r, id, lanes, leaf);
        return;
    }
    const MeshView& mesh = view.meshes[instance.shape];
    if (!mesh.nodes) return;
    if (instance.transform == kNoTransformIndex && coherent(r)) {
        // The packet as it is, without the copy below, when one permutation serves all its rays
        // (nearly always).
        AxisSet sets[6];
        if (axis_sets(r, sets) == 1) {
            intersect_mesh_packet(s, r, make_watertight_packet(r, sets[0]), mesh, id);
            return;
        }
    }
    PacketRays local =
        instance.transform == kNoTransformIndex ? r : transform_packet(r, view.object_from_world[instance.transform]);
    if (!coherent(local)) {
        intersect_instance_lanes(s, r, id, lanes, leaf);
        return;
    }
    for_each_permutation(local, [&](const PacketRays& subset, const WatertightPacket& w) {
        intersect_mesh_packet(s, subset, w, mesh, id);
    });
}

inline void trace_packet(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    // Dead lanes copy lane 0, and the live mask is (1 << count) - 1.
    RAYCAST_DCHECK(count >= 1 && count <= kLanes);
    PacketState s{view, rays, hits, count, t_min, splat(t_min), splat(0.0f)};
    const PacketRays r = load_packet(rays, count);
    refresh_best(s);

    // Planes are unbounded and few: each is tested outside the BVH, as the single-ray path does.
    for (uint32_t i = 0; i < view.plane_count; ++i)
        intersect_shape_lanes(s, r, view.plane_instances[i], r.live, nullptr);
    if (view.instance_node_count == 0) return;

    traverse_packet(
        view.instance_nodes, r, s.t_min_v, [&] { return cull_distance_v(s.best_t); },
        [&](uint32_t first, uint32_t n, VM lanes, const BvhNode* leaf) {
            for (uint32_t i = first; i < first + n; ++i)
                intersect_instance_packet(s, r, view.instance_ids[i], lanes, leaf);
            return false;
        });
}

inline void trace_packet_occluded(const PacketSceneView& view, const Ray* rays, int count, float t_min,
                                  const float* t_max, bool* blocked, const BackFaceSkipping& skipping) {
    RAYCAST_DCHECK(count >= 1 && count <= kLanes);
    PacketRays r = load_packet(rays, count);
    unsigned skip_rays = 0;  // the lanes that may skip the back faces of skipping.instances
    if (skipping.instances)
        for (int lane = 0; lane < count; ++lane) skip_rays |= unsigned{skipping.rays[lane]} << lane;
    float t_max_lanes[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) t_max_lanes[lane] = lane < count ? t_max[lane] : 0.0f;
    const VF t_max_v = load(t_max_lanes), t_min_v = splat(t_min);
    const VF t_cull = cull_distance_v(t_max_v);  // as traverse_bvh culls an any-hit query
    for (int lane = 0; lane < count; ++lane) blocked[lane] = false;

    // Scalar code for everything but meshes, lane by lane, as in trace_packet.
    auto occluded_lanes = [&](uint32_t id) {
        unsigned now_blocked = 0;
        for (unsigned b = bits(r.live); b; b &= b - 1) {
            const unsigned lane = lowest_bit(b);
            if (occluded_instance(*view.scene, id, rays[lane], t_min, t_max[lane])) now_blocked |= 1u << lane;
        }
        mark_blocked(r, mask_from_bits(now_blocked), blocked);
    };
    for (uint32_t i = 0; i < view.plane_count && any(r.live); ++i)  // as in trace_packet
        occluded_shape_lanes(view, view.plane_instances[i], r, t_min_v, t_max_v, blocked);
    if (view.instance_node_count == 0 || !any(r.live)) return;

    traverse_packet(view.instance_nodes, r, t_min_v, [&] { return t_cull; }, [&](uint32_t first, uint32_t n, VM, const BvhNode*) {
        for (uint32_t i = first; i < first + n; ++i) {
            const uint32_t id = view.instance_ids[i];
            const Instance& instance = view.instances[id];
            if (has_simd_test(instance.kind)) {
                occluded_shape_lanes(view, id, r, t_min_v, t_max_v, blocked);
            } else if (instance.kind != ShapeKind::Mesh) {
                occluded_lanes(id);
            } else if (view.meshes[instance.shape].nodes) {
                const MeshView& mesh = view.meshes[instance.shape];
                const VM skip = mask_from_bits(skip_rays != 0 && skipping.instances[id] ? skip_rays : 0);
                if (instance.transform == kNoTransformIndex) {  // the packet as it is, no copy
                    occluded_mesh_packet(r, mesh, t_min, t_max_v, t_cull, blocked, skip);
                } else {
                    PacketRays local = transform_packet(r, view.object_from_world[instance.transform]);
                    occluded_mesh_packet(local, mesh, t_min, t_max_v, t_cull, blocked, skip);
                    r.live = local.live;  // less the lanes it blocked
                }
            }
            if (!any(r.live)) return true;
        }
        return false;
    });
}

#ifdef RAYCAST_PACKET_FRUSTUM
// Several packets of one pinhole camera (the four 4x4 packets of an 8x8 block of pixels) walk a
// mesh's BVH together, as one frustum over all their rays: a node's children are tested once
// for the block instead of once per packet, and at a leaf each packet whose own frustum enters
// the leaf's box tests its triangles, as it would have on its own walk (the four packets'
// tests in one register). The triangles are not shared, so the gain is what the walk was: the
// trace alone 1.09x faster at 100k triangles and 1.065x at 1M, level at 1k (a walk of three
// nodes) and at 5M, where a block's frustum is too wide for the leaves and each packet walks
// alone (docs/performance.md). The hits are the same: the block's frustum holds every packet's,
// and each packet's holds its rays (make_frustum), so no ray misses a box it enters, and a
// ray's closest hit does not depend on the order the triangles came in (offer).

// One packet of a block: its rays, its triangle test's constants, its frustum, and its hits.
struct SharedPacket {
    PacketRays r;
    SameOctant octant;
    WatertightPacket w;
    PacketFrustum f;
    PacketState* s;
};

inline float packet_cull(const SharedPacket& packet) {
    return max_of_lanes(cull_distance_v(packet.s->best_t), packet.r.live);
}

// The frustum of packets[0, count) together: their ranges of inverses, from their one origin
// (the caller has checked that they share it and their near bounds), and their spread as
// make_frustum finds a packet's, over all their lanes.
inline PacketFrustum shared_frustum(const SharedPacket* packets, int count) {
    PacketFrustum block = packets[0].f;
    float widest = 0;
    for (int axis = 0; axis < 3; ++axis) {
        for (int p = 1; p < count; ++p) {
            const PacketFrustum& f = packets[p].f;
            block.near_lo[axis] = f.near_lo[axis] < block.near_lo[axis] ? f.near_lo[axis] : block.near_lo[axis];
            block.near_hi[axis] = f.near_hi[axis] > block.near_hi[axis] ? f.near_hi[axis] : block.near_hi[axis];
            block.far_lo[axis] = f.far_lo[axis] < block.far_lo[axis] ? f.far_lo[axis] : block.far_lo[axis];
            block.far_hi[axis] = f.far_hi[axis] > block.far_hi[axis] ? f.far_hi[axis] : block.far_hi[axis];
            block.direction_lo[axis] =
                f.direction_lo[axis] < block.direction_lo[axis] ? f.direction_lo[axis] : block.direction_lo[axis];
            block.direction_hi[axis] =
                f.direction_hi[axis] > block.direction_hi[axis] ? f.direction_hi[axis] : block.direction_hi[axis];
        }
        const float range = block.direction_hi[axis] - block.direction_lo[axis];
        widest = range > widest ? range : widest;
    }
    block.spread = widest / block.length;
    return block;
}

// traverse_frustum with the frustum of packets[0, count) (shared_frustum), each leaf tested by
// those of them whose own frustum enters its box before their own cull distance.
inline void traverse_frustum_shared(const MeshView& mesh, const PacketFrustum& block, const SharedPacket* packets,
                                    int count, float t_min, uint32_t object) {
    const WideBvhNode* nodes = mesh.nodes;
    struct Pending {
        uint32_t ref;
        float t_entry;
        uint32_t parent, slot;  // where the child's box is: a leaf's is tested again for each packet
    };
    Pending stack[kWideStackSize];
    int stack_size = 0;
    Pending current{0, 0.0f, 0, 0};  // the root node
    // The packets' frusta a lane each (frustum_children's terms), for their tests at the leaves.
    alignas(32) float culls[8] = {};
    alignas(32) float near_lo[3][8] = {}, near_hi[3][8] = {}, far_lo[3][8] = {}, far_hi[3][8] = {};
    for (int p = 0; p < count; ++p) {
        const PacketFrustum& f = packets[p].f;
        for (int axis = 0; axis < 3; ++axis) {
            near_lo[axis][p] = f.near_lo[axis];
            near_hi[axis][p] = f.near_hi[axis];
            far_lo[axis][p] = f.far_lo[axis];
            far_hi[axis][p] = f.far_hi[axis];
        }
        culls[p] = packet_cull(packets[p]);
    }
    static_assert(kMaxSharedPackets <= 8, "a packet a lane of wide8");
    const unsigned packet_lanes = (1u << count) - 1;
    auto max_cull = [&] {
        float cull = culls[0];
        for (int p = 1; p < count; ++p) cull = culls[p] > cull ? culls[p] : cull;
        return cull;
    };
    float cull = max_cull();
    ShearedVertices sheared;
    for (;;) {
        if ((current.ref & kWideLeafFlag) == 0) {
            const WideBvhNode& node = nodes[current.ref];
            wide8::VF t_entry;
            unsigned hits = frustum_children(node, block, t_min, cull, t_entry);
            if (hits != 0) {
                float t[kWideBvhWidth];
                wide8::store(t, t_entry);
                Pending entered[kWideBvhWidth];
                int entered_count = 0;
                for (; hits; hits &= hits - 1) {
                    const unsigned slot = lowest_bit(hits);
                    const Pending child{node.child[slot], t[slot], current.ref, slot};
                    prefetch_child(mesh, child.ref);
                    int i = entered_count++;
                    for (; i > 0 && entered[i - 1].t_entry < child.t_entry; --i) entered[i] = entered[i - 1];
                    entered[i] = child;
                }
                RAYCAST_DCHECK(stack_size + entered_count - 1 <= kWideStackSize);
                for (int i = 0; i + 1 < entered_count; ++i) stack[stack_size++] = entered[i];
                current = entered[entered_count - 1];
                continue;
            }
        } else {
            // Every packet's frustum against the leaf's box at once, a packet a lane, as
            // frustum_children tests a node's children (the packets share the block's origin
            // and near bounds).
            using wide8::load;
            using wide8::vmax;
            using wide8::vmin;
            const WideBvhNode& parent = nodes[current.parent];
            wide8::VF entry = wide8::splat(t_min), exit = load(culls);
            for (int axis = 0; axis < 3; ++axis) {
                const float* bounds = parent.bounds[axis][block.near[axis]];
                const float* far_bounds = parent.bounds[axis][1 - block.near[axis]];
                const wide8::VF to_near = wide8::splat(bounds[current.slot] - block.origin[axis]);
                const wide8::VF to_far = wide8::splat(far_bounds[current.slot] - block.origin[axis]);
                entry = vmax(entry, vmin(to_near * load(near_lo[axis]), to_near * load(near_hi[axis])));
                exit = vmin(exit, vmax(to_far * load(far_lo[axis]), to_far * load(far_hi[axis])));
            }
            for (unsigned b = wide8::bits(entry <= exit) & packet_lanes; b; b &= b - 1) {
                const unsigned p = lowest_bit(b);
                const LeafBox leaf{nullptr, {}, &parent, current.slot, &packets[p].octant};
                intersect_leaf_packet(*packets[p].s, packets[p].r, packets[p].w, mesh, object,
                                      current.ref & kWidePayloadMask, leaf, sheared);
                culls[p] = packet_cull(packets[p]);
            }
            cull = max_cull();
        }
        for (;;) {
            if (stack_size == 0) return;
            const Pending next = stack[--stack_size];
            if (next.t_entry <= cull) {
                current = next;
                break;
            }
        }
    }
}

// trace_packet for each packet of rays[0, count) (kLanes to a packet), the packets walking each
// untransformed mesh together, when they can: rays of one origin that go one way along every
// axis (a pinhole camera's), t_min >= 0, and a scene whose objects all lie in one leaf of its
// instance BVH (one mesh, or a few objects), where trace_packet tests every one of them anyway.
// Each packet first tests the other objects, as trace_packet does; then the packets walk each
// untransformed mesh together, the order of the leaf's objects being all that changes (and a
// closest hit does not depend on it). In a deeper instance BVH the meshes' hits would come too
// late to cull the objects behind them: a mesh in front of 3,600 spheres rendered 1.31x slower
// that way. Returns false, having done nothing, when the packets cannot share.
inline bool trace_packets_together(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    if (!(t_min >= 0) || view.instance_node_count == 0 || view.instance_nodes[0].count == 0) return false;
    const int packet_count = (count + kLanes - 1) / kLanes;
    auto rays_in = [&](int p) { return count - p * kLanes < kLanes ? count - p * kLanes : kLanes; };
    SharedPacket packets[kMaxSharedPackets];
    for (int p = 0; p < packet_count; ++p) {
        SharedPacket& packet = packets[p];
        packet.r = load_packet(rays + p * kLanes, rays_in(p));
        AxisSet sets[6];
        if (!same_octant(packet.r, packet.octant) || !one_origin(packet.r) || axis_sets(packet.r, sets) != 1)
            return false;
        packet.w = make_watertight_packet(packet.r, sets[0]);
        packet.f = make_frustum(packet.r, packet.octant);
        for (int axis = 0; axis < 3; ++axis)
            if (packet.f.near[axis] != packets[0].f.near[axis] || !(packet.f.origin[axis] == packets[0].f.origin[axis]))
                return false;
    }
    static_assert(kMaxSharedPackets == 4, "one state per packet below");
    auto state = [&](int p) {  // the packets past packet_count are never used (and point at the first's rays)
        const int at = p < packet_count ? p * kLanes : 0;
        return PacketState{view, rays + at, hits + at, p < packet_count ? rays_in(p) : 0, t_min, splat(t_min),
                           splat(0.0f)};
    };
    PacketState states[kMaxSharedPackets] = {state(0), state(1), state(2), state(3)};

    // Every object is in the instance BVH's one leaf: the untransformed meshes are walked
    // together, after each packet has tested the rest as trace_packet does.
    const BvhNode& leaf = view.instance_nodes[0];
    auto shared = [&](uint32_t id) {
        const Instance& instance = view.instances[id];
        return instance.kind == ShapeKind::Mesh && instance.transform == kNoTransformIndex;
    };
    for (int p = 0; p < packet_count; ++p) {
        SharedPacket& packet = packets[p];
        PacketState& s = states[p];
        packet.s = &s;
        refresh_best(s);
        // Planes are unbounded and few: each is tested outside the BVH, as in trace_packet.
        for (uint32_t i = 0; i < view.plane_count; ++i)
            intersect_shape_lanes(s, packet.r, view.plane_instances[i], packet.r.live, nullptr);
        // The one leaf's box is not tested (as in trace_packet), so every hit counts.
        for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
            if (!shared(view.instance_ids[i]))
                intersect_instance_packet(s, packet.r, view.instance_ids[i], packet.r.live, nullptr);
    }
    const PacketFrustum block = shared_frustum(packets, packet_count);
    for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
        const uint32_t id = view.instance_ids[i];
        if (!shared(id)) continue;
        const MeshView& mesh = view.meshes[view.instances[id].shape];
        if (!mesh.nodes) continue;
        if (frustum_too_wide(block, mesh)) {  // each packet as in trace_packet
            for (int p = 0; p < packet_count; ++p)
                walk_mesh_packet(*packets[p].s, packets[p].r, packets[p].w, mesh, id, &packets[p].f, &packets[p].octant);
            continue;
        }
        traverse_frustum_shared(mesh, block, packets, packet_count, t_min, id);
    }
    return true;
}
#endif

// trace_packet for each packet of rays[0, count) (kLanes to a packet, count <= kMaxSharedPackets
// * kLanes), together where they can be (trace_packets_together).
inline void trace_packets(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    RAYCAST_DCHECK(count >= 1 && count <= kMaxSharedPackets * kLanes);
#ifdef RAYCAST_PACKET_FRUSTUM
    if (count > kLanes && trace_packets_together(view, rays, count, t_min, hits)) return;
#endif
    for (int first = 0; first < count; first += kLanes)
        trace_packet(view, rays + first, count - first < kLanes ? count - first : kLanes, t_min, hits + first);
}
