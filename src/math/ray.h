// A ray origin + t·direction. The direction is not required to be unit length: under a
// transform it is not, and t stays the same parameter in world and object space.
#pragma once

#include "math/vec.h"

namespace raycast {

struct Ray {
    Vec3f origin;
    Vec3f direction;

    Vec3f at(float t) const { return origin + direction * t; }
};

}  // namespace raycast
