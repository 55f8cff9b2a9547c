// SIMD wrapper, portable C++: 4 lanes in plain arrays. Included inside a kernel's namespace
// (no include guard, no includes): see packet_view.h. The operations are written for any width,
// so that the single-ray kernel's 8-lane wrapper (ray_simd_portable.h) shares them.
template <int N>
struct LanesF {
    float v[N];
};
template <int N>
struct LanesM {
    unsigned bits;
};
#define RAYCAST_LANEWISE(op)                                    \
    template <int N>                                            \
    inline LanesF<N> operator op(LanesF<N> a, LanesF<N> b) {    \
        LanesF<N> r;                                            \
        for (int i = 0; i < N; ++i) r.v[i] = a.v[i] op b.v[i];  \
        return r;                                               \
    }
RAYCAST_LANEWISE(+)
RAYCAST_LANEWISE(-)
RAYCAST_LANEWISE(*)
RAYCAST_LANEWISE(/)
#undef RAYCAST_LANEWISE
#define RAYCAST_COMPARE(op)                                                      \
    template <int N>                                                             \
    inline LanesM<N> operator op(LanesF<N> a, LanesF<N> b) {                     \
        unsigned m = 0;                                                          \
        for (int i = 0; i < N; ++i) m |= (a.v[i] op b.v[i]) ? 1u << i : 0u;     \
        return {m};                                                              \
    }
RAYCAST_COMPARE(<)
RAYCAST_COMPARE(<=)
RAYCAST_COMPARE(>)
RAYCAST_COMPARE(==)
RAYCAST_COMPARE(!=)
#undef RAYCAST_COMPARE
template <int N>
inline LanesF<N> vmin(LanesF<N> a, LanesF<N> b) {
    LanesF<N> r;
    for (int i = 0; i < N; ++i) r.v[i] = a.v[i] < b.v[i] ? a.v[i] : b.v[i];
    return r;
}
template <int N>
inline LanesF<N> vmax(LanesF<N> a, LanesF<N> b) {
    LanesF<N> r;
    for (int i = 0; i < N; ++i) r.v[i] = a.v[i] > b.v[i] ? a.v[i] : b.v[i];
    return r;
}
template <int N>
inline LanesF<N> vabs(LanesF<N> a) {
    LanesF<N> r;
    for (int i = 0; i < N; ++i) r.v[i] = a.v[i] < 0 ? -a.v[i] : a.v[i];
    return r;
}
template <int N>
inline void store(float* p, LanesF<N> a) {
    for (int i = 0; i < N; ++i) p[i] = a.v[i];
}
template <int N>
inline LanesM<N> operator&(LanesM<N> a, LanesM<N> b) { return {a.bits & b.bits}; }
template <int N>
inline LanesM<N> operator|(LanesM<N> a, LanesM<N> b) { return {a.bits | b.bits}; }
template <int N>
inline LanesM<N> andnot(LanesM<N> a, LanesM<N> b) { return {a.bits & ~b.bits}; }
template <int N>
inline bool any(LanesM<N> a) { return a.bits != 0; }
template <int N>
inline unsigned bits(LanesM<N> a) { return a.bits; }
template <int N>
inline LanesF<N> select(LanesM<N> m, LanesF<N> a, LanesF<N> b) {
    LanesF<N> r;
    for (int i = 0; i < N; ++i) r.v[i] = (m.bits >> i) & 1 ? a.v[i] : b.v[i];
    return r;
}

constexpr int kLanes = 4;
using VF = LanesF<kLanes>;
using VM = LanesM<kLanes>;
inline VF splat(float x) { return {{x, x, x, x}}; }
inline VF load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
// Lane i < count takes first[i * stride], the others first[0] (a field of an array of structs:
// read in place, for a store of the struct moments ago forwards to a load of the same size, and
// not to a vector load of a copy written field by field).
inline VF load_strided(const float* first, int stride, int count) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = first[i < count ? i * stride : 0];
    return r;
}
// Lane i of out[f] is first[6 i + f] (f < 6) for i < count, lane 0's for the others: the six
// fields of an array of six-float structs (rays), each field as load_strided reads it.
inline void load_six_fields(const float* first, int count, VF* out) {
    for (int f = 0; f < 6; ++f) out[f] = load_strided(first + f, 6, count);
}
inline VM mask_from_bits(unsigned b) { return {b & ((1u << kLanes) - 1)}; }
inline unsigned sign_bits(VF a) {
    unsigned m = 0;
    for (int i = 0; i < kLanes; ++i) m |= __builtin_signbit(a.v[i]) ? 1u << i : 0u;
    return m;
}
inline VF vsqrt(VF a) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = __builtin_sqrtf(a.v[i]);
    return r;
}
// |magnitude| with the sign of `sign`, as std::copysign.
inline VF vcopysign(VF magnitude, VF sign) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = __builtin_copysignf(magnitude.v[i], sign.v[i]);
    return r;
}
