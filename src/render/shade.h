// The optics of one surface point, as pure functions: the course's Phong formula (or MIT 6.837's
// Blinn variants) for one light, the mirror and refracted directions, and the offset that lets a
// new ray leave the surface it starts on. The integrators (render/integrator.h) put them together.
#pragma once

#include "math/ray.h"
#include "scene/conventions.h"
#include "scene/material.h"

namespace raycast {

/// One light's diffuse and specular terms at a point, before the light's colour.
struct LightReflection {
    Vec3f diffuse;   ///< kd·max(0, N·L)
    Vec3f specular;  ///< ks times the model's specular factor
};

/// The reflection model for one light: colour leaving the surface towards `to_viewer` lit from
/// `to_light` (all unit vectors), split into its two terms.
LightReflection reflect_light_terms(const Material& material, SpecularModel model, Vec3f normal, Vec3f to_light,
                                    Vec3f to_viewer);

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
float ray_travel_scale(Vec3f origin, Vec3f direction, float t);

/// A point nudged off a surface along its normal, towards `side`, far enough that a ray starting
/// there cannot hit the surface it left (used for shadow, reflected and transmitted rays).
/// `travel_scale` is ray_travel_scale of the ray that found the point.
Vec3f offset_ray_origin(Vec3f position, Vec3f normal, Vec3f side, float travel_scale);

}  // namespace raycast
