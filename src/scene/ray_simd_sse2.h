// SIMD wrapper of the single-ray kernel, SSE2 (every x86-64 CPU): 8 lanes as two 4-wide
// registers. SSE2 has no variable shuffle, so table lookups go through memory. Included inside a
// kernel's namespace after the packet kernel's 4-lane wrapper (no include guard, no includes;
// <emmintrin.h> comes first in the .cpp): see packet_view.h.
struct F8 {
    __m128 lo, hi;
};
struct M8 {
    __m128 lo, hi;  // all ones in a true lane
};
struct I8 {
    unsigned char index[8];
};
inline F8 load8(const float* p) { return {_mm_loadu_ps(p), _mm_loadu_ps(p + 4)}; }
inline F8 splat8(float x) { return {_mm_set1_ps(x), _mm_set1_ps(x)}; }

// divide3: the SSE wrapper's (packet_simd_sse2.h).
#define RAYCAST_F8_OP(op, fn) \
    inline F8 operator op(F8 a, F8 b) { return {fn(a.lo, b.lo), fn(a.hi, b.hi)}; }
RAYCAST_F8_OP(+, _mm_add_ps)
RAYCAST_F8_OP(-, _mm_sub_ps)
RAYCAST_F8_OP(*, _mm_mul_ps)
RAYCAST_F8_OP(/, _mm_div_ps)
#undef RAYCAST_F8_OP
#define RAYCAST_M8_CMP(op, fn) \
    inline M8 operator op(F8 a, F8 b) { return {fn(a.lo, b.lo), fn(a.hi, b.hi)}; }
RAYCAST_M8_CMP(<, _mm_cmplt_ps)
RAYCAST_M8_CMP(<=, _mm_cmple_ps)
RAYCAST_M8_CMP(>, _mm_cmpgt_ps)
RAYCAST_M8_CMP(!=, _mm_cmpneq_ps)
#undef RAYCAST_M8_CMP
inline F8 vmin(F8 a, F8 b) { return {_mm_min_ps(a.lo, b.lo), _mm_min_ps(a.hi, b.hi)}; }
inline F8 vmax(F8 a, F8 b) { return {_mm_max_ps(a.lo, b.lo), _mm_max_ps(a.hi, b.hi)}; }
inline F8 vabs(F8 a) {
    const __m128 sign = _mm_set1_ps(-0.0f);
    return {_mm_andnot_ps(sign, a.lo), _mm_andnot_ps(sign, a.hi)};
}
inline M8 operator&(M8 a, M8 b) { return {_mm_and_ps(a.lo, b.lo), _mm_and_ps(a.hi, b.hi)}; }
inline M8 operator|(M8 a, M8 b) { return {_mm_or_ps(a.lo, b.lo), _mm_or_ps(a.hi, b.hi)}; }
inline M8 andnot(M8 a, M8 b) { return {_mm_andnot_ps(b.lo, a.lo), _mm_andnot_ps(b.hi, a.hi)}; }
inline unsigned bits(M8 a) {
    return static_cast<unsigned>(_mm_movemask_ps(a.lo)) | static_cast<unsigned>(_mm_movemask_ps(a.hi)) << 4;
}
inline void store(float* p, F8 a) {
    _mm_storeu_ps(p, a.lo);
    _mm_storeu_ps(p + 4, a.hi);
}
inline M8 first_lanes(uint32_t n) {
    const __m128i count = _mm_set1_epi32(static_cast<int>(n));
    return {_mm_castsi128_ps(_mm_cmpgt_epi32(count, _mm_setr_epi32(0, 1, 2, 3))),
            _mm_castsi128_ps(_mm_cmpgt_epi32(count, _mm_setr_epi32(4, 5, 6, 7)))};
}
inline F8 keep(M8 m, F8 a) { return {_mm_and_ps(m.lo, a.lo), _mm_and_ps(m.hi, a.hi)}; }
inline I8 load_bytes(const unsigned char* p) {
    I8 r;
    for (int i = 0; i < 8; ++i) r.index[i] = p[i];
    return r;
}
inline F8 lookup(F8 table, I8 index) {
    alignas(16) float t[8], r[8];
    store(t, table);
    for (int i = 0; i < 8; ++i) r[i] = t[index.index[i] & 7];
    return load8(r);
}
inline F8 lookup(F8 low, F8 high, I8 index) {
    alignas(16) float t[16], r[8];
    store(t, low);
    store(t + 8, high);
    for (int i = 0; i < 8; ++i) r[i] = t[index.index[i] & 15];
    return load8(r);
}

// The node test's width: 8 children as two registers, 4 as one (the packet kernel's wrapper,
// packet_simd_sse2.h, included first).
template <int kWidth>
struct NodeLanes;
template <>
struct NodeLanes<8> {
    using F = F8;
    static F load(const float* p) { return {_mm_load_ps(p), _mm_load_ps(p + 4)}; }
    static F broadcast(float x) { return splat8(x); }
};
template <>
struct NodeLanes<4> {
    using F = VF;
    static F load(const float* p) { return {_mm_load_ps(p)}; }
    static F broadcast(float x) { return splat(x); }
};
using NodeF = NodeLanes<kWideBvhWidth>::F;
inline NodeF load_node(const float* p) { return NodeLanes<kWideBvhWidth>::load(p); }
inline NodeF splat_node(float x) { return NodeLanes<kWideBvhWidth>::broadcast(x); }

// Node lanes ordered by their bits read as signed 32-bit integers (see hit_children for when that
// order is the floats' own): the larger and smaller of each pair, and where a <= b. SSE2 has no
// 32-bit integer max or min (SSE4.1 has), so each is a compare and a select.
inline __m128 greater_by_bits(__m128 a, __m128 b) {
    return _mm_castsi128_ps(_mm_cmpgt_epi32(_mm_castps_si128(a), _mm_castps_si128(b)));
}
inline __m128 pick(__m128 mask, __m128 a, __m128 b) {
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}
inline __m128 max_by_bits(__m128 a, __m128 b) { return pick(greater_by_bits(a, b), a, b); }
inline __m128 min_by_bits(__m128 a, __m128 b) { return pick(greater_by_bits(a, b), b, a); }
inline unsigned not_greater_bits(__m128 a, __m128 b) {
    return ~static_cast<unsigned>(_mm_movemask_ps(greater_by_bits(a, b))) & 0xfu;
}
inline F8 max_by_bits(F8 a, F8 b) { return {max_by_bits(a.lo, b.lo), max_by_bits(a.hi, b.hi)}; }
inline F8 min_by_bits(F8 a, F8 b) { return {min_by_bits(a.lo, b.lo), min_by_bits(a.hi, b.hi)}; }
inline unsigned not_greater_by_bits(F8 a, F8 b) {
    return not_greater_bits(a.lo, b.lo) | not_greater_bits(a.hi, b.hi) << 4;
}
inline VF max_by_bits(VF a, VF b) { return {max_by_bits(a.v, b.v)}; }
inline VF min_by_bits(VF a, VF b) { return {min_by_bits(a.v, b.v)}; }
inline unsigned not_greater_by_bits(VF a, VF b) { return not_greater_bits(a.v, b.v); }
