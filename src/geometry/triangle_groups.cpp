#include "geometry/triangle_groups.h"

#include <algorithm>

#include "base/check.h"

namespace raycast {

namespace {

using namespace group_layout;

// One group being filled: its triangles' corners as numbers of its own vertices.
struct OpenGroup {
    uint32_t vertex[kGroupMaxVertices];  // mesh vertex indices
    uint8_t corner[3][kGroupMaxTriangles];
    uint32_t id[kGroupMaxTriangles];
    uint32_t vertices = 0, triangles = 0;

    // Adds triangle `id` if it fits: a free triangle slot, and slots for the vertices it does not
    // share with the group so far. Vertices are shared by index, as the mesh shares them.
    bool add(const TriangleMesh& mesh, uint32_t triangle) {
        if (triangles == kGroupMaxTriangles) return false;
        const uint32_t* corners = &mesh.indices[3 * size_t{triangle}];
        uint8_t number[3];
        uint32_t added = 0;
        for (int k = 0; k < 3; ++k) {
            uint32_t found = vertices + added;
            for (uint32_t v = 0; v < vertices + added; ++v)
                if (vertex[v] == corners[k]) found = v;
            if (found == vertices + added) {
                if (found == kGroupMaxVertices) return false;
                vertex[found] = corners[k];
                ++added;
            }
            number[k] = static_cast<uint8_t>(found);
        }
        vertices += added;
        for (int k = 0; k < 3; ++k) corner[k][triangles] = number[k];
        id[triangles++] = triangle;
        return true;
    }
};

// Splits ids[0..count) greedily into groups and calls emit(group, is_last) for each.
template <typename EmitFn>
void split_into_groups(const TriangleMesh& mesh, const uint32_t* ids, size_t count, EmitFn&& emit) {
    OpenGroup group;
    for (size_t i = 0; i < count; ++i) {
        if (group.add(mesh, ids[i])) continue;
        emit(group, false);
        group = OpenGroup{};
        const bool added = group.add(mesh, ids[i]);
        RAYCAST_CHECK(added);  // one triangle always fits an empty group
    }
    if (group.triangles > 0) emit(group, true);
}

}  // namespace

uint32_t triangle_group_blocks(const TriangleMesh& mesh, const uint32_t* ids, size_t count) {
    uint32_t blocks = 0;
    split_into_groups(mesh, ids, count,
                      [&](const OpenGroup& group, bool) { blocks += group_blocks(group.triangles, group.vertices); });
    return blocks;
}

void write_triangle_groups(const TriangleMesh& mesh, const uint32_t* ids, size_t count, GroupBlock* out) {
    split_into_groups(mesh, ids, count, [&](const OpenGroup& group, bool is_last) {
        const uint32_t k = group.triangles, v = group.vertices;
        const uint32_t blocks = group_blocks(k, v);
        unsigned char* bytes = out->bytes;
        std::fill(bytes, bytes + 16 * size_t{blocks}, static_cast<unsigned char>(0));
        bytes[0] = static_cast<unsigned char>(k);
        bytes[1] = static_cast<unsigned char>(v);
        bytes[2] = is_last ? kGroupEndsLeaf : 0;
        for (uint32_t c = 0; c < 3; ++c) std::memcpy(bytes + group_corners_offset() + c * k, group.corner[c], k);
        for (uint32_t j = 0; j < v; ++j) {
            const Vec3f& p = mesh.positions[group.vertex[j]];
            std::memcpy(bytes + group_vertices_offset(k) + 4 * j, &p.x, 4);
            std::memcpy(bytes + group_vertices_offset(k) + 4 * (v + j), &p.y, 4);
            std::memcpy(bytes + group_vertices_offset(k) + 4 * (2 * v + j), &p.z, 4);
        }
        std::memcpy(bytes + group_ids_offset(k, v), group.id, 4 * size_t{k});
        out += blocks;
    });
}

uint32_t group_lane_of(const GroupBlock* group, uint32_t id) {
    const uint32_t k = group_triangle_count(group), v = group_vertex_count(group);
    // A group spans several blocks: address it from a pointer to its first byte, not as
    // `group->bytes + offset`, which names an array of 16 (UBSan's bounds check says so).
    const unsigned char* bytes = group->bytes;
    uint32_t lane = 0;
    for (; lane < k; ++lane) {
        uint32_t lane_id;
        std::memcpy(&lane_id, bytes + group_ids_offset(k, v) + 4 * lane, 4);
        if (lane_id == id) break;
    }
    return lane;
}

}  // namespace raycast
