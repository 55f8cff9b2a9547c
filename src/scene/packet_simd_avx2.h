// SIMD wrapper, AVX2: 8 lanes. Included inside a kernel's namespace (no include guard, no
// includes; <immintrin.h> comes first in the .cpp): see packet_view.h.
constexpr int kLanes = 8;
struct VF {
    __m256 v;
};
struct VM {
    __m256 v;  // all ones in a true lane
};
inline VF splat(float x) { return {_mm256_set1_ps(x)}; }
inline VF load(const float* p) { return {_mm256_loadu_ps(p)}; }
inline void store(float* p, VF a) { _mm256_storeu_ps(p, a.v); }
// Lane i < count takes first[i * stride], the others first[0] (a field of an array of structs:
// read in place, for a store of the struct moments ago forwards to a load of the same size, and
// not to a vector load of a copy written field by field).
inline VF load_strided(const float* first, int stride, int count) {
    auto at = [&](int lane) { return first[lane < count ? lane * stride : 0]; };
    return {_mm256_setr_ps(at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7))};
}
// Lane i of out[f] is first[6 i + f] (f < 6) for i < count, lane 0's for the others: the six
// fields of an array of six-float structs (rays), each field as load_strided reads it.
inline void load_six_fields(const float* first, int count, VF* out) {
    for (int f = 0; f < 6; ++f) out[f] = load_strided(first + f, 6, count);
}
inline VF operator+(VF a, VF b) { return {_mm256_add_ps(a.v, b.v)}; }
inline VF operator-(VF a, VF b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline VF operator*(VF a, VF b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline VF operator/(VF a, VF b) { return {_mm256_div_ps(a.v, b.v)}; }
inline VM operator<(VF a, VF b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
inline VM operator<=(VF a, VF b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
inline VM operator>(VF a, VF b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
inline VM operator==(VF a, VF b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)}; }
inline VM operator!=(VF a, VF b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_NEQ_UQ)}; }
inline VF vmin(VF a, VF b) { return {_mm256_min_ps(a.v, b.v)}; }
inline VF vmax(VF a, VF b) { return {_mm256_max_ps(a.v, b.v)}; }
inline VF vabs(VF a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
inline VM operator&(VM a, VM b) { return {_mm256_and_ps(a.v, b.v)}; }
inline VM operator|(VM a, VM b) { return {_mm256_or_ps(a.v, b.v)}; }
inline VM andnot(VM a, VM b) { return {_mm256_andnot_ps(b.v, a.v)}; }
inline unsigned bits(VM a) { return static_cast<unsigned>(_mm256_movemask_ps(a.v)); }
inline bool any(VM a) { return bits(a) != 0; }
inline unsigned sign_bits(VF a) { return static_cast<unsigned>(_mm256_movemask_ps(a.v)); }
inline VM mask_from_bits(unsigned b) {
    const __m256i lane_bits = _mm256_set_epi32(128, 64, 32, 16, 8, 4, 2, 1);
    const __m256i selected = _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), lane_bits);
    return {_mm256_castsi256_ps(_mm256_cmpeq_epi32(selected, lane_bits))};
}
inline VF select(VM m, VF a, VF b) { return {_mm256_blendv_ps(b.v, a.v, m.v)}; }
inline VF vsqrt(VF a) { return {_mm256_sqrt_ps(a.v)}; }
// |magnitude| with the sign of `sign`, as std::copysign.
inline VF vcopysign(VF magnitude, VF sign) {
    const __m256 sign_bit = _mm256_set1_ps(-0.0f);
    return {_mm256_or_ps(_mm256_andnot_ps(sign_bit, magnitude.v), _mm256_and_ps(sign_bit, sign.v))};
}
inline float hmin(VF a) {
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(a.v), _mm256_extractf128_ps(a.v, 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
inline float hmax(VF a) {
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(a.v), _mm256_extractf128_ps(a.v, 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
