// The packet tracer, written once over the SIMD wrapper of the file that includes it
// (packet_<isa>.cpp, inside that instruction set's namespace; no include guard, no includes).
//
// A packet is kLanes rays from neighbouring pixels. It walks each BVH together: a node is
// entered when any ray's slab test passes, so one box test in SIMD serves every ray. Triangle
// tests are the watertight test of geometry/triangle.h evaluated in every lane with exactly the
// same floating-point operations in the same order, so each lane finds bit for bit the hit the
// single-ray path finds (the results never depend on the path; tests check it).
//
// Only fields of the shared structs are read here, never their inline functions (see
// packet_view.h for why).

constexpr float kBoxWiden = 4 * 5.96046448e-08f;  // as in bvh.h's intersect_box
constexpr float kTiny = 1e-30f;
constexpr uint32_t kNoTransformIndex = 0xffffffffu;

struct PacketRays {
    VF ox, oy, oz;
    VF dx, dy, dz;
    VF ix, iy, iz;  // safe inverses of the direction, for slab tests
    VM live;        // lanes that hold a ray
};

// The watertight test's per-ray constants (see make_watertight_ray). The axis permutation must
// be the same in every live lane; `uniform` says whether it is.
struct WatertightPacket {
    int kx = 0, ky = 1, kz = 2;
    bool uniform = false;
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

inline float scalar_abs(float x) { return x < 0 ? -x : x; }

inline float safe_inverse_scalar(float d) {
    const float magnitude = scalar_abs(d);
    const float safe = magnitude < kTiny ? (d < 0 || (d == 0 && 1 / d < 0) ? -kTiny : kTiny) : d;
    return 1.0f / safe;
}

inline VF pick(const VF& x, const VF& y, const VF& z, int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
inline float pick(float x, float y, float z, int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }

inline unsigned lowest_lane(unsigned b) { return static_cast<unsigned>(__builtin_ctz(b)); }

// Fills the inverse directions from the ray components.
inline void prepare_inverses(PacketRays& r) {
    float d[3][kLanes], inv[3][kLanes];
    store(d[0], r.dx);
    store(d[1], r.dy);
    store(d[2], r.dz);
    for (int axis = 0; axis < 3; ++axis)
        for (int lane = 0; lane < kLanes; ++lane) inv[axis][lane] = safe_inverse_scalar(d[axis][lane]);
    r.ix = load(inv[0]);
    r.iy = load(inv[1]);
    r.iz = load(inv[2]);
}

// The same choice as make_watertight_ray, lane by lane, then the shear constants in SIMD.
inline WatertightPacket make_watertight_packet(const PacketRays& r) {
    WatertightPacket w;
    float d[3][kLanes];
    store(d[0], r.dx);
    store(d[1], r.dy);
    store(d[2], r.dz);
    const unsigned live = bits(r.live);
    bool first = true;
    for (int lane = 0; lane < kLanes; ++lane) {
        if (!((live >> lane) & 1u)) continue;
        const float ax = scalar_abs(d[0][lane]), ay = scalar_abs(d[1][lane]), az = scalar_abs(d[2][lane]);
        const int kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
        int kx = kz == 2 ? 0 : kz + 1;
        int ky = kx == 2 ? 0 : kx + 1;
        if (d[kz][lane] < 0) {
            const int swap = kx;
            kx = ky;
            ky = swap;
        }
        if (first) {
            w.kx = kx;
            w.ky = ky;
            w.kz = kz;
            first = false;
        } else if (kx != w.kx || ky != w.ky || kz != w.kz) {
            return w;  // not uniform
        }
    }
    w.uniform = true;
    const VF dkz = pick(r.dx, r.dy, r.dz, w.kz);
    w.sx = pick(r.dx, r.dy, r.dz, w.kx) / dkz;
    w.sy = pick(r.dx, r.dy, r.dz, w.ky) / dkz;
    w.sz = splat(1.0f) / dkz;
    w.okx = pick(r.ox, r.oy, r.oz, w.kx);
    w.oky = pick(r.ox, r.oy, r.oz, w.ky);
    w.okz = pick(r.ox, r.oy, r.oz, w.kz);
    return w;
}

inline VF cull_distance_v(VF t_best) { return t_best + vabs(t_best) * splat(1.0f / 1024); }

// The slab test in every lane, widened like intersect_box so that it never misses.
inline VM box_hits(const BvhNode& node, const PacketRays& r, VF t_min, VF t_cull, VF& t_entry) {
    const Bounds3f& b = node.bounds;
    const VF n0 = (splat(b.lower.x) - r.ox) * r.ix, f0 = (splat(b.upper.x) - r.ox) * r.ix;
    const VF n1 = (splat(b.lower.y) - r.oy) * r.iy, f1 = (splat(b.upper.y) - r.oy) * r.iy;
    const VF n2 = (splat(b.lower.z) - r.oz) * r.iz, f2 = (splat(b.upper.z) - r.oz) * r.iz;
    const VF near = vmax(vmax(vmin(n0, f0), vmin(n1, f1)), vmin(n2, f2));
    const VF far = vmin(vmin(vmax(n0, f0), vmax(n1, f1)), vmax(n2, f2));
    const VF widen = splat(kBoxWiden);
    const VF t0 = vmax(near - vabs(near) * widen, t_min);
    const VF t1 = vmin(far + vabs(far) * widen, t_cull);
    t_entry = t0;
    return (t0 <= t1) & r.live;
}

inline float lane_value(VF v, unsigned lane) {
    float values[kLanes];
    store(values, v);
    return values[lane];
}

// Walks a BVH with the packet; visit_leaf(first, count, lanes) is called for every leaf that
// some live ray's box test reaches. best_t is re-read after every leaf.
template <typename LeafFn>
inline void traverse_packet(const BvhNode* nodes, const PacketRays& r, const VF& t_min, const VF& best_t,
                            LeafFn&& visit_leaf) {
    VF t_entry;
    VM mask = box_hits(nodes[0], r, t_min, cull_distance_v(best_t), t_entry);
    if (!any(mask)) return;
    uint32_t stack[128];
    int stack_size = 0;
    uint32_t current = 0;
    for (;;) {
        const BvhNode& node = nodes[current];
        if (node.count != 0) {
            visit_leaf(node.first, node.count, mask);
        } else {
            const VF t_cull = cull_distance_v(best_t);
            VF t_left, t_right;
            const VM hit_left = box_hits(nodes[node.first], r, t_min, t_cull, t_left);
            const VM hit_right = box_hits(nodes[node.first + 1], r, t_min, t_cull, t_right);
            const bool any_left = any(hit_left), any_right = any(hit_right);
            if (any_left && any_right) {
                // Nearer child first, as seen by the first ray that enters both.
                const VM both = hit_left & hit_right;
                const unsigned lane = lowest_lane(any(both) ? bits(both) : bits(hit_left));
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
            mask = box_hits(nodes[current], r, t_min, cull_distance_v(best_t), t_entry);
            if (any(mask)) break;
        }
    }
}

// Offers each lane in `candidates` the hit (t, u, v) on (object, prim); keeps the closer, with
// ties broken as is_closer() does.
inline void offer(PacketState& s, VM candidates, VF t, VF u, VF v, uint32_t object, uint32_t prim, uint32_t leaf) {
    VM closer = candidates & (t < s.best_t);
    const VM ties = candidates & (t == s.best_t);
    if (any(ties)) {
        unsigned extra = 0;
        for (unsigned b = bits(ties); b; b &= b - 1) {
            const unsigned lane = lowest_lane(b);
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
        const unsigned lane = lowest_lane(b);
        Hit& hit = s.hits[lane];
        hit.t = ts[lane];
        hit.u = us[lane];
        hit.v = vs[lane];
        hit.object = object;
        hit.prim = prim;
        hit.leaf = leaf;
    }
    s.best_t = select(closer, t, s.best_t);
}

// The watertight test of intersect_triangle, term for term, in every lane.
inline void intersect_triangle_packet(PacketState& s, const WatertightPacket& w, const VM& live,
                                      const PacketMeshView& mesh, uint32_t leaf, uint32_t object) {
    const LeafTriangle& tri = mesh.triangles[leaf];
    const VF a_kx = splat(pick(tri.p0.x, tri.p0.y, tri.p0.z, w.kx)) - w.okx;
    const VF a_ky = splat(pick(tri.p0.x, tri.p0.y, tri.p0.z, w.ky)) - w.oky;
    const VF a_kz = splat(pick(tri.p0.x, tri.p0.y, tri.p0.z, w.kz)) - w.okz;
    const VF b_kx = splat(pick(tri.p1.x, tri.p1.y, tri.p1.z, w.kx)) - w.okx;
    const VF b_ky = splat(pick(tri.p1.x, tri.p1.y, tri.p1.z, w.ky)) - w.oky;
    const VF b_kz = splat(pick(tri.p1.x, tri.p1.y, tri.p1.z, w.kz)) - w.okz;
    const VF c_kx = splat(pick(tri.p2.x, tri.p2.y, tri.p2.z, w.kx)) - w.okx;
    const VF c_ky = splat(pick(tri.p2.x, tri.p2.y, tri.p2.z, w.ky)) - w.oky;
    const VF c_kz = splat(pick(tri.p2.x, tri.p2.y, tri.p2.z, w.kz)) - w.okz;
    const VF ax = a_kx - w.sx * a_kz, ay = a_ky - w.sy * a_kz;
    const VF bx = b_kx - w.sx * b_kz, by = b_ky - w.sy * b_kz;
    const VF cx = c_kx - w.sx * c_kz, cy = c_ky - w.sy * c_kz;
    const VF u0 = cx * by - cy * bx;
    const VF u1 = ax * cy - ay * cx;
    const VF u2 = bx * ay - by * ax;
    const VF zero = splat(0.0f);
    const VM negative = (u0 < zero) | (u1 < zero) | (u2 < zero);
    const VM positive = (u0 > zero) | (u1 > zero) | (u2 > zero);
    VM valid = andnot(live, negative & positive);
    if (!any(valid)) return;
    const VF det = u0 + u1 + u2;
    valid = valid & (det != zero);
    if (!any(valid)) return;
    const VF az = w.sz * a_kz, bz = w.sz * b_kz, cz = w.sz * c_kz;
    const VF t = (u0 * az + u1 * bz + u2 * cz) / det;
    valid = valid & (t > s.t_min_v);
    if (!any(valid)) return;
    // The triangle's id is read only for a hit: another array, and mostly another cache line.
    offer(s, valid, t, u1 / det, u2 / det, object, mesh.prim_ids[leaf], leaf);
}

inline void refresh_best(PacketState& s) {
    float ts[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) ts[lane] = lane < s.count ? s.hits[lane].t : __builtin_inff();
    s.best_t = load(ts);
}

// Hands the lanes to the scalar code, one ray at a time (exactly the single-ray path).
inline void intersect_instance_lanes(PacketState& s, uint32_t id, VM lanes) {
    RAYCAST_DCHECK((bits(lanes) >> s.count) == 0);
    for (unsigned b = bits(lanes); b; b &= b - 1) {
        const unsigned lane = lowest_lane(b);
        intersect_instance(*s.view.scene, id, s.rays[lane], s.t_min, s.hits[lane]);
    }
    refresh_best(s);
}

inline void intersect_mesh_packet(PacketState& s, const PacketRays& r, const WatertightPacket& w,
                                  const PacketMeshView& mesh, uint32_t object) {
    if (mesh.node_count == 0) return;
    traverse_packet(mesh.nodes, r, s.t_min_v, s.best_t, [&](uint32_t first, uint32_t count, VM) {
        for (uint32_t i = first; i < first + count; ++i)
            intersect_triangle_packet(s, w, r.live, mesh, i, object);
    });
}

// Moves the packet into an instance's object space as to_object_space does, operation for
// operation.
inline PacketRays transform_packet(const PacketRays& r, const Mat4& m) {
    PacketRays o;
    o.ox = splat(m.m[0][0]) * r.ox + splat(m.m[0][1]) * r.oy + splat(m.m[0][2]) * r.oz + splat(m.m[0][3]);
    o.oy = splat(m.m[1][0]) * r.ox + splat(m.m[1][1]) * r.oy + splat(m.m[1][2]) * r.oz + splat(m.m[1][3]);
    o.oz = splat(m.m[2][0]) * r.ox + splat(m.m[2][1]) * r.oy + splat(m.m[2][2]) * r.oz + splat(m.m[2][3]);
    o.dx = splat(m.m[0][0]) * r.dx + splat(m.m[0][1]) * r.dy + splat(m.m[0][2]) * r.dz;
    o.dy = splat(m.m[1][0]) * r.dx + splat(m.m[1][1]) * r.dy + splat(m.m[1][2]) * r.dz;
    o.dz = splat(m.m[2][0]) * r.dx + splat(m.m[2][1]) * r.dy + splat(m.m[2][2]) * r.dz;
    o.live = r.live;
    prepare_inverses(o);
    return o;
}

inline void trace_packet(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    // Dead lanes copy lane 0, and the live mask is (1 << count) - 1.
    RAYCAST_DCHECK(count >= 1 && count <= kLanes);
    PacketState s{view, rays, hits, count, t_min, splat(t_min), splat(0.0f)};
    // Structure of arrays; dead lanes repeat lane 0 so that they hold no garbage.
    float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    for (int lane = 0; lane < kLanes; ++lane) {
        const Ray& ray = rays[lane < count ? lane : 0];
        ox[lane] = ray.origin.x;
        oy[lane] = ray.origin.y;
        oz[lane] = ray.origin.z;
        dx[lane] = ray.direction.x;
        dy[lane] = ray.direction.y;
        dz[lane] = ray.direction.z;
    }
    PacketRays r;
    r.ox = load(ox);
    r.oy = load(oy);
    r.oz = load(oz);
    r.dx = load(dx);
    r.dy = load(dy);
    r.dz = load(dz);
    r.live = mask_from_bits((1u << count) - 1);
    prepare_inverses(r);
    refresh_best(s);

    // Planes are unbounded and few: the scalar code tests them, as the single-ray path does.
    for (uint32_t i = 0; i < view.plane_count; ++i)
        for (int lane = 0; lane < count; ++lane)
            intersect_instance(*view.scene, view.plane_instances[i], rays[lane], t_min, hits[lane]);
    if (view.plane_count > 0) refresh_best(s);
    if (view.instance_node_count == 0) return;

    bool have_world_watertight = false;
    WatertightPacket world_watertight;
    traverse_packet(view.instance_nodes, r, s.t_min_v, s.best_t, [&](uint32_t first, uint32_t n, VM lanes) {
        for (uint32_t i = first; i < first + n; ++i) {
            const uint32_t id = view.instance_ids[i];
            const Instance& instance = view.instances[id];
            if (instance.kind != ShapeKind::Mesh) {
                intersect_instance_lanes(s, id, lanes);
                continue;
            }
            const PacketMeshView& mesh = view.meshes[instance.shape];
            if (instance.transform == kNoTransformIndex) {
                if (!have_world_watertight) {
                    world_watertight = make_watertight_packet(r);
                    have_world_watertight = true;
                }
                if (world_watertight.uniform)
                    intersect_mesh_packet(s, r, world_watertight, mesh, id);
                else
                    intersect_instance_lanes(s, id, lanes);
            } else {
                const PacketRays local = transform_packet(r, view.object_from_world[instance.transform]);
                const WatertightPacket w = make_watertight_packet(local);
                if (w.uniform)
                    intersect_mesh_packet(s, local, w, mesh, id);
                else
                    intersect_instance_lanes(s, id, lanes);
            }
        }
    });
}
