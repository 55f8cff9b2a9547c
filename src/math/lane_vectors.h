// Vectors of several lanes stored one array per component (structure of arrays): a loop over the
// lanes that does one vector operation is one the compiler makes SIMD instructions of, each lane
// doing exactly the scalar operation (the same bits: the build never fuses a*b+c). Packets of
// camera rays and of hits are shaded this way (scene/camera.h, scene/intersect_packet.h,
// render/integrators.cpp).
#pragma once

#include <cmath>

#include "math/vec.h"

namespace raycast {

/// The most lanes a LaneVectors holds: a packet of the widest SIMD kernel (16 rays).
constexpr int kMaxLanes = 16;

struct LaneVectors {
    float x[kMaxLanes], y[kMaxLanes], z[kMaxLanes];

    Vec3f at(int j) const { return {x[j], y[j], z[j]}; }
    void set(int j, Vec3f v) {
        x[j] = v.x;
        y[j] = v.y;
        z[j] = v.z;
    }
};

/// normalize() of lanes [0, count) of `a`, in place, and their lengths before: a / |a|, a zero
/// vector staying zero. Dividing by 1 leaves a component exactly as it is, and a division made
/// on no condition is one the compiler vectorises (a conditional one might trap where the scalar
/// code would not divide, so GCC keeps it scalar).
inline void normalize_lanes(LaneVectors& a, float* length, int count) {
    for (int j = 0; j < count; ++j) length[j] = std::sqrt(a.x[j] * a.x[j] + a.y[j] * a.y[j] + a.z[j] * a.z[j]);
    for (int j = 0; j < count; ++j) {
        const float divisor = length[j] > 0 ? length[j] : 1.0f;
        a.x[j] = a.x[j] / divisor;
        a.y[j] = a.y[j] / divisor;
        a.z[j] = a.z[j] / divisor;
    }
}

}  // namespace raycast
