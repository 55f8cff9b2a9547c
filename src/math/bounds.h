// Axis-aligned bounding boxes. An empty box has lower = +inf and upper = -inf, so that
// growing it by any point gives that point.
#pragma once

#include <limits>

#include "math/vec.h"

namespace raycast {

struct Bounds3f {
    Vec3f lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                std::numeric_limits<float>::infinity()};
    Vec3f upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                -std::numeric_limits<float>::infinity()};

    bool is_empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
    Vec3f extent() const { return upper - lower; }
    Vec3f center() const { return (lower + upper) * 0.5f; }
    /// Surface area; zero for an empty box. The SAH only needs it up to a constant factor.
    float half_area() const {
        if (is_empty()) return 0;
        const Vec3f e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
    void grow(Vec3f p) {
        lower = min(lower, p);
        upper = max(upper, p);
    }
    void grow(const Bounds3f& b) {
        lower = min(lower, b.lower);
        upper = max(upper, b.upper);
    }
};

inline Bounds3f merge(Bounds3f a, const Bounds3f& b) {
    a.grow(b);
    return a;
}

}  // namespace raycast
