// Lights, and what a light gives a point: the direction towards it and the light that arrives.
#pragma once

#include <cmath>
#include <limits>

#include "math/vec.h"

namespace raycast {

struct Light {
    enum class Kind { Directional, Point };
    Kind kind = Kind::Directional;
    Vec3f direction{0, 0, -1};  ///< directional: unit, the way the light travels
    Vec3f position;             ///< point
    Vec3f color{1, 1, 1};
    Vec3f attenuation{1, 0, 0};  ///< point: 1 / (c + l·d + q·d²); (1, 0, 0) is none (the course)
};

struct Illumination {
    Vec3f to_light;  ///< unit
    Vec3f color;     ///< arriving light
    float distance;  ///< to the light; infinity for directional lights
};

/// What arrives at `point` from the light. shade_camera_hits_locally (render/integrators.cpp)
/// does the same operations for a packet's points at once: a change here is a change there.
inline Illumination illuminate(const Light& light, Vec3f point) {
    if (light.kind == Light::Kind::Directional)
        return {-light.direction, light.color, std::numeric_limits<float>::infinity()};
    const Vec3f offset = light.position - point;
    const float distance = length(offset);
    const Vec3f& a = light.attenuation;
    float falloff = a.x + a.y * distance + a.z * distance * distance;
    if (!(falloff > 0)) falloff = 1;
    const Vec3f color = falloff == 1 ? light.color : light.color / falloff;
    return {normalize(offset), color, distance};
}

}  // namespace raycast
