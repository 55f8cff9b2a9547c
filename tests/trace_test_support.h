// Inputs and reports shared by the tests of the BVHs and of what is traced through them
// (src/bvh/*_test.cpp, src/scene/mesh_kernel_test.cpp): random boxes, triangle soups, closed and
// open meshes, points where triangles meet, scenes of one mesh, and readable rays and hits.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bvh/build_bvh.h"
#include "geometry/hit.h"
#include "geometry/triangle_groups.h"
#include "scene/build_scene.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"
#include "scene_builders.h"

namespace raycast::test {

inline Bounds3f box(Vec3f lower, Vec3f upper) {
    Bounds3f b;
    b.lower = lower;
    b.upper = upper;
    return b;
}

inline bool contains(const Bounds3f& outer, const Bounds3f& inner) {
    for (int a = 0; a < 3; ++a)
        if (inner.lower[a] < outer.lower[a] || inner.upper[a] > outer.upper[a]) return false;
    return true;
}

// What a tree over `prims` must hold: the ids of those with a box (sorted), and the box of all.
inline std::vector<uint32_t> ids_with_boxes(const std::vector<BvhPrimitive>& prims, Bounds3f& all) {
    std::vector<uint32_t> ids;
    for (const BvhPrimitive& p : prims)
        if (!p.bounds.is_empty()) {
            ids.push_back(p.id);
            all.grow(p.bounds);
        }
    std::sort(ids.begin(), ids.end());
    return ids;
}

inline std::vector<BvhPrimitive> random_boxes(std::mt19937& rng, size_t count, float world, float max_size) {
    std::uniform_real_distribution<float> u(-1, 1), size_exp(-4, 0);
    std::vector<BvhPrimitive> prims(count);
    for (size_t i = 0; i < count; ++i) {
        const Vec3f c{u(rng) * world, u(rng) * world, u(rng) * world};
        const float s = max_size * std::pow(10.0f, size_exp(rng));
        const Vec3f half{s * std::fabs(u(rng)), s * std::fabs(u(rng)), s * std::fabs(u(rng))};
        prims[i] = {box(c - half, c + half), static_cast<uint32_t>(i)};
    }
    return prims;
}

/// Every packet instruction set this CPU runs, and None (one ray at a time).
inline std::vector<PacketIsa> packet_isas() {
    std::vector<PacketIsa> isas;
    for (PacketIsa isa : {PacketIsa::None, PacketIsa::Portable, PacketIsa::Sse2, PacketIsa::Avx2, PacketIsa::Avx512})
        if (packet_isa_available(isa)) isas.push_back(isa);
    return isas;
}

inline TriangleMesh soup(std::mt19937& rng, size_t count, float world, float size) {
    std::uniform_real_distribution<float> u(-1, 1), size_exp(-1.5f, 0);
    TriangleMesh mesh;
    for (size_t i = 0; i < count; ++i) {
        const Vec3f c{u(rng) * world, u(rng) * world, u(rng) * world};
        const float s = size * std::pow(10.0f, size_exp(rng));
        for (int k = 0; k < 3; ++k) {
            mesh.indices.push_back(static_cast<uint32_t>(mesh.positions.size()));
            mesh.positions.push_back(c + Vec3f{u(rng), u(rng), u(rng)} * s);
        }
    }
    return mesh;
}

// A height field over [0, n]², cells cut along alternating diagonals.
inline TriangleMesh grid_mesh(std::mt19937& rng, int n, float bumpiness) {
    std::uniform_real_distribution<float> u(-1, 1);
    TriangleMesh mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            mesh.positions.push_back({static_cast<float>(i), static_cast<float>(j), bumpiness * u(rng)});
    auto at = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if ((i + j) % 2 == 0) {
                mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                mesh.indices.insert(mesh.indices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
            } else {
                mesh.indices.insert(mesh.indices.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
                mesh.indices.insert(mesh.indices.end(), {at(i + 1, j), at(i, j + 1), at(i, j)});
            }
        }
    return mesh;
}

inline SceneDesc scene_desc() {
    SceneDesc desc;
    desc.file = "test.scene";
    CameraDesc camera;
    camera.center = {0, 0, 20};
    camera.angle_degrees = 30;
    camera.width = camera.height = 8;
    desc.camera = camera;
    desc.materials.resize(1);
    ObjectDesc root;
    root.kind = ObjectDesc::Kind::Group;
    desc.root = root;
    return desc;
}

inline int add_mesh(SceneDesc& desc, TriangleMesh mesh) {
    desc.meshes.push_back({"mesh" + std::to_string(desc.meshes.size()) + ".obj", std::move(mesh)});
    return static_cast<int>(desc.meshes.size()) - 1;
}

inline Scene scene_with(SceneDesc desc, int threads = 1) {
    SceneBuildOptions options;
    options.threads = threads;
    return build_scene(std::move(desc), options);
}

inline Scene scene_of_mesh(TriangleMesh mesh, int threads = 1) {
    SceneDesc desc = scene_desc();
    const int index = add_mesh(desc, std::move(mesh));
    desc.root->children.push_back(mesh_object(index));
    return scene_with(std::move(desc), threads);
}

// Calls fn(triangle, block of its group) for every triangle in the mesh's groups.
template <typename Fn>
void for_each_group_triangle(const MeshShape& shape, Fn&& fn) {
    if (shape.groups.empty()) return;
    const GroupBlock* end = shape.groups.data() + shape.groups.size() - kGroupPaddingBlocks;
    for (const GroupBlock* group = shape.groups.data(); group < end; group = next_group(group))
        for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane)
            fn(group_triangle(group, lane), static_cast<uint32_t>(group - shape.groups.data()));
}

inline std::string describe(const Hit& h) {
    if (!h.is_hit()) return "miss";
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "t=%.9g (%a) object %u prim %u u=%.9g v=%.9g", static_cast<double>(h.t),
                  static_cast<double>(h.t), h.object, h.prim, static_cast<double>(h.u), static_cast<double>(h.v));
    return buffer;
}

inline std::string describe(const Ray& r, float t_min) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "ray (%a, %a, %a) + t·(%a, %a, %a), t_min %g", static_cast<double>(r.origin.x),
                  static_cast<double>(r.origin.y), static_cast<double>(r.origin.z), static_cast<double>(r.direction.x),
                  static_cast<double>(r.direction.y), static_cast<double>(r.direction.z), static_cast<double>(t_min));
    return buffer;
}

inline Vec3f corner(const TriangleMesh& mesh, size_t triangle, int k) {
    return mesh.positions[mesh.indices[3 * triangle + static_cast<size_t>(k)]];
}

// A point of triangle t where it meets its neighbours: a corner, or a point computed on an edge
// (in float, so within rounding of the edge; the watertight test must still hit one of the
// triangles that share it).
inline Vec3f shared_point_of(const TriangleMesh& mesh, size_t t, std::mt19937& rng) {
    std::uniform_int_distribution<int> k3(0, 2), kind(0, 2);
    std::uniform_real_distribution<float> u01(0, 1);
    const int k = k3(rng);
    const Vec3f a = corner(mesh, t, k), b = corner(mesh, t, (k + 1) % 3);
    switch (kind(rng)) {
        case 0:
            return a;
        case 1:
            return a + (b - a) * 0.5f;
        default:
            return a + (b - a) * u01(rng);
    }
}

// The same for a random triangle of the mesh.
inline Vec3f shared_point(const TriangleMesh& mesh, std::mt19937& rng) {
    std::uniform_int_distribution<size_t> pick(0, mesh.triangle_count() - 1);
    const size_t t = pick(rng);
    return shared_point_of(mesh, t, rng);
}

// Groups of triangles ids[0..count) of `mesh` as the scene writes them, with the padding.
inline std::vector<GroupBlock> groups_of(const TriangleMesh& mesh, const std::vector<uint32_t>& ids) {
    std::vector<GroupBlock> groups(triangle_group_blocks(mesh, ids.data(), ids.size()) + kGroupPaddingBlocks);
    write_triangle_groups(mesh, ids.data(), ids.size(), groups.data());
    return groups;
}

// Checks one group against the mesh it was made from: within the group limits, each triangle's
// id in range and seen for the first time (counted in `seen`), its corners the mesh's own, and
// found again by its id.
inline void expect_group_of(const GroupBlock* group, const TriangleMesh& mesh, std::vector<int>& seen) {
    ASSERT_GE(group_triangle_count(group), 1u);
    ASSERT_LE(group_triangle_count(group), static_cast<uint32_t>(kGroupMaxTriangles));
    ASSERT_LE(group_vertex_count(group), static_cast<uint32_t>(kGroupMaxVertices));
    for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) {
        const GroupTriangle tri = group_triangle(group, lane);
        ASSERT_LT(tri.id, seen.size());
        EXPECT_EQ(seen[tri.id]++, 0) << "triangle " << tri.id << " is in two groups";
        EXPECT_EQ(tri.p0, corner(mesh, tri.id, 0));
        EXPECT_EQ(tri.p1, corner(mesh, tri.id, 1));
        EXPECT_EQ(tri.p2, corner(mesh, tri.id, 2));
        EXPECT_EQ(group_lane_of(group, tri.id), lane);
    }
    EXPECT_EQ(group_lane_of(group, 0xffffffffu), group_triangle_count(group));
}

/// The bits of a float, to compare results exactly (a NaN equals itself, -0 differs from +0).
inline uint32_t bits_of(float x) {
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

}  // namespace raycast::test
