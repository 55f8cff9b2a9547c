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

// bvh.h's cull_distance.
inline float cull_distance_scalar(float t_best) { return t_best + scalar_abs(t_best) * (1.0f / 1024); }

inline unsigned lowest_bit(unsigned b) { return static_cast<unsigned>(__builtin_ctz(b)); }

// make_watertight_ray's axes (geometry/triangle.h): kz where |direction| is largest, and kx, ky
// the next two, swapped when the direction points down kz, which keeps the winding.
struct WatertightAxes {
    int kx, ky, kz;
};

inline WatertightAxes watertight_axes(float dx, float dy, float dz) {
    const float ax = scalar_abs(dx), ay = scalar_abs(dy), az = scalar_abs(dz);
    const int kz = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    const float d[3] = {dx, dy, dz};
    if (d[kz] < 0) {
        const int swap = kx;
        kx = ky;
        ky = swap;
    }
    return {kx, ky, kz};
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
