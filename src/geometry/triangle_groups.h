// Mesh triangles packed for a SIMD test of one ray against several triangles at once: groups of up
// to 8 triangles sharing up to 16 vertices, each vertex stored once (a closed mesh has about half
// as many vertices as triangles, so a group of 8 triangles usually has 8-10 of them). A group
// holds exact copies of the vertex coordinates, so every test of a grouped triangle computes what
// the watertight test (geometry/triangle.h) computes from the mesh itself.
// Entry points: GroupBlock, append_triangle_groups, group_triangle.
#pragma once

#include <cstdint>
#include <cstring>

#include "base/check.h"
#include "geometry/triangle_mesh.h"
#include "math/vec.h"

namespace raycast {

constexpr int kGroupMaxTriangles = 8;
constexpr int kGroupMaxVertices = 16;
/// Bit of a group's flags byte: the last group of a BVH leaf (a leaf's groups are consecutive).
constexpr uint8_t kGroupEndsLeaf = 1;
/// Blocks of padding after the last group: the SIMD kernels load whole registers (up to 64
/// bytes) from a group's planes, which may run past its end.
constexpr uint32_t kGroupPaddingBlocks = 4;

/// Groups are stored in, and addressed by, 16-byte blocks. A group, from its first block:
///   byte 0: triangle count k (1..8); byte 1: vertex count v (1..16); byte 2: flags; byte 3: 0
///   byte 4: the k triangles' first corners (vertex numbers within the group, one byte each),
///           then their second corners, then their third corners
///   from group_vertices_offset(k), 4-aligned: the v vertices' x coordinates (floats), then
///           their y, then their z
///   from group_ids_offset(k, v): the k triangles' ids (uint32: their index in the mesh)
/// and it ends at the next 16-byte boundary (geometry/triangle_group_layout.inl has the offsets).
struct alignas(16) GroupBlock {
    unsigned char bytes[16];
};

namespace group_layout {
#include "geometry/triangle_group_layout.inl"
}  // namespace group_layout

/// The blocks that triangles ids[0..count) of `mesh` need as groups (the same split as
/// write_triangle_groups makes: greedily, in this order).
uint32_t triangle_group_blocks(const TriangleMesh& mesh, const uint32_t* ids, size_t count);

/// Writes triangles ids[0..count) of `mesh` as groups from `out` on (triangle_group_blocks of
/// them), splitting greedily in this order; the last group gets kGroupEndsLeaf.
void write_triangle_groups(const TriangleMesh& mesh, const uint32_t* ids, size_t count, GroupBlock* out);

/// A grouped triangle as the mesh had it.
struct GroupTriangle {
    Vec3f p0, p1, p2;
    uint32_t id = 0;
};

inline uint32_t group_triangle_count(const GroupBlock* group) { return group->bytes[0]; }
inline uint32_t group_vertex_count(const GroupBlock* group) { return group->bytes[1]; }
inline bool group_ends_leaf(const GroupBlock* group) { return (group->bytes[2] & kGroupEndsLeaf) != 0; }
/// The group stored after `group` (in the same leaf unless `group` ends its leaf).
inline const GroupBlock* next_group(const GroupBlock* group) {
    return group + group_layout::group_blocks(group_triangle_count(group), group_vertex_count(group));
}

/// Triangle `lane` (< group_triangle_count) of a group. Inline: shading a mesh hit calls it once
/// per hit, and a call would return the 40-byte triangle through memory.
inline GroupTriangle group_triangle(const GroupBlock* group, uint32_t lane) {
    const uint32_t k = group_triangle_count(group), v = group_vertex_count(group);
    RAYCAST_DCHECK(lane < k);
    const unsigned char* bytes = group->bytes;
    auto vertex = [&](uint32_t corner) {
        const uint32_t j = bytes[group_layout::group_corners_offset() + corner * k + lane];
        Vec3f p;
        std::memcpy(&p.x, bytes + group_layout::group_vertices_offset(k) + 4 * j, 4);
        std::memcpy(&p.y, bytes + group_layout::group_vertices_offset(k) + 4 * (v + j), 4);
        std::memcpy(&p.z, bytes + group_layout::group_vertices_offset(k) + 4 * (2 * v + j), 4);
        return p;
    };
    GroupTriangle triangle;
    triangle.p0 = vertex(0);
    triangle.p1 = vertex(1);
    triangle.p2 = vertex(2);
    std::memcpy(&triangle.id, bytes + group_layout::group_ids_offset(k, v) + 4 * lane, 4);
    return triangle;
}

/// The lane of the triangle with this id, or group_triangle_count if the group does not hold it.
uint32_t group_lane_of(const GroupBlock* group, uint32_t id);

}  // namespace raycast
