// 4x4 matrices for the scene's transforms. Row-major storage: m[row][col]; points are columns,
// so a matrix maps p to M·p and M = A·B applies B first.
#pragma once

#include "math/vec.h"

namespace raycast {

struct Mat4 {
    float m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    static Mat4 identity() { return Mat4{}; }
    static Mat4 translate(Vec3f offset);
    static Mat4 scale(Vec3f factors);
    /// Right-handed rotations (counter-clockwise seen from the axis tip), angles in degrees.
    static Mat4 rotate_x(float degrees);
    static Mat4 rotate_y(float degrees);
    static Mat4 rotate_z(float degrees);
    /// Rotation about an axis through the origin; the axis need not be unit length (not zero).
    static Mat4 rotate(Vec3f axis, float degrees);
    /// From 16 numbers listed row by row (MIT 6.837's `Matrix`).
    static Mat4 from_rows(const float values[16]);
    /// From 16 numbers listed column by column (the course's `Matrix4f`).
    static Mat4 from_columns(const float values[16]);

    bool operator==(const Mat4& other) const;
    bool is_identity() const { return *this == Mat4{}; }
};

Mat4 operator*(const Mat4& a, const Mat4& b);
Mat4 transpose(const Mat4& a);
/// The determinant, computed in double precision.
double determinant(const Mat4& a);
/// Inverse computed in double precision by cofactors; `ok` is false (and the result the identity)
/// when the matrix is singular or its inverse is not finite.
Mat4 inverse(const Mat4& a, bool* ok = nullptr);

/// M·(p, 1): moves, rotates and scales a point.
inline Vec3f transform_point(const Mat4& a, Vec3f p) {
    return {a.m[0][0] * p.x + a.m[0][1] * p.y + a.m[0][2] * p.z + a.m[0][3],
            a.m[1][0] * p.x + a.m[1][1] * p.y + a.m[1][2] * p.z + a.m[1][3],
            a.m[2][0] * p.x + a.m[2][1] * p.y + a.m[2][2] * p.z + a.m[2][3]};
}
/// M·(v, 0): rotates and scales a direction; no translation, no renormalisation.
inline Vec3f transform_vector(const Mat4& a, Vec3f v) {
    return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
            a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
            a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
/// Maps an object-space normal to world space given object_from_world (= M⁻¹): (M⁻¹)ᵀ·n,
/// normalised. This keeps normals perpendicular to surfaces under non-uniform scales.
inline Vec3f transform_normal(const Mat4& object_from_world, Vec3f n) {
    const Mat4& a = object_from_world;
    return normalize_any_length(Vec3f{a.m[0][0] * n.x + a.m[1][0] * n.y + a.m[2][0] * n.z,
                           a.m[0][1] * n.x + a.m[1][1] * n.y + a.m[2][1] * n.z,
                           a.m[0][2] * n.x + a.m[1][2] * n.y + a.m[2][2] * n.z});
}

}  // namespace raycast
