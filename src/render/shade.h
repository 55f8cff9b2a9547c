// The optics of one surface point, as pure functions: the course's Phong formula (or MIT 6.837's
// Blinn variants) for one light, and the offset that lets a new ray leave the surface it starts
// on. The integrators (render/integrator.h) put them together.
#pragma once

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

/// A point nudged off a surface along its normal, towards `side`, far enough that a ray starting
/// there cannot hit the surface it left (used for shadow rays).
Vec3f offset_ray_origin(Vec3f position, Vec3f normal, Vec3f side);

}  // namespace raycast
