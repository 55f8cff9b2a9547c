// Ray-sphere intersection. The ray direction need not be unit length (transformed rays are not),
// so the full quadratic a·t² + 2b·t + c is solved, in the numerically careful form of
// Haines et al., "Precision Improvements for Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7).
#pragma once

#include <cmath>

#include "math/ray.h"

namespace raycast {

struct Sphere {
    Vec3f center;
    float radius = 1;
};

/// √(a·b) for a, b >= 0: √a·√b where the product leaves float's range. A sphere tested in the
/// object space of a transform that shrinks or grows it by 1e10 has a = |d|² and b (about r²) both
/// near 1e20 or 1e-24, and the product overflowed (the sphere came out black) or vanished. Where it
/// does not, exactly the product's root, so that ordinary images keep their every bit. The packet
/// kernels' sphere test does the same (scene/packet_kernel.inl, sphere_hits).
inline float root_of_product(float a, float b) {
    const float product = a * b;
    if ((product < __builtin_inff() && product > 0) || b == 0 || a == 0) return std::sqrt(product);
    return std::sqrt(a) * std::sqrt(b);  // overflow, underflow, or NaN (which stays NaN)
}

/// The nearest root t of |o + t·d − c| = r with t > t_min, or false.
inline bool intersect_sphere(const Sphere& sphere, const Ray& ray, float t_min, float& t_hit) {
    const Vec3f f = ray.origin - sphere.center;
    const Vec3f d = ray.direction;
    const float a = dot(d, d);
    const float half_b = dot(f, d);
    const float c = dot(f, f) - sphere.radius * sphere.radius;
    // b² − a·c computed as a·(r² − |f − (b/a)·d|²): the subtraction of nearly equal squares that
    // ruins the textbook formula far from the sphere does not happen here.
    const Vec3f closest = f - d * (half_b / a);
    const float discriminant = sphere.radius * sphere.radius - dot(closest, closest);
    if (!(discriminant >= 0)) return false;
    const float q = -(half_b + std::copysign(root_of_product(a, discriminant), half_b));
    if (q == 0) return false;
    float t0 = q / a, t1 = c / q;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_min) {
        t_hit = t0;
        return true;
    }
    if (t1 > t_min) {
        t_hit = t1;
        return true;
    }
    return false;
}

}  // namespace raycast
