// The closest-hit record: small, filled during traversal; position, normal and material are
// worked out once afterwards from (object, prim, u, v).
#pragma once

#include <cstdint>
#include <limits>

namespace raycast {

constexpr uint32_t kNoObject = std::numeric_limits<uint32_t>::max();

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    float u = 0, v = 0;         ///< barycentric weights of a triangle's vertices 1 and 2; a surface of
                                ///< revolution's profile parameter in u (on piece `prim`)
    uint32_t object = kNoObject;  ///< the object's place in the scene file (its order)
    uint32_t prim = 0;          ///< the triangle's index in its mesh; a surface of revolution's piece;
                                ///< 0 for other shapes
    /// Where a mesh keeps the triangle: the first block of its group (MeshShape::groups), in
    /// which surface_at finds its corners next to those just tested (the mesh keeps no other
    /// copy of them). 0 for other shapes.
    uint32_t leaf = 0;
    /// The triangle's place in that group (0 to 7): surface_at reads its corners there without
    /// searching the group's ids for `prim`. 0 for other shapes.
    uint32_t lane = 0;

    bool is_hit() const { return object != kNoObject; }
};

/// The ordering that makes the closest hit unique: nearer first, and on an exact tie the object
/// listed first in the scene file, then the lower triangle index (the course's loops keep the
/// first of equal hits). Every traversal path uses it, so their images are identical.
inline bool is_closer(float t, uint32_t object, uint32_t prim, const Hit& best) {
    if (t != best.t) return t < best.t;
    return object != best.object ? object < best.object : prim < best.prim;
}

}  // namespace raycast
