#include "geometry/triangle_mesh.h"

namespace raycast {

Bounds3f mesh_bounds(const TriangleMesh& mesh) {
    Bounds3f bounds;
    for (uint32_t index : mesh.indices) bounds.grow(mesh.positions[index]);
    return bounds;
}

}  // namespace raycast
