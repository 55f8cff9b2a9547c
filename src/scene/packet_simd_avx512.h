// SIMD wrapper, AVX-512 (AVX512F only): 16 lanes. Included inside a kernel's namespace (no
// include guard, no includes; <immintrin.h> comes first in the .cpp): see packet_view.h.
constexpr int kLanes = 16;
struct VF {
    __m512 v;
};
struct VM {
    __mmask16 m;
};
inline VF splat(float x) { return {_mm512_set1_ps(x)}; }
inline VF load(const float* p) { return {_mm512_loadu_ps(p)}; }
inline void store(float* p, VF a) { _mm512_storeu_ps(p, a.v); }
// Lane i < count takes first[i * stride], the others first[0] (a field of an array of structs:
// read in place, for a store of the struct moments ago forwards to a load of the same size, and
// not to a vector load of a copy written field by field).
inline VF load_strided(const float* first, int stride, int count) {
    auto at = [&](int lane) { return first[lane < count ? lane * stride : 0]; };
    return {_mm512_setr_ps(at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7), at(8), at(9), at(10), at(11),
                           at(12), at(13), at(14), at(15))};
}
// Lane i of out[f] is first[6 i + f] (f < 6) for i < count, lane 0's for the others: the six
// fields of an array of six-float structs (16 rays are 96 floats), transposed in registers: six
// loads (masked past the last struct, which suppresses their faults), then each field picked
// from the six with three two-register permutes. About a sixth of the instructions of six
// load_strided calls.
struct SixFieldTables {
    int index[6][3][16];     // field f's lanes in the permute of chunks 2p and 2p + 1
    unsigned from[6][3];     // the lanes that permute p fills
};
constexpr SixFieldTables make_six_field_tables() {
    SixFieldTables t{};
    for (int f = 0; f < 6; ++f)
        for (int i = 0; i < 16; ++i) {
            const int p = (6 * i + f) / 32;
            t.index[f][p][i] = 6 * i + f - 32 * p;
            t.from[f][p] |= 1u << i;
        }
    return t;
}
inline void load_six_fields(const float* first, int count, VF* out) {
    static constexpr SixFieldTables kTables = make_six_field_tables();
    const unsigned floats = 6u * static_cast<unsigned>(count);
    __m512 chunk[6];
    for (unsigned c = 0; c < 6; ++c) {
        const unsigned begin = 16 * c;
        const unsigned valid = floats >= begin + 16 ? 0xFFFFu : (floats > begin ? (1u << (floats - begin)) - 1 : 0u);
        chunk[c] = _mm512_maskz_loadu_ps(static_cast<__mmask16>(valid), first + begin);
    }
    const __mmask16 live = static_cast<__mmask16>((1u << count) - 1);
    for (int f = 0; f < 6; ++f) {
        auto pick = [&](int p) {
            const __m512i index = _mm512_loadu_si512(kTables.index[f][p]);
            return _mm512_permutex2var_ps(chunk[2 * p], index, chunk[2 * p + 1]);
        };
        __m512 v = pick(0);
        v = _mm512_mask_mov_ps(v, static_cast<__mmask16>(kTables.from[f][1]), pick(1));
        v = _mm512_mask_mov_ps(v, static_cast<__mmask16>(kTables.from[f][2]), pick(2));
        if (count < 16) v = _mm512_mask_mov_ps(_mm512_permutexvar_ps(_mm512_setzero_si512(), v), live, v);
        out[f].v = v;
    }
}
inline VF operator+(VF a, VF b) { return {_mm512_add_ps(a.v, b.v)}; }
inline VF operator-(VF a, VF b) { return {_mm512_sub_ps(a.v, b.v)}; }
inline VF operator*(VF a, VF b) { return {_mm512_mul_ps(a.v, b.v)}; }
inline VF operator/(VF a, VF b) { return {_mm512_div_ps(a.v, b.v)}; }
inline VM operator<(VF a, VF b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
inline VM operator<=(VF a, VF b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
inline VM operator>(VF a, VF b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
inline VM operator==(VF a, VF b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_EQ_OQ)}; }
inline VM operator!=(VF a, VF b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_NEQ_UQ)}; }
inline VF vmin(VF a, VF b) { return {_mm512_min_ps(a.v, b.v)}; }
inline VF vmax(VF a, VF b) { return {_mm512_max_ps(a.v, b.v)}; }
inline VF vabs(VF a) { return {_mm512_abs_ps(a.v)}; }
inline VM operator&(VM a, VM b) { return {static_cast<__mmask16>(a.m & b.m)}; }
inline VM operator|(VM a, VM b) { return {static_cast<__mmask16>(a.m | b.m)}; }
inline VM andnot(VM a, VM b) { return {static_cast<__mmask16>(a.m & ~b.m)}; }
inline unsigned bits(VM a) { return a.m; }
inline bool any(VM a) { return a.m != 0; }
inline unsigned sign_bits(VF a) {
    return _mm512_cmp_epi32_mask(_mm512_castps_si512(a.v), _mm512_setzero_si512(), _MM_CMPINT_LT);
}
inline VM mask_from_bits(unsigned b) { return {static_cast<__mmask16>(b)}; }
inline VF select(VM m, VF a, VF b) { return {_mm512_mask_blend_ps(m.m, b.v, a.v)}; }
inline VF vsqrt(VF a) { return {_mm512_sqrt_ps(a.v)}; }
// |magnitude| with the sign of `sign`, as std::copysign (integer logic: AVX512F has no float and/or).
inline VF vcopysign(VF magnitude, VF sign) {
    const __m512i sign_bit = _mm512_set1_epi32(static_cast<int>(0x80000000u));
    return {_mm512_castsi512_ps(_mm512_or_si512(_mm512_andnot_si512(sign_bit, _mm512_castps_si512(magnitude.v)),
                                                _mm512_and_si512(sign_bit, _mm512_castps_si512(sign.v))))};
}
inline float hmin(VF a) { return _mm512_reduce_min_ps(a.v); }
inline float hmax(VF a) { return _mm512_reduce_max_ps(a.v); }
