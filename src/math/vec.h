// Small fixed-size vectors: Vec2f, Vec3f and the operations a ray caster needs.
// Plain structs with public fields, so arrays of them are flat float data.
#pragma once

#include <cmath>

namespace raycast {

struct Vec2f {
    float x = 0, y = 0;
};

struct Vec3f {
    float x = 0, y = 0, z = 0;

    constexpr Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}

    /// Component by axis number 0, 1, 2 (x, y, z).
    constexpr float operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
    constexpr float& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
};

constexpr Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator*(float s, Vec3f a) { return {s * a.x, s * a.y, s * a.z}; }
constexpr Vec3f operator/(Vec3f a, float s) { return {a.x / s, a.y / s, a.z / s}; }
/// Component-wise product (colours, scales).
constexpr Vec3f operator*(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3f& operator+=(Vec3f& a, Vec3f b) { return a = a + b; }
constexpr bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
constexpr bool operator!=(Vec3f a, Vec3f b) { return !(a == b); }

constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
/// a / |a|; the zero vector stays zero rather than becoming NaN.
inline Vec3f normalize(Vec3f a) {
    const float len = length(a);
    return len > 0 ? a / len : a;
}
/// The largest of |a.x|, |a.y|, |a.z|, as std::fmax finds it (a NaN component is passed over
/// unless all are NaN). Written as comparisons because GCC calls fmaxf as a library function, and
/// every shaded hit needs this for its ray offset (render/shade.h).
inline float max_abs(Vec3f a) {
    const auto larger = [](float x, float y) { return x > y ? x : (y == y ? y : x); };  // x, y >= 0 or NaN
    return larger(std::fabs(a.x), larger(std::fabs(a.y), std::fabs(a.z)));
}
inline bool is_zero(Vec3f a) { return a.x == 0 && a.y == 0 && a.z == 0; }
/// Whether |a|² neither underflows nor overflows float: products with `a` are then safe.
inline bool has_ordinary_length(Vec3f a) {
    const float squared = a.x * a.x + a.y * a.y + a.z * a.z;
    return squared > 1e-30f && squared < 1e30f;
}
/// normalize() for vectors from a scene file, whose length may overflow (1e38) or underflow
/// (1e-30) when squared: those are first divided by their largest component. Vectors of ordinary
/// length give exactly normalize(a).
inline Vec3f normalize_any_length(Vec3f a) {
    if (has_ordinary_length(a)) return normalize(a);
    const float largest = std::fmax(std::fabs(a.x), std::fmax(std::fabs(a.y), std::fabs(a.z)));
    if (!(largest > 0) || !std::isfinite(largest)) return normalize(a);
    return normalize(a / largest);
}
/// Componentwise minimum and maximum. A NaN in `b` is ignored (the result is a's component), as
/// fmin/fmax do, which keeps a box grown by a NaN point valid. Written as comparisons rather than
/// std::fmin, which GCC calls as a library function: box growing is the BVH build's inner loop.
inline float min_ignoring_nan(float a, float b) { return b < a ? b : a; }
inline float max_ignoring_nan(float a, float b) { return b > a ? b : a; }
inline Vec3f min(Vec3f a, Vec3f b) {
    return {min_ignoring_nan(a.x, b.x), min_ignoring_nan(a.y, b.y), min_ignoring_nan(a.z, b.z)};
}
inline Vec3f max(Vec3f a, Vec3f b) {
    return {max_ignoring_nan(a.x, b.x), max_ignoring_nan(a.y, b.y), max_ignoring_nan(a.z, b.z)};
}
inline Vec3f abs(Vec3f a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline bool is_finite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
/// The axis (0, 1, 2) of the largest component.
constexpr int max_axis(Vec3f a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }

}  // namespace raycast
