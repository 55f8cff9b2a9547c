#include "render/shade.h"

#include <cmath>
#include <cstring>

namespace raycast {

namespace {

// max(0, x), with NaN giving 0 as std::fmax does; written as a comparison because GCC calls
// fmaxf as a library function.
float positive_part(float x) { return x > 0 ? x : 0.0f; }

// std::pow(base, exponent) for base >= 0 (or NaN), skipping the call where the answer is known:
// half the lit points face away from the highlight, and powf is the dearest step of shading.
float specular_power(float base, float exponent) {
    if (base == 0 && exponent > 0) return 0;
    return std::pow(base, exponent);
}

}  // namespace

LightReflection reflect_light_terms(const Material& material, SpecularModel model, Vec3f normal, Vec3f to_light,
                                    Vec3f to_viewer) {
    const float n_dot_l = dot(normal, to_light);
    const Vec3f diffuse = material.diffuse * positive_part(n_dot_l);
    float specular = 0;
    switch (model) {
        case SpecularModel::Phong: {
            // The handout's formula, term for term: R = 2(L·N)N − L and ks·max(0, V·R)^s, with no
            // gate on L·N (the course's reference images have none).
            const Vec3f reflected = 2 * n_dot_l * normal - to_light;
            specular = specular_power(positive_part(dot(to_viewer, reflected)), material.shininess);
            break;
        }
        case SpecularModel::BlinnClampedByNdotL:
        case SpecularModel::BlinnTimesNdotL: {
            const Vec3f half_vector = normalize(to_light + to_viewer);
            specular = specular_power(positive_part(dot(normal, half_vector)), material.shininess);
            if (model == SpecularModel::BlinnClampedByNdotL && !(n_dot_l > 0)) specular = 0;
            if (model == SpecularModel::BlinnTimesNdotL) specular *= positive_part(n_dot_l);
            break;
        }
    }
    return {diffuse, material.specular * specular};
}

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

// The float just above |x| in magnitude, minus |x|: one unit in the last place.
float ulp(float x) {
    x = std::fabs(x);
    return std::nextafter(x, INFINITY) - x;
}

float max_abs(Vec3f v) { return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z))); }

}  // namespace

float ray_travel_scale(Vec3f origin, Vec3f direction, float t) {
    const float scale = max_abs(origin) + std::fabs(t) * max_abs(direction);
    return std::isfinite(scale) ? scale : 0.0f;
}

Vec3f offset_ray_origin(Vec3f position, Vec3f normal, Vec3f side, float travel_scale) {
    // The hit point is o + t·d rounded, with t itself a little off, and the surface it lies on is
    // only as exact as the point's own coordinates: its error is a few ulps of the largest of
    // them and of the ray's magnitudes (pbrt-v4 and Mitsuba 3 bound it the same way). Moving by a
    // multiple of that bound along the normal clears the surface at any scene scale, where a
    // fixed epsilon is either too small far from the origin or visibly too large in a tiny scene.
    const float distance = 64 * ulp(max_abs(position)) + 16 * ulp(travel_scale) + 1e-30f;
    const Vec3f n = dot(normal, side) < 0 ? -normal : normal;
    return position + n * distance;
}

}  // namespace raycast
