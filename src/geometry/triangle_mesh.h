// A triangle mesh as flat arrays, as loaded from an OBJ file: no object per triangle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "math/bounds.h"
#include "math/vec.h"

namespace raycast {

constexpr uint32_t kNoNormal = 0xffffffffu;

struct TriangleMesh {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;         ///< 3 per triangle, into positions
    std::vector<Vec3f> normals;            ///< the file's vn lines; empty if it has none
    std::vector<uint32_t> normal_indices;  ///< 3 per triangle into normals, or kNoNormal for a
                                           ///< face without them; empty if the file has no vn
    size_t triangle_count() const { return indices.size() / 3; }
    bool has_normals() const { return !normal_indices.empty(); }
};

/// The box around every position the faces use.
Bounds3f mesh_bounds(const TriangleMesh& mesh);

}  // namespace raycast
