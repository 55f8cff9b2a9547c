// The optics of one surface point, as pure functions: the course's Phong formula (or MIT 6.837's
// Blinn variants) for one light, the mirror and refracted directions, and the offset that lets a
// new ray leave the surface it starts on. The integrators (render/integrator.h) put them together.
#pragma once

#include <cmath>

#include "math/ray.h"
#include "scene/conventions.h"
#include "scene/material.h"

namespace raycast {

/// One light's diffuse and specular terms at a point, before the light's colour.
struct LightReflection {
    Vec3f diffuse;   ///< kd·max(0, N·L)
    Vec3f specular;  ///< ks times the model's specular factor
};

namespace shade_detail {

// max(0, x), with NaN giving 0 as std::fmax does; written as a comparison because GCC calls
// fmaxf as a library function.
inline float positive_part(float x) { return x > 0 ? x : 0.0f; }

// std::pow(base, exponent) for base >= 0 (or NaN), skipping the call where the answer is known:
// half the lit points face away from the highlight, and powf is the dearest step of shading.
inline float specular_power(float base, float exponent) {
    if (base == 0 && exponent > 0) return 0;
    return std::pow(base, exponent);
}

}  // namespace shade_detail

/// The reflection model for one light: colour leaving the surface towards `to_viewer` lit from
/// `to_light` (all unit vectors), split into its two terms. Inline, as are the other per-hit
/// helpers here: shading calls it for every light at every hit, and a call returns its two
/// colours through memory. shade_camera_hits_locally (integrators.cpp) does these operations
/// a step at a time for a packet's hits: a change here is a change there (ExplainTest checks).
inline LightReflection reflect_light_terms(const Material& material, SpecularModel model, Vec3f normal,
                                           Vec3f to_light, Vec3f to_viewer) {
    using shade_detail::positive_part;
    using shade_detail::specular_power;
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

/// Whether reflect_light_terms is exactly zero, both terms, for these vectors, found without
/// the power where it can be: then a shadow ray towards the light cannot change the colour and is
/// not traced (as pbrt does). Assumes finite material colours (the parser admits no others).
/// True only where the terms are zero; false says nothing.
inline bool reflects_no_light(const Material& material, SpecularModel model, Vec3f normal, Vec3f to_light,
                              Vec3f to_viewer) {
    const float n_dot_l = dot(normal, to_light);
    if (n_dot_l > 0) return false;  // kd·(N·L)
    switch (model) {
        case SpecularModel::Phong: {
            // The power of a base of 0 is 0 for a positive exponent (1 for 0).
            const Vec3f reflected = 2 * n_dot_l * normal - to_light;
            return material.shininess > 0 && !(dot(to_viewer, reflected) > 0);
        }
        case SpecularModel::BlinnClampedByNdotL: return true;
        case SpecularModel::BlinnTimesNdotL: break;  // 0 times the power: zero unless that overflows
    }
    const LightReflection terms = reflect_light_terms(material, model, normal, to_light, to_viewer);
    return terms.diffuse == Vec3f{0, 0, 0} && terms.specular == Vec3f{0, 0, 0};
}

/// The same, summed: diffuse + specular.
inline Vec3f reflect_light(const Material& material, SpecularModel model, Vec3f normal, Vec3f to_light,
                           Vec3f to_viewer) {
    const LightReflection r = reflect_light_terms(material, model, normal, to_light, to_viewer);
    return r.diffuse + r.specular;
}

/// The mirror image of direction `d` about the plane with unit normal `n`: d − 2(d·n)n. Either
/// side's normal gives the same direction, and |result| = |d|.
Vec3f mirror_direction(Vec3f d, Vec3f n);

/// Snell's law: the direction in which unit direction `d` continues through a surface with unit
/// normal `n` (either side), going from a medium of index `from_index` into one of `to_index`.
/// False for total internal reflection (no transmitted ray). The result is a unit vector.
bool refract_direction(Vec3f d, Vec3f n, float from_index, float to_index, Vec3f& refracted);

/// How large the numbers were that a hit point o + t·d came from: max|o| + |t|·max|d|. A point
/// near the origin seen from far away is only as accurate as the long ray that found it.
inline float ray_travel_scale(Vec3f origin, Vec3f direction, float t) {
    const float scale = max_abs(origin) + std::fabs(t) * max_abs(direction);
    return std::isfinite(scale) ? scale : 0.0f;
}

/// The scale of every number a hit point came from: ray_travel_scale of the ray that found it, or
/// that of the shape it lies on (SurfacePoint::geometry_scale) where larger. A point near the
/// origin on a floor of two triangles 4000 across was found 3e-5 off the floor, more than an
/// offset for its own coordinates, and its shadow rays met the floor again.
inline float hit_travel_scale(Vec3f origin, Vec3f direction, float t, float geometry_scale) {
    const float travel = ray_travel_scale(origin, direction, t);
    return geometry_scale > travel ? geometry_scale : travel;
}

/// How far offset_ray_origin moves a point found by a ray of `travel_scale` (hit_travel_scale):
/// far enough that a ray starting there cannot hit the surface it left.
float ray_offset_distance(Vec3f position, float travel_scale);

/// `position` moved `distance` (ray_offset_distance) along `normal`, to the side of `side`: for
/// the many rays that leave one point, which need the distance only once.
inline Vec3f offset_ray_origin_by(Vec3f position, Vec3f normal, Vec3f side, float distance) {
    const Vec3f n = dot(normal, side) < 0 ? -normal : normal;
    return position + n * distance;
}

/// A point nudged off a surface along its normal, towards `side`, far enough that a ray starting
/// there cannot hit the surface it left (used for shadow, reflected and transmitted rays).
/// `travel_scale` is hit_travel_scale of the point.
inline Vec3f offset_ray_origin(Vec3f position, Vec3f normal, Vec3f side, float travel_scale) {
    return offset_ray_origin_by(position, normal, side, ray_offset_distance(position, travel_scale));
}

}  // namespace raycast
