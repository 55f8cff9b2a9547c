// Shading a hit: the course's Phong formula (or MIT 6.837's Blinn variants, by the scene's
// conventions), summed over the lights, plus ambient light where a scene has it.
#pragma once

#include "scene/scene.h"

namespace raycast {

/// The colour seen along `ray` at `hit`. With `shadows`, a light counts only if nothing lies
/// between the point and the light.
Vec3f shade(const Scene& scene, const Ray& ray, const Hit& hit, bool shadows);

/// The reflection model for one light, exposed for tests: colour leaving the surface towards
/// `to_viewer` lit from `to_light` (all unit vectors), before multiplying by the light's colour.
Vec3f reflect_light(const Material& material, SpecularModel model, Vec3f normal, Vec3f to_light, Vec3f to_viewer);

/// A point nudged off a surface along its normal, towards `side`, far enough that a ray starting
/// there cannot hit the surface it left (used for shadow rays).
Vec3f offset_ray_origin(Vec3f position, Vec3f normal, Vec3f side);

}  // namespace raycast
