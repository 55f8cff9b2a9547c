// SIMD wrapper, portable C++: 4 lanes in plain arrays. Included inside a kernel's namespace
// (no include guard, no includes): see packet_view.h.
constexpr int kLanes = 4;
struct VF {
    float v[kLanes];
};
struct VM {
    unsigned bits;
};
inline VF splat(float x) { return {{x, x, x, x}}; }
inline VF load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline void store(float* p, VF a) {
    for (int i = 0; i < kLanes; ++i) p[i] = a.v[i];
}
#define RAYCAST_LANEWISE(op)                              \
    inline VF operator op(VF a, VF b) {                   \
        VF r;                                             \
        for (int i = 0; i < kLanes; ++i) r.v[i] = a.v[i] op b.v[i]; \
        return r;                                         \
    }
RAYCAST_LANEWISE(+)
RAYCAST_LANEWISE(-)
RAYCAST_LANEWISE(*)
RAYCAST_LANEWISE(/)
#undef RAYCAST_LANEWISE
#define RAYCAST_COMPARE(op)                                            \
    inline VM operator op(VF a, VF b) {                                \
        unsigned m = 0;                                                \
        for (int i = 0; i < kLanes; ++i) m |= (a.v[i] op b.v[i]) ? 1u << i : 0u; \
        return {m};                                                    \
    }
RAYCAST_COMPARE(<)
RAYCAST_COMPARE(<=)
RAYCAST_COMPARE(>)
RAYCAST_COMPARE(==)
RAYCAST_COMPARE(!=)
#undef RAYCAST_COMPARE
inline VF vmin(VF a, VF b) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = a.v[i] < b.v[i] ? a.v[i] : b.v[i];
    return r;
}
inline VF vmax(VF a, VF b) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = a.v[i] > b.v[i] ? a.v[i] : b.v[i];
    return r;
}
inline VF vabs(VF a) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = a.v[i] < 0 ? -a.v[i] : a.v[i];
    return r;
}
inline VM operator&(VM a, VM b) { return {a.bits & b.bits}; }
inline VM operator|(VM a, VM b) { return {a.bits | b.bits}; }
inline VM andnot(VM a, VM b) { return {a.bits & ~b.bits}; }
inline bool any(VM a) { return a.bits != 0; }
inline unsigned bits(VM a) { return a.bits; }
inline VM mask_from_bits(unsigned b) { return {b & ((1u << kLanes) - 1)}; }
inline VF select(VM m, VF a, VF b) {
    VF r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = (m.bits >> i) & 1 ? a.v[i] : b.v[i];
    return r;
}
