// Scalar pieces that the single-ray kernel (ray_kernel.inl) and the packet kernel
// (packet_kernel.inl) share: each includes this inside its own anonymous namespace, so every
// instruction set gets its own copy (no include guard, no includes; see packet_view.h for why).

#include "geometry/triangle_group_layout.inl"

constexpr float kBoxWiden = 4 * 5.96046448e-08f;  // as in bvh.h's intersect_box
constexpr float kTiny = 1e-30f;
// A wide node pushes at most kWideBvhWidth - 1 children, and the tree is at most kMaxBvhDepth deep.
constexpr int kWideStackSize = (kWideBvhWidth - 1) * kMaxBvhDepth + 1;

inline float scalar_abs(float x) { return x < 0 ? -x : x; }

// What bvh.h's safe_inverse divides 1 by: components smaller than 1e-30 (zero among them)
// become ±1e-30 with their sign, so that no 0·∞ makes a NaN.
inline float safe_divisor(float d) {
    return scalar_abs(d) < kTiny ? (__builtin_signbit(d) ? -kTiny : kTiny) : d;
}

// Whether 1 / safe_divisor(d) < 0, read off d without the division, so that a box test's choice
// of near bounds need not wait for it: the sign bit (safe_divisor keeps the sign, -0 included),
// but for NaN and -inf, whose inverses (NaN and -0) are not below 0.
inline bool inverse_is_negative(float d) { return __builtin_signbit(d) && d > -__builtin_inff(); }

// How a slab test stays conservative (never misses a box the ray meets): a computed distance
// fl(fl(b - o)·fl(1/d)) is within three roundings of the true (b - o)/d, a relative error below
// 2^-22. With a negative t_min, the entry and exit are widened by more than that (|x|·kBoxWiden,
// as intersect_box does). With t_min >= 0 (every ray a renderer traces) the widening moves into
// the ray's constants instead, off the node test's critical path: near bounds are multiplied by
// an inverse 8 ulps (2^-20) smaller in magnitude and far bounds by one 8 ulps larger, which moves
// a positive entry nearer and a positive exit farther by more than the rounding (a fourth one
// included, for the scaled inverse) could move them. A negative near distance only gets nearer to
// 0 but stays negative (the sign of a product is exact), so the entry max(t_min, ...) is what the
// exact test gives; a negative far distance means the box is behind t_min either way.
constexpr float kInverseShrink = 1.0f - 8 * 5.96046448e-08f, kInverseGrow = 1.0f + 8 * 5.96046448e-08f;

// bvh.h's cull_distance and leaf_floor.
inline float cull_distance_scalar(float t_best) { return t_best + scalar_abs(t_best) * (1.0f / 1024); }
inline float leaf_floor_scalar(float leaf_entry) { return leaf_entry - scalar_abs(leaf_entry) * (1.0f / 2048); }

inline unsigned lowest_bit(unsigned b) { return static_cast<unsigned>(__builtin_ctz(b)); }

// make_watertight_ray's axes (geometry/triangle.h): kz where |direction| is largest, and kx, ky
// the next two, swapped when the direction points down kz, which keeps the winding.
struct WatertightAxes {
    int kx, ky, kz;
};

// Computed without a branch (the comparisons' bits index constant tables): an occlusion ray's
// direction is as good as random, and a branch on it mispredicts about every other ray.
inline WatertightAxes watertight_axes(float dx, float dy, float dz) {
    const float ax = scalar_abs(dx), ay = scalar_abs(dy), az = scalar_abs(dz);
    // kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2), for each of the 8 outcomes.
    const unsigned outcome = static_cast<unsigned>(ax >= ay) | static_cast<unsigned>(ax >= az) << 1 |
                             static_cast<unsigned>(ay >= az) << 2;
    const unsigned kz = (0x192Au >> (2 * outcome)) & 3u;
    const unsigned kx = (0x09u >> (2 * kz)) & 3u;  // kz + 1 mod 3
    const unsigned ky = (0x12u >> (2 * kz)) & 3u;  // kz + 2 mod 3
    const unsigned negative = static_cast<unsigned>(dx < 0) | static_cast<unsigned>(dy < 0) << 1 |
                              static_cast<unsigned>(dz < 0) << 2;
    const unsigned swap = (0u - ((negative >> kz) & 1u)) & (kx ^ ky);  // d[kz] < 0: kx and ky swapped
    return {static_cast<int>(kx ^ swap), static_cast<int>(ky ^ swap), static_cast<int>(kz)};
}

// Group bytes, read as floats and ids (group planes are stored in an array of bytes).
inline float group_float(const unsigned char* p) {
    float x;
    __builtin_memcpy(&x, p, 4);
    return x;
}

inline uint32_t group_id(const unsigned char* group, uint32_t lane) {
    uint32_t id;
    __builtin_memcpy(&id, group + group_ids_offset(group[0], group[1]) + 4 * lane, 4);
    return id;
}
