// SIMD wrapper of the single-ray kernel, portable C++: 8 lanes in plain arrays, for CPUs with no
// kernel of their own, with the operations of the packet kernel's portable wrapper
// (packet_simd_portable.h, included first). Included inside a kernel's namespace (no include
// guard, no includes): see packet_view.h.
using F8 = LanesF<8>;
using M8 = LanesM<8>;
struct I8 {
    unsigned char index[8];
};
// By bytes: group planes are floats stored in an array of bytes.
inline F8 load8(const float* p) {
    F8 r;
    __builtin_memcpy(r.v, p, sizeof r.v);
    return r;
}
inline F8 splat8(float x) { return {{x, x, x, x, x, x, x, x}}; }

// (a[i] / b[i]) for i < 3 (one SIMD division in the other wrappers).
inline void divide3(const float* a, const float* b, float* q) {
    for (int i = 0; i < 3; ++i) q[i] = a[i] / b[i];
}
inline M8 first_lanes(uint32_t n) { return {n >= 8 ? 0xffu : (1u << n) - 1}; }
inline F8 keep(M8 m, F8 a) { return select(m, a, splat8(0.0f)); }
inline I8 load_bytes(const unsigned char* p) {
    I8 r;
    __builtin_memcpy(r.index, p, sizeof r.index);
    return r;
}
inline F8 lookup(F8 table, I8 index) {
    F8 r;
    for (int i = 0; i < 8; ++i) r.v[i] = table.v[index.index[i] & 7];
    return r;
}
inline F8 lookup(F8 low, F8 high, I8 index) {
    F8 r;
    for (int i = 0; i < 8; ++i) {
        const unsigned j = index.index[i] & 15u;
        r.v[i] = j < 8 ? low.v[j] : high.v[j - 8];
    }
    return r;
}

// The node test's width: one array per bound of a node's children.
using NodeF = LanesF<kWideBvhWidth>;
inline NodeF load_node(const float* p) {
    NodeF r;
    __builtin_memcpy(r.v, p, sizeof r.v);
    return r;
}
inline NodeF splat_node(float x) {
    NodeF r;
    for (float& lane : r.v) lane = x;
    return r;
}

// Node lanes ordered by their bits read as signed 32-bit integers (see hit_children for when that
// order is the floats' own): the larger and smaller of each pair, and where a <= b.
inline int32_t lane_bits(float x) {
    int32_t i;
    __builtin_memcpy(&i, &x, 4);
    return i;
}
inline NodeF max_by_bits(NodeF a, NodeF b) {
    NodeF r;
    for (int i = 0; i < kWideBvhWidth; ++i) r.v[i] = lane_bits(a.v[i]) > lane_bits(b.v[i]) ? a.v[i] : b.v[i];
    return r;
}
inline NodeF min_by_bits(NodeF a, NodeF b) {
    NodeF r;
    for (int i = 0; i < kWideBvhWidth; ++i) r.v[i] = lane_bits(a.v[i]) > lane_bits(b.v[i]) ? b.v[i] : a.v[i];
    return r;
}
inline unsigned not_greater_by_bits(NodeF a, NodeF b) {
    unsigned r = 0;
    for (int i = 0; i < kWideBvhWidth; ++i) r |= (lane_bits(a.v[i]) > lane_bits(b.v[i]) ? 0u : 1u) << i;
    return r;
}
