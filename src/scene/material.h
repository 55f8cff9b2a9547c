// Surface materials: the Phong parameters, plus what later ray-tracing stages will need.
#pragma once

#include "math/vec.h"

namespace raycast {

struct Material {
    Vec3f diffuse{1, 1, 1};
    Vec3f specular{0, 0, 0};
    float shininess = 0;
    Vec3f reflective{0, 0, 0};
    Vec3f transparent{0, 0, 0};
    float index_of_refraction = 1;
};

}  // namespace raycast
