// SIMD wrapper of the single-ray kernel, AVX2: the packet kernel's 8-lane wrapper
// (packet_simd_avx2.h, included first) and table lookups with vpermps. Included inside a
// kernel's namespace (no include guard, no includes; <immintrin.h> comes first in the .cpp): see
// packet_view.h.
using F8 = VF;
using M8 = VM;
struct I8 {
    __m256i v;
};
inline F8 load8(const float* p) { return load(p); }
inline F8 splat8(float x) { return splat(x); }

using sse::divide3;  // the SSE wrapper's (packet_simd_sse2.h)
// Lanes [0, n) true (n <= 8): eight of sixteen words, eight true then eight false.
alignas(64) constexpr int32_t kFirstLanesWindow[16] = {-1, -1, -1, -1, -1, -1, -1, -1, 0, 0, 0, 0, 0, 0, 0, 0};
inline M8 first_lanes(uint32_t n) { return {_mm256_loadu_ps(reinterpret_cast<const float*>(kFirstLanesWindow + 8 - n))}; }
// a where m is true, else +0.0.
inline F8 keep(M8 m, F8 a) { return {_mm256_and_ps(m.v, a.v)}; }
// Eight bytes, each widened to a lane.
inline I8 load_bytes(const unsigned char* p) {
    return {_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)))};
}
// table[index[i] mod 8] in lane i.
inline F8 lookup(F8 table, I8 index) { return {_mm256_permutevar8x32_ps(table.v, index.v)}; }
// (low, high)[index[i] mod 16] in lane i: bit 3 of the index picks the register. With AVX-512VL
// (ray_avx512.cpp) one two-table permute; with AVX2 two permutes and a blend.
inline F8 lookup(F8 low, F8 high, I8 index) {
#ifdef __AVX512VL__
    return {_mm256_permutex2var_ps(low.v, index.v, high.v)};
#else
    const __m256 from_high = _mm256_castsi256_ps(_mm256_slli_epi32(index.v, 28));
    return {_mm256_blendv_ps(_mm256_permutevar8x32_ps(low.v, index.v), _mm256_permutevar8x32_ps(high.v, index.v),
                             from_high)};
#endif
}

// The node test's width: one register per bound of a node's children (nodes are 64-byte
// aligned): AVX for 8 children, the SSE2 wrapper (namespace sse) for 4.
template <int kWidth>
struct NodeLanes;
template <>
struct NodeLanes<8> {
    using F = F8;
    static F load(const float* p) { return {_mm256_load_ps(p)}; }
    static F broadcast(float x) { return splat8(x); }
};
template <>
struct NodeLanes<4> {
    using F = sse::VF;
    static F load(const float* p) { return {_mm_load_ps(p)}; }
    static F broadcast(float x) { return sse::splat(x); }
};
using NodeF = NodeLanes<kWideBvhWidth>::F;
inline NodeF load_node(const float* p) { return NodeLanes<kWideBvhWidth>::load(p); }
inline NodeF splat_node(float x) { return NodeLanes<kWideBvhWidth>::broadcast(x); }

// Node lanes ordered by their bits read as signed 32-bit integers (see hit_children for when that
// order is the floats' own): the larger and smaller of each pair, and where a <= b.
inline F8 max_by_bits(F8 a, F8 b) {
    return {_mm256_castsi256_ps(_mm256_max_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v)))};
}
inline F8 min_by_bits(F8 a, F8 b) {
    return {_mm256_castsi256_ps(_mm256_min_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v)))};
}
inline unsigned not_greater_by_bits(F8 a, F8 b) {
    const __m256i greater = _mm256_cmpgt_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v));
    return ~static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(greater))) & 0xffu;
}
inline sse::VF max_by_bits(sse::VF a, sse::VF b) {
    return {_mm_castsi128_ps(_mm_max_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
}
inline sse::VF min_by_bits(sse::VF a, sse::VF b) {
    return {_mm_castsi128_ps(_mm_min_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
}
inline unsigned not_greater_by_bits(sse::VF a, sse::VF b) {
    const __m128i greater = _mm_cmpgt_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v));
    return ~static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(greater))) & 0xfu;
}
