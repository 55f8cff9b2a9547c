#include "render/shade.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace raycast {

Vec3f mirror_direction(Vec3f d, Vec3f n) { return d - 2 * dot(d, n) * n; }

bool refract_direction(Vec3f d, Vec3f n, float from_index, float to_index, Vec3f& refracted) {
    // With n turned against d, cos θi = −d·n; Snell: sin θt = η sin θi with η = n1/n2, and
    // T = η d + (η cos θi − cos θt) n, where cos θt = √(1 − η²(1 − cos² θi)).
    if (dot(d, n) > 0) n = -n;
    const float eta = from_index / to_index;
    const float cos_incident = -dot(d, n);
    const float sin2_transmitted = eta * eta * (1 - cos_incident * cos_incident);
    if (sin2_transmitted > 1) return false;  // total internal reflection
    const float cos_transmitted = std::sqrt(1 - sin2_transmitted);
    refracted = normalize(eta * d + (eta * cos_incident - cos_transmitted) * n);
    return true;
}

namespace {

// The float just above |x| in magnitude, minus |x|: one unit in the last place. The next float
// up from a non-negative one is the next bit pattern (std::nextafter's answer, without the
// library call; +inf and NaN give NaN either way).
float ulp(float x) {
    x = std::fabs(x);
    uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    ++bits;
    float next;
    std::memcpy(&next, &bits, sizeof next);
    return next - x;
}

}  // namespace

float ray_offset_distance(Vec3f position, float travel_scale) {
    // The hit point is o + t·d rounded, with t itself a little off, and the surface it lies on is
    // only as exact as the point's own coordinates: its error is a few ulps of the largest of
    // them and of the ray's magnitudes (pbrt-v4 and Mitsuba 3 bound it the same way). Moving by a
    // multiple of that bound along the normal clears the surface at any scene scale, where a
    // fixed epsilon is either too small far from the origin or visibly too large in a tiny scene.
    return 64 * ulp(max_abs(position)) + 16 * ulp(travel_scale) + 1e-30f;
}

}  // namespace raycast
