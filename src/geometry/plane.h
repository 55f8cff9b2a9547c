// The infinite plane n·P = offset (the course's "ax + by + cz = d"). The normal is kept as given:
// scaling it would change what `offset` means.
#pragma once

#include "math/ray.h"

namespace raycast {

struct Plane {
    Vec3f normal{0, 1, 0};
    float offset = 0;
};

/// t where the ray meets the plane, if t > t_min; rays parallel to the plane miss.
inline bool intersect_plane(const Plane& plane, const Ray& ray, float t_min, float& t_hit) {
    const float denominator = dot(plane.normal, ray.direction);
    if (denominator == 0) return false;
    const float t = (plane.offset - dot(plane.normal, ray.origin)) / denominator;
    if (!(t > t_min)) return false;
    t_hit = t;
    return true;
}

}  // namespace raycast
