// SIMD wrapper, SSE2 (every x86-64 CPU): 4 lanes. Included inside a kernel's namespace (no
// include guard, no includes; <emmintrin.h> comes first in the .cpp): see packet_view.h.
constexpr int kLanes = 4;
struct VF {
    __m128 v;
};
struct VM {
    __m128 v;  // all ones in a true lane
};
inline VF splat(float x) { return {_mm_set1_ps(x)}; }
inline VF load(const float* p) { return {_mm_loadu_ps(p)}; }
inline void store(float* p, VF a) { _mm_storeu_ps(p, a.v); }
// Lane i < count takes first[i * stride], the others first[0] (a field of an array of structs:
// read in place, for a store of the struct moments ago forwards to a load of the same size, and
// not to a vector load of a copy written field by field).
inline VF load_strided(const float* first, int stride, int count) {
    auto at = [&](int lane) { return first[lane < count ? lane * stride : 0]; };
    return {_mm_setr_ps(at(0), at(1), at(2), at(3))};
}
// Lane i of out[f] is first[6 i + f] (f < 6) for i < count, lane 0's for the others: the six
// fields of an array of six-float structs (rays), each field as load_strided reads it.
inline void load_six_fields(const float* first, int count, VF* out) {
    for (int f = 0; f < 6; ++f) out[f] = load_strided(first + f, 6, count);
}
inline VF operator+(VF a, VF b) { return {_mm_add_ps(a.v, b.v)}; }
inline VF operator-(VF a, VF b) { return {_mm_sub_ps(a.v, b.v)}; }
inline VF operator*(VF a, VF b) { return {_mm_mul_ps(a.v, b.v)}; }
inline VF operator/(VF a, VF b) { return {_mm_div_ps(a.v, b.v)}; }
inline VM operator<(VF a, VF b) { return {_mm_cmplt_ps(a.v, b.v)}; }
inline VM operator<=(VF a, VF b) { return {_mm_cmple_ps(a.v, b.v)}; }
inline VM operator>(VF a, VF b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
inline VM operator==(VF a, VF b) { return {_mm_cmpeq_ps(a.v, b.v)}; }
inline VM operator!=(VF a, VF b) { return {_mm_cmpneq_ps(a.v, b.v)}; }
inline VF vmin(VF a, VF b) { return {_mm_min_ps(a.v, b.v)}; }
inline VF vmax(VF a, VF b) { return {_mm_max_ps(a.v, b.v)}; }
inline VF vabs(VF a) { return {_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)}; }
inline VM operator&(VM a, VM b) { return {_mm_and_ps(a.v, b.v)}; }
inline VM operator|(VM a, VM b) { return {_mm_or_ps(a.v, b.v)}; }
inline VM andnot(VM a, VM b) { return {_mm_andnot_ps(b.v, a.v)}; }
inline unsigned bits(VM a) { return static_cast<unsigned>(_mm_movemask_ps(a.v)); }
inline bool any(VM a) { return bits(a) != 0; }
inline unsigned sign_bits(VF a) { return static_cast<unsigned>(_mm_movemask_ps(a.v)); }
inline VM mask_from_bits(unsigned b) {
    const __m128i lane_bits = _mm_set_epi32(8, 4, 2, 1);
    const __m128i selected = _mm_and_si128(_mm_set1_epi32(static_cast<int>(b)), lane_bits);
    return {_mm_castsi128_ps(_mm_cmpeq_epi32(selected, lane_bits))};
}
inline VF select(VM m, VF a, VF b) { return {_mm_or_ps(_mm_and_ps(m.v, a.v), _mm_andnot_ps(m.v, b.v))}; }
inline VF vsqrt(VF a) { return {_mm_sqrt_ps(a.v)}; }
// |magnitude| with the sign of `sign`, as std::copysign.
inline VF vcopysign(VF magnitude, VF sign) {
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    return {_mm_or_ps(_mm_andnot_ps(sign_bit, magnitude.v), _mm_and_ps(sign_bit, sign.v))};
}

// (a[i] / b[i]) for i < 3, as one SSE division: three scalar ones in a row would add their
// latencies to the time before a ray's first test (the single-ray kernel's set-up; its SSE2
// and AVX2 wrappers both take it from here).
inline void divide3(const float* a, const float* b, float* q) {
    const __m128 r = _mm_div_ps(_mm_setr_ps(a[0], a[1], a[2], 1.0f), _mm_setr_ps(b[0], b[1], b[2], 1.0f));
    q[0] = _mm_cvtss_f32(r);
    q[1] = _mm_cvtss_f32(_mm_shuffle_ps(r, r, 1));
    q[2] = _mm_cvtss_f32(_mm_shuffle_ps(r, r, 2));
}
