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
    const float q = -(half_b + std::copysign(std::sqrt(a * discriminant), half_b));
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
