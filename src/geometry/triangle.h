// Ray-triangle intersection with the watertight test of Woop, Benthin and Wald, "Watertight
// Ray/Triangle Intersection" (JCGT 2013). The triangle is sheared into a space where the ray is
// the +z axis, and the three 2D edge functions are evaluated from vertex coordinates that every
// triangle sharing the vertex computes identically, so a ray through a shared edge or vertex
// never slips between neighbours.
#pragma once

#include <utility>

#include "math/ray.h"

namespace raycast {

/// A ray prepared for the watertight test: the axis permutation and the shear constants.
struct WatertightRay {
    Vec3f origin;
    int kx = 0, ky = 1, kz = 2;  ///< kz: the axis where |direction| is largest
    float sx = 0, sy = 0, sz = 1;
};

inline WatertightRay make_watertight_ray(const Ray& ray) {
    WatertightRay w;
    w.origin = ray.origin;
    const Vec3f d = ray.direction;
    w.kz = max_axis(abs(d));
    w.kx = w.kz == 2 ? 0 : w.kz + 1;
    w.ky = w.kx == 2 ? 0 : w.kx + 1;
    // Swapping x and y keeps the winding, and so the sign of the edge functions, the same.
    if (d[w.kz] < 0) std::swap(w.kx, w.ky);
    w.sx = d[w.kx] / d[w.kz];
    w.sy = d[w.ky] / d[w.kz];
    w.sz = 1.0f / d[w.kz];
    return w;
}

/// Where a ray meets a triangle: t and the barycentric weights of p1 (u) and p2 (v).
struct TriangleHit {
    float t, u, v;
};

/// True if the ray meets triangle (p0, p1, p2) at some t > t_min. Either winding is hit.
/// A degenerate triangle (zero area seen along the ray) is never hit.
inline bool intersect_triangle(const WatertightRay& ray, Vec3f p0, Vec3f p1, Vec3f p2, float t_min,
                               TriangleHit& hit) {
    const Vec3f a = p0 - ray.origin, b = p1 - ray.origin, c = p2 - ray.origin;
    const float ax = a[ray.kx] - ray.sx * a[ray.kz], ay = a[ray.ky] - ray.sy * a[ray.kz];
    const float bx = b[ray.kx] - ray.sx * b[ray.kz], by = b[ray.ky] - ray.sy * b[ray.kz];
    const float cx = c[ray.kx] - ray.sx * c[ray.kz], cy = c[ray.ky] - ray.sy * c[ray.kz];
    // Edge functions: u0 belongs to the edge opposite p0, and so on.
    const float u0 = cx * by - cy * bx;
    const float u1 = ax * cy - ay * cx;
    const float u2 = bx * ay - by * ax;
    if ((u0 < 0 || u1 < 0 || u2 < 0) && (u0 > 0 || u1 > 0 || u2 > 0)) return false;
    const float det = u0 + u1 + u2;
    if (det == 0) return false;
    const float az = ray.sz * a[ray.kz], bz = ray.sz * b[ray.kz], cz = ray.sz * c[ray.kz];
    const float t = (u0 * az + u1 * bz + u2 * cz) / det;
    if (!(t > t_min)) return false;
    hit = {t, u1 / det, u2 / det};
    return true;
}

/// Whether the triangle has no area in floats: its vertices are on one line (or coincide). Such a
/// triangle is never hit, because the scene keeps it out of its BVHs (build_scene.cpp); the test
/// above alone does not promise that: when the triangle's line passes through the ray's origin,
/// rounding in the shear can leave two edge functions 0 and the third not, a "hit" at a vertex
/// that the ray does not meet.
inline bool is_degenerate_triangle(Vec3f p0, Vec3f p1, Vec3f p2) { return is_zero(cross(p1 - p0, p2 - p0)); }

/// The geometric normal normalize((p1 − p0) × (p2 − p0)): counter-clockwise faces face you.
/// normalize_any_length: a triangle a few billion across (cross product 1e19, squared past float)
/// or a millionth of a millionth (squared below it) still has a unit normal, not zero.
inline Vec3f triangle_normal(Vec3f p0, Vec3f p1, Vec3f p2) { return normalize_any_length(cross(p1 - p0, p2 - p0)); }

}  // namespace raycast
