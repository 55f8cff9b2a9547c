// Tests for what meshes are traced with: triangle groups (geometry/triangle_groups.h), the
// single-ray kernels of every instruction set (scene/ray_kernel.inl) and the packet kernels'
// occlusion query (scene/packet_kernel.inl). Each must give exactly the answers of the scalar
// code: the same hits bit for bit, so that every path renders the same image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bvh/bvh.h"
#include "geometry/triangle.h"
#include "geometry/triangle_groups.h"
#include "scene/build_scene.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"
#include "scene_builders.h"
#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // tests/scene_builders.h and tests/trace_test_support.h

// Every kernel this CPU runs once: None selects the portable one.
std::vector<PacketIsa> ray_kernel_isas() {
    std::vector<PacketIsa> isas;
    for (PacketIsa isa : {PacketIsa::Portable, PacketIsa::Sse2, PacketIsa::Avx2, PacketIsa::Avx512})
        if (packet_isa_available(isa)) isas.push_back(isa);
    return isas;
}

// Whether a packet lane's hit is the single-ray path's, field for field (t, u and v bit for bit).
::testing::AssertionResult same_hit(const Hit& got, const Hit& expected) {
    if (bits_of(got.t) == bits_of(expected.t) && got.object == expected.object && got.prim == expected.prim &&
        got.leaf == expected.leaf && got.lane == expected.lane && bits_of(got.u) == bits_of(expected.u) &&
        bits_of(got.v) == bits_of(expected.v))
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "hit " << describe(got) << " leaf " << got.leaf << " lane " << got.lane
                                         << ", the single-ray path's " << describe(expected) << " leaf "
                                         << expected.leaf << " lane " << expected.lane;
}

// Whether `got` is what intersect() finds for the ray alone (with t_min 0): both a miss, or the
// same hit as same_hit() compares them.
::testing::AssertionResult is_single_ray_hit(const Scene& scene, const Ray& ray, const Hit& got) {
    Hit expected;
    intersect(scene, ray, 0, expected);
    if (got.is_hit() != expected.is_hit())
        return ::testing::AssertionFailure() << (got.is_hit() ? "a hit" : "a miss") << " where the single-ray path finds "
                                             << (expected.is_hit() ? "a hit" : "a miss") << ", " << describe(ray, 0);
    if (!expected.is_hit()) return ::testing::AssertionSuccess();
    return same_hit(got, expected) << ", " << describe(ray, 0);
}

// Separate triangles (no shared vertices) of mixed sizes, some of them degenerate.
TriangleMesh soup_mesh(std::mt19937& rng, size_t count, float world) {
    TriangleMesh mesh = soup(rng, count, world, 2);
    for (size_t i = 3; i < count; i += 17) {  // collinear corners: zero area
        const Vec3f a = corner(mesh, i, 0), b = corner(mesh, i, 1);
        mesh.positions[mesh.indices[3 * i + 2]] = a + (b - a) * 0.5f;
    }
    for (size_t i = 5; i < count; i += 23) mesh.positions[mesh.indices[3 * i + 1]] = corner(mesh, i, 0);  // a repeated corner
    return mesh;
}

// Rays of every kind towards the triangles `ids` of `mesh`.
std::vector<Ray> rays_towards(const TriangleMesh& mesh, const std::vector<uint32_t>& ids, std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(-1, 1);
    std::uniform_int_distribution<size_t> pick(0, ids.size() - 1);
    std::vector<Ray> rays;
    for (int r = 0; r < count; ++r) {
        Ray ray;
        ray.origin = {u(rng) * 12, u(rng) * 12, u(rng) * 12};
        const uint32_t target = ids[pick(rng)];
        ray.direction = (r % 4 == 0 ? (corner(mesh, target, 0) + corner(mesh, target, 1) + corner(mesh, target, 2)) * (1.0f / 3)
                                    : shared_point_of(mesh, target, rng)) -
                        ray.origin;
        if (r % 7 == 1) ray.direction = Vec3f{u(rng), u(rng), u(rng)};
        if (r % 11 == 2) ray.direction.x = 0;
        if (r % 13 == 3) ray.direction = {0, 0, r % 2 ? -1.0f : 1.0f};
        if (r % 19 == 4) ray.direction = ray.direction * 1e-3f;  // not unit length
        rays.push_back(ray);
    }
    return rays;
}

// The kernels' own copy of their shared scalar pieces (they include it inside their own
// namespaces), to test watertight_axes directly.
namespace kernel_common {
#include "scene/kernel_common.inl"
}  // namespace kernel_common

// The kernels choose the watertight test's axes without a branch (a table indexed by the
// comparisons' bits: an occlusion ray's direction is as good as random, and a branch on it
// mispredicted about every other ray). Random rays almost never tie two components or carry a
// zero, an infinity or a NaN, so every combination of such values is checked here against
// make_watertight_ray, the scalar test's choice.
TEST(MeshKernel, TheWatertightAxesAreTheScalarTestsForEverySpecialDirection) {
    const float values[] = {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, -2.0f, 0.5f, -0.5f,
                            std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                            INFINITY, -INFINITY, 1e-40f, -1e-40f};
    int checked = 0;
    for (float x : values)
        for (float y : values)
            for (float z : values) {
                const WatertightRay expected = make_watertight_ray(Ray{{0, 0, 0}, {x, y, z}});
                const kernel_common::WatertightAxes got = kernel_common::watertight_axes(x, y, z);
                EXPECT_TRUE(got.kx == expected.kx && got.ky == expected.ky && got.kz == expected.kz)
                    << "direction (" << x << ", " << y << ", " << z << "): axes " << got.kx << got.ky << got.kz
                    << ", the scalar test's " << expected.kx << expected.ky << expected.kz;
                ++checked;
            }
    EXPECT_EQ(checked, 14 * 14 * 14);
}

// The single-ray kernel picks each axis's near bound from the sign of the direction's component
// instead of its inverse's (the division would hold up the first node's loads). Every special
// float is checked against the inverse that the box tests use (bvh.h's safe_inverse): -0 and
// tiny negatives have negative inverses, -inf's is -0 and a NaN's is NaN, neither below 0.
TEST(MeshKernel, TheNearBoundsSideIsTheInverseDirectionsSignForEverySpecialComponent) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float values[] = {0.0f, -0.0f, 1.0f, -1.0f, 1e-31f, -1e-31f, 1e-40f, -1e-40f,
                            std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                            INFINITY, -INFINITY, nan, -nan};
    int negative = 0;
    for (float d : values) {
        const bool expected = safe_inverse(d) < 0;
        EXPECT_EQ(kernel_common::inverse_is_negative(d), expected) << "component " << d << ", sign bit "
                                                                   << std::signbit(d);
        negative += expected ? 1 : 0;
    }
    EXPECT_EQ(negative, 5);  // -0, -1, -1e-31, -1e-40 and -max: not -inf, not -NaN
}

TEST(TriangleGroups, EveryKernelTestsAGroupBitForBitAsTheScalarTest) {
    std::mt19937 rng(52);
    std::uniform_real_distribution<float> u01(0, 1);
    const TriangleMesh grid = grid_mesh(rng, 12, 0.5f);
    const TriangleMesh soup = soup_mesh(rng, 60, 4);
    // Groups of every shape: the grid's (up to 8 triangles, 9-10 vertices: two registers of
    // vertices), small ones (a triangle or two), and the soup's (5 triangles, 15 vertices).
    struct Case {
        const TriangleMesh* mesh;
        std::vector<uint32_t> ids;
    };
    std::vector<Case> cases;
    for (uint32_t first = 0; first + 8 <= grid.triangle_count(); first += 37) {
        Case c{&grid, {}};
        for (uint32_t i = 0; i < 8; ++i) c.ids.push_back(first + i);
        cases.push_back(c);
    }
    cases.push_back({&grid, {5}});
    cases.push_back({&grid, {10, 11, 12}});
    {
        Case c{&soup, {}};
        for (uint32_t i = 0; i < soup.triangle_count(); ++i) c.ids.push_back(i);
        cases.push_back(c);
    }
    int hits = 0, tested = 0;
    for (const Case& c : cases) {
        const std::vector<GroupBlock> groups = groups_of(*c.mesh, c.ids);
        const std::vector<Ray> rays = rays_towards(*c.mesh, c.ids, rng, 300);
        for (size_t r = 0; r < rays.size(); ++r) {
            const Ray& ray = rays[r];
            const float t_min = r % 5 == 0 ? u01(rng) : (r % 31 == 0 ? -INFINITY : 0.0f);
            const WatertightRay w = make_watertight_ray(ray);  // the scalar test's
            const GroupBlock* end = groups.data() + groups.size() - kGroupPaddingBlocks;
            for (const GroupBlock* group = groups.data(); group < end; group = next_group(group)) {
                for (PacketIsa isa : ray_kernel_isas()) {
                    GroupLanes lanes;
                    mesh_ray_kernel(isa).test_group(group, ray, t_min, lanes);
                    EXPECT_EQ(lanes.hits >> group_triangle_count(group), 0u) << "hits past the group's triangles";
                    for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) {
                        const GroupTriangle tri = group_triangle(group, lane);
                        TriangleHit expected{};
                        const bool hit = intersect_triangle(w, tri.p0, tri.p1, tri.p2, t_min, expected);
                        const bool lane_hit = (lanes.hits >> lane) & 1u;
                        ++tested;
                        hits += hit;
                        ASSERT_EQ(lane_hit, hit) << packet_isa_name(isa) << ", triangle " << tri.id << ", "
                                                 << describe(ray, t_min);
                        if (!hit) continue;
                        ASSERT_EQ(bits_of(lanes.t[lane]), bits_of(expected.t)) << packet_isa_name(isa) << " t, " << describe(ray, t_min);
                        ASSERT_EQ(bits_of(lanes.u[lane]), bits_of(expected.u)) << packet_isa_name(isa) << " u, " << describe(ray, t_min);
                        ASSERT_EQ(bits_of(lanes.v[lane]), bits_of(expected.v)) << packet_isa_name(isa) << " v, " << describe(ray, t_min);
                    }
                }
            }
        }
    }
    EXPECT_GT(hits, tested / 40) << "the rays should find plenty of hits (" << tested << " tests)";
}

// ---------------------------------------------------------------------------------------------
// Scenes

// The closest hit by testing every triangle of the mesh with the scalar test.
Hit brute_force(const TriangleMesh& mesh, const Ray& ray, float t_min, uint32_t object) {
    Hit best;
    const WatertightRay w = make_watertight_ray(ray);
    for (uint32_t i = 0; i < mesh.triangle_count(); ++i) {
        TriangleHit h;
        if (!intersect_triangle(w, corner(mesh, i, 0), corner(mesh, i, 1), corner(mesh, i, 2), t_min, h)) continue;
        if (is_closer(h.t, object, i, best)) best = Hit{h.t, h.u, h.v, object, i};
    }
    return best;
}

TEST(MeshKernel, EveryKernelFindsTheBruteForceHitAndItsAnyHitAgrees) {
    std::mt19937 rng(53);
    std::uniform_real_distribution<float> u01(0, 1);
    TriangleMesh mesh = soup_mesh(rng, 1500, 6);
    const TriangleMesh grid = grid_mesh(rng, 20, 0.4f);  // shares vertices: groups of 8
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    for (const Vec3f& p : grid.positions) mesh.positions.push_back(p * 0.5f - Vec3f{5, 5, 0});
    for (uint32_t index : grid.indices) mesh.indices.push_back(base + index);
    const MeshShape shape = build_mesh_shape(mesh, 2);
    const MeshView view{shape.bvh.nodes.data(), shape.groups.data()};
    std::vector<uint32_t> ids;
    for (uint32_t i = 0; i < mesh.triangle_count(); ++i) ids.push_back(i);
    const std::vector<Ray> rays = rays_towards(mesh, ids, rng, 1500);
    int hits = 0;
    for (size_t r = 0; r < rays.size(); ++r) {
        const Ray& ray = rays[r];
        const float t_min = r % 6 == 0 ? u01(rng) * 4 : 0.0f;
        const Hit expected = brute_force(mesh, ray, t_min, 3);
        hits += expected.is_hit();
        for (PacketIsa isa : ray_kernel_isas()) {
            const MeshRayKernel& kernel = mesh_ray_kernel(isa);
            Hit hit;
            uint64_t boxes = 0;
            kernel.intersect(view, ray, t_min, 3, hit, &boxes);
            ASSERT_EQ(hit.is_hit(), expected.is_hit()) << packet_isa_name(isa) << ", " << describe(ray, t_min);
            EXPECT_GT(boxes, 0u);
            if (expected.is_hit()) {
                ASSERT_EQ(bits_of(hit.t), bits_of(expected.t)) << packet_isa_name(isa) << ", " << describe(ray, t_min);
                ASSERT_EQ(hit.prim, expected.prim) << packet_isa_name(isa) << ", " << describe(ray, t_min);
                ASSERT_EQ(bits_of(hit.u), bits_of(expected.u));
                ASSERT_EQ(bits_of(hit.v), bits_of(expected.v));
                ASSERT_EQ(hit.object, 3u);
                ASSERT_EQ(hit.lane, group_lane_of(&shape.groups[hit.leaf], hit.prim));
                ASSERT_LT(hit.lane, group_triangle_count(&shape.groups[hit.leaf]));
                // Any hit: nothing strictly before the closest hit, something just past it.
                ASSERT_FALSE(kernel.occluded(view, ray, t_min, expected.t)) << packet_isa_name(isa) << ", " << describe(ray, t_min);
                ASSERT_TRUE(kernel.occluded(view, ray, t_min, std::nextafter(expected.t, INFINITY)))
                    << packet_isa_name(isa) << ", " << describe(ray, t_min);
            } else {
                ASSERT_FALSE(kernel.occluded(view, ray, t_min, INFINITY)) << packet_isa_name(isa) << ", " << describe(ray, t_min);
            }
            if (expected.is_hit()) {
                // An equal t found before on another object: the object listed first keeps it.
                Hit tie{expected.t, 0, 0, 1, 0, 0};
                kernel.intersect(view, ray, t_min, 3, tie, nullptr);
                EXPECT_EQ(tie.object, 1u) << packet_isa_name(isa);
                tie = Hit{expected.t, 0, 0, 5, 0, 0};
                kernel.intersect(view, ray, t_min, 3, tie, nullptr);
                EXPECT_EQ(tie.object, 3u) << packet_isa_name(isa);
            }
        }
    }
    EXPECT_GT(hits, 500);
}

TEST(MeshShape, KeepsNoPositionsOrIndicesButKeepsTheFileNormals) {
    std::mt19937 rng(54);
    TriangleMesh mesh = grid_mesh(rng, 10, 0.3f);
    mesh.normals = {{0, 0, 1}, {0, 0.6f, 0.8f}, {0.6f, 0, 0.8f}};
    for (size_t i = 0; i < mesh.indices.size(); ++i) mesh.normal_indices.push_back(static_cast<uint32_t>(i % 3));
    const MeshShape shape = build_mesh_shape(mesh, 1);
    EXPECT_TRUE(shape.mesh.positions.empty());
    EXPECT_TRUE(shape.mesh.indices.empty());
    EXPECT_EQ(shape.mesh.normals, mesh.normals);
    EXPECT_EQ(shape.mesh.normal_indices, mesh.normal_indices);
    EXPECT_EQ(shape.triangle_count, mesh.triangle_count());

    // surface_at still interpolates the file's normals and gives flat ones where a face has none.
    SceneDesc desc = scene_desc();
    mesh.normal_indices[3 * 7] = kNoNormal;
    const int index = add_mesh(desc, mesh);
    desc.root->children.push_back(mesh_object(index));
    const Scene scene = build(std::move(desc));
    EXPECT_EQ(scene.triangle_count(), mesh.triangle_count());
    int smooth = 0, flat = 0;
    for (uint32_t i = 0; i < mesh.triangle_count(); ++i) {
        const Vec3f target = (corner(mesh, i, 0) + corner(mesh, i, 1) + corner(mesh, i, 2)) * (1.0f / 3);
        const Ray ray{target + Vec3f{0.01f, 0.02f, 5}, {-0.01f, -0.02f, -5}};
        Hit hit;
        intersect(scene, ray, 0, hit);
        ASSERT_TRUE(hit.is_hit());
        const uint32_t* n = &mesh.normal_indices[3 * size_t{hit.prim}];
        Vec3f expected = triangle_normal(corner(mesh, hit.prim, 0), corner(mesh, hit.prim, 1), corner(mesh, hit.prim, 2));
        if (n[0] != kNoNormal) {
            expected = normalize(mesh.normals[n[0]] * (1 - hit.u - hit.v) + mesh.normals[n[1]] * hit.u +
                                 mesh.normals[n[2]] * hit.v);
            ++smooth;
        } else {
            ++flat;
        }
        EXPECT_EQ(surface_at(scene, ray, hit).normal, expected) << "triangle " << hit.prim;
    }
    EXPECT_GT(smooth, 100);
    EXPECT_GT(flat, 0);
}

// ---------------------------------------------------------------------------------------------
// Packets

// Spheres, planes, a triangle and meshes, some of them transformed: every kind of instance.
Scene mixed_scene(std::mt19937& rng) {
    SceneDesc desc = scene_desc();
    const int soup = add_mesh(desc, soup_mesh(rng, 300, 3));
    const int grid = add_mesh(desc, grid_mesh(rng, 16, 0.5f));
    std::vector<ObjectDesc>& objects = desc.root->children;
    objects.push_back(mesh_object(soup));
    objects.push_back(transform(Mat4::translate({-8, -8, -2}) * Mat4::rotate({1, 1, 0}, 20), mesh_object(grid)));
    objects.push_back(sphere({2, 2, 1}, 1.5f));
    objects.push_back(transform(Mat4::translate({-3, 3, 0}) * Mat4::scale({0.5f, 2, 1}), sphere({0, 0, 0}, 1)));
    objects.push_back(triangle({-6, -6, -4}, {6, -6, -4}, {0, 6, -4.5f}));
    objects.push_back(plane({0, 0, 1}, -7));
    objects.push_back(transform(Mat4::scale({1, 1, 2}), mesh_object(soup)));
    return build(std::move(desc));
}

TEST(PacketOcclusion, EveryIsaBlocksExactlyTheRaysOccludedBlocks) {
    std::mt19937 rng(55);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    const Scene scene = mixed_scene(rng);
    int blocked_count = 0, total = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 300; ++packet) {
            const int count = 1 + packet % tracer.lanes();
            Ray rays[kMaxPacketLanes];
            float t_max[kMaxPacketLanes];
            // Shadow rays from points of the scene towards one point light, or one direction;
            // and every fourth packet incoherent: random origins and directions.
            const Vec3f light{u(rng) * 10, u(rng) * 10, 4 + 6 * u01(rng)};
            const Vec3f sun = normalize(Vec3f{u(rng), u(rng), 1});
            const Vec3f centre{u(rng) * 6, u(rng) * 6, u(rng) * 6};
            for (int k = 0; k < count; ++k) {
                const Vec3f from = centre + Vec3f{u(rng), u(rng), u(rng)} * (packet % 4 == 3 ? 6.0f : 1.0f);
                switch (packet % 4) {
                    case 0:  // towards a point light, up to it
                        rays[k] = {from, light - from};
                        t_max[k] = 1;
                        break;
                    case 1:  // towards the sun, unbounded
                        rays[k] = {from, sun};
                        t_max[k] = INFINITY;
                        break;
                    case 2:  // short rays: many end before anything
                        rays[k] = {from, Vec3f{u(rng), u(rng), u(rng)}};
                        t_max[k] = u01(rng) * 2;
                        break;
                    default:
                        rays[k] = {from, Vec3f{u(rng), u(rng), u(rng)}};
                        t_max[k] = k % 5 == 0 ? 0.0f : 30 * u01(rng);
                }
            }
            const float t_min = packet % 3 == 0 ? 0.05f : 0.0f;
            bool blocked[kMaxPacketLanes];
            tracer.occluded(rays, count, t_min, t_max, blocked);
            for (int k = 0; k < count; ++k) {
                const bool expected = occluded(scene, rays[k], t_min, t_max[k]);
                ASSERT_EQ(blocked[k], expected) << packet_isa_name(isa) << ", packet " << packet << ", lane " << k << ", "
                                                << describe(rays[k], t_min) << ", t_max " << t_max[k];
                blocked_count += expected;
                ++total;
            }
        }
    }
    EXPECT_GT(blocked_count, total / 5);
    EXPECT_LT(blocked_count, total * 4 / 5);
}

// Ambient-occlusion rays: every lane of a packet leaves one point of a bumpy mesh (inside a
// triangle, on an edge, at a vertex; on the surface or just off it), in directions over the
// hemisphere or the whole sphere, so a packet spans every octant and several watertight axis
// permutations, and its rays part within a few nodes. Lengths run from nothing to past the mesh.
TEST(PacketOcclusion, RaysFromOnePointInEveryDirectionAreBlockedExactlyAsOneByOne) {
    std::mt19937 rng(91);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    const TriangleMesh grid = grid_mesh(rng, 24, 0.6f);
    SceneDesc desc = scene_desc();
    const int id = add_mesh(desc, grid);
    desc.root->children.push_back(mesh_object(id));
    // A second sheet standing across the first, so that rays leaving it have walls in every direction.
    desc.root->children.push_back(
        transform(Mat4::translate({12, 4, -12}) * Mat4::rotate({1, 0, 0}, 90), mesh_object(id)));
    const Scene scene = build(std::move(desc));
    const size_t triangles = grid.indices.size() / 3;
    int blocked_count = 0, total = 0, mixed_packets = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 400; ++packet) {
            const size_t t = std::uniform_int_distribution<size_t>(0, triangles - 1)(rng);
            const Vec3f a = corner(grid, t, 0), b = corner(grid, t, 1), c = corner(grid, t, 2);
            float w1 = u01(rng), w2 = u01(rng) * (1 - w1);
            if (packet % 7 == 1) w2 = 0;                       // on an edge
            if (packet % 7 == 2) w1 = w2 = 0;                  // at a vertex
            Vec3f point = a + (b - a) * w1 + (c - a) * w2;
            const Vec3f normal = normalize(cross(b - a, c - a));
            if (packet % 3 != 0) point = point + normal * 1e-4f;  // just off the surface
            const int count = packet % 5 == 4 ? 1 + packet % tracer.lanes() : tracer.lanes();
            Ray rays[kMaxPacketLanes];
            float t_max[kMaxPacketLanes];
            unsigned octants = 0;
            for (int k = 0; k < count; ++k) {
                Vec3f direction{u(rng), u(rng), u(rng)};
                if (packet % 2 == 0 && dot(direction, normal) < 0) direction = direction - normal * (2 * dot(direction, normal));
                rays[k] = {point, direction};
                t_max[k] = k % 6 == 0 ? INFINITY : u01(rng) * 8;
                octants |= 1u << ((direction.x < 0) + 2 * (direction.y < 0) + 4 * (direction.z < 0));
            }
            mixed_packets += (octants & (octants - 1)) != 0;
            bool blocked[kMaxPacketLanes];
            tracer.occluded(rays, count, 0, t_max, blocked);
            for (int k = 0; k < count; ++k) {
                const bool expected = occluded(scene, rays[k], 0, t_max[k]);
                ASSERT_EQ(blocked[k], expected) << packet_isa_name(isa) << ", packet " << packet << ", lane " << k << ", "
                                                << describe(rays[k], 0) << ", t_max " << t_max[k];
                blocked_count += expected;
                ++total;
            }
        }
    }
    EXPECT_GT(mixed_packets, 300);
    EXPECT_GT(blocked_count, total / 10);
    EXPECT_LT(blocked_count, total * 9 / 10);
    std::printf("%d of %d rays blocked\n", blocked_count, total);
}

TEST(PacketIntersect, RaysThatPointDifferentWaysGetTheirSingleRayHits) {
    // Lanes whose dominant axes differ need different watertight permutations: the packet
    // kernels trace each set of lanes that share one.
    std::mt19937 rng(56);
    std::uniform_real_distribution<float> u(-1, 1);
    const Scene scene = mixed_scene(rng);
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 200; ++packet) {
            const int count = 1 + packet % tracer.lanes();
            Ray rays[kMaxPacketLanes];
            const Vec3f origin{u(rng) * 8, u(rng) * 8, 6};
            for (int k = 0; k < count; ++k) rays[k] = {packet % 2 ? origin : Vec3f{u(rng) * 8, u(rng) * 8, 6}, {u(rng), u(rng), u(rng)}};
            Hit hits[kMaxPacketLanes];
            tracer.intersect(rays, count, 0, hits);
            for (int k = 0; k < count; ++k) ASSERT_TRUE(is_single_ray_hit(scene, rays[k], hits[k])) << packet_isa_name(isa);
        }
    }
}

// Packets whose rays all go one way (every direction component keeps its sign) are walked as a
// frustum where the kernel has one (AVX2, AVX-512): bounds on every ray's slab distances, never
// tighter than one ray's own. Camera-like packets (one origin, directions a little apart) and
// shadow-like ones (origins spread, one direction or one target), from barely apart to far
// apart, at a bumpy sheet seen head-on and at a grazing angle: each lane gets exactly its
// single-ray hit, and its single-ray any-hit answer.
TEST(PacketIntersect, RaysThatGoOneWayGetTheirSingleRayHitsAndAnyHits) {
    std::mt19937 rng(57);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    SceneDesc desc = scene_desc();
    const int id = add_mesh(desc, grid_mesh(rng, 40, 0.7f));
    desc.root->children.push_back(mesh_object(id));
    desc.root->children.push_back(transform(Mat4::translate({0, 0, -3}) * Mat4::scale({0.5f, 0.5f, 1}), mesh_object(id)));
    const Scene scene = build(std::move(desc));
    int hit_count = 0, total = 0, blocked_count = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 400; ++packet) {
            const int count = packet % 3 == 0 ? 1 + packet % tracer.lanes() : tracer.lanes();
            const float spread = std::pow(10.0f, -4 + 4 * u01(rng));  // 1e-4 to 1
            const Vec3f target{20 + u(rng) * 22, 20 + u(rng) * 22, 0};
            const bool grazing = packet % 4 == 1;
            const Vec3f origin = grazing ? Vec3f{target.x - 30, target.y - 25 * u01(rng), 1.5f}
                                         : Vec3f{20 + u(rng) * 10, 20 + u(rng) * 10, 12};
            const Vec3f sun = normalize(target - origin);
            Ray rays[kMaxPacketLanes];
            float t_max[kMaxPacketLanes];
            for (int k = 0; k < count; ++k) {
                const Vec3f jitter = Vec3f{u(rng), u(rng), u(rng)} * spread;
                switch (packet % 3) {
                    case 0:  // one origin, directions a little apart: camera rays
                        rays[k] = {origin, sun + jitter * 0.1f};
                        break;
                    case 1:  // origins apart, one direction: shadow rays towards the sun
                        rays[k] = {origin + jitter * 5.0f, sun};
                        break;
                    default:  // origins apart, one target: shadow rays towards a point light
                        rays[k] = {origin + jitter * 5.0f, target - (origin + jitter * 5.0f)};
                }
                if (packet % 5 == 4) {  // |x| = |z| in every lane: watertight_axes's tie
                    const float m = 0.5f + 0.5f * u01(rng);
                    rays[k].direction = {m, (0.2f + 0.7f * u01(rng)) * m, -m};
                }
                t_max[k] = k % 3 == 0 ? INFINITY : u01(rng) * 40;
            }
            Hit hits[kMaxPacketLanes];
            tracer.intersect(rays, count, 0, hits);
            bool blocked[kMaxPacketLanes];
            tracer.occluded(rays, count, 0, t_max, blocked);
            for (int k = 0; k < count; ++k) {
                ASSERT_TRUE(is_single_ray_hit(scene, rays[k], hits[k])) << packet_isa_name(isa);
                ASSERT_EQ(blocked[k], occluded(scene, rays[k], 0, t_max[k]))
                    << packet_isa_name(isa) << ", " << describe(rays[k], 0) << ", t_max " << t_max[k];
                ++total;
                blocked_count += blocked[k];
                hit_count += hits[k].is_hit();
            }
        }
    }
    EXPECT_GT(hit_count, total / 2);
    EXPECT_LT(hit_count, total);
    EXPECT_GT(blocked_count, total / 4);
    EXPECT_LT(blocked_count, total);
}

// A packet from one origin is walked as a frustum unless its rays lie farther apart, where they
// reach the mesh's box, than kFrustumMaxFootprint of the mesh's leaves (a small image of a fine
// mesh); then each lane tests the boxes itself. Camera packets on both sides of that line: each
// lane gets exactly its single-ray hit.
TEST(PacketIntersect, CameraPacketsNarrowOrWideAgainstTheLeavesGetTheirSingleRayHits) {
    std::mt19937 rng(58);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    SceneDesc desc = scene_desc();
    desc.root->children.push_back(mesh_object(add_mesh(desc, grid_mesh(rng, 48, 0.3f))));
    const Scene scene = build(std::move(desc));
    const MeshShape& mesh = scene.meshes[0];
    ASSERT_GT(mesh.leaf_size, 0.5f);  // leaves of up to 8 triangles of a grid of unit squares
    ASSERT_LT(mesh.leaf_size, 4.0f);
    int narrow = 0, wide = 0, packets = 0, hit_count = 0, total = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 300; ++packet, ++packets) {
            const int count = tracer.lanes();
            const Vec3f origin{4 + 16 * u01(rng), 4 + 16 * u01(rng), 4 + 20 * u01(rng)};
            // Down z, up x and y in every lane: the rays go one way, as a frustum needs.
            const Vec3f centre{0.7f + 0.6f * u01(rng), 0.7f + 0.6f * u01(rng), -1};
            // Half the packets a pixel's width apart at most, half up to a small image's 4 pixels.
            const float spread = packet % 2 ? std::pow(10.0f, -4 + 2 * u01(rng)) : 0.1f + 0.55f * u01(rng);
            Ray rays[kMaxPacketLanes];
            float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int k = 0; k < count; ++k) {
                rays[k] = {origin, normalize(centre + Vec3f{u(rng), u(rng), 0} * spread)};
                for (int axis = 0; axis < 3; ++axis) {
                    lo[axis] = std::min(lo[axis], rays[k].direction[axis]);
                    hi[axis] = std::max(hi[axis], rays[k].direction[axis]);
                }
            }
            // The kernel's rule, for unit directions: the distance to the box times the widest
            // range of a component.
            const float widest = std::max(hi[0] - lo[0], std::max(hi[1] - lo[1], hi[2] - lo[2]));
            const Vec3f nearest = max(mesh.bounds.lower, min(origin, mesh.bounds.upper));
            (length(origin - nearest) * widest > kFrustumMaxFootprint * mesh.leaf_size ? wide : narrow) += 1;
            Hit hits[kMaxPacketLanes];
            tracer.intersect(rays, count, 0, hits);
            for (int k = 0; k < count; ++k) {
                ASSERT_TRUE(is_single_ray_hit(scene, rays[k], hits[k])) << packet_isa_name(isa);
                ++total;
                hit_count += hits[k].is_hit();
            }
        }
    }
    EXPECT_GT(narrow, packets / 4) << "leaf size " << mesh.leaf_size;
    EXPECT_GT(wide, packets / 10) << "leaf size " << mesh.leaf_size;
    EXPECT_GT(hit_count, total / 2);
}

// A block of a pinhole camera's rays, up to kMaxSharedPackets packets of 4x4 pixels, as the
// renderer makes them: where every object lies in one leaf of the instance BVH, the packets walk
// each untransformed mesh together and test everything else (planes, spheres) each on its own;
// elsewhere each packet traces alone. Blocks narrow and wide against the leaves, whole and cut
// short (the edge of an image), at one mesh alone, at a mesh with a sphere and a plane, at a mesh
// with a transformed copy, at 24 meshes and at 64 transformed copies, and blocks that cannot
// share (one ray from another origin, or going the other way): each ray gets exactly its
// single-ray hit.
TEST(PacketIntersect, BlocksOfCameraPacketsGetTheirSingleRayHitsWhetherTheyShareOneWalkOrNot) {
    std::mt19937 rng(59);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    auto mesh_alone = [&] {
        SceneDesc desc = scene_desc();
        desc.root->children.push_back(mesh_object(add_mesh(desc, grid_mesh(rng, 48, 0.3f))));
        return build(std::move(desc));
    };
    auto mesh_and_others = [&] {  // two objects in the instance BVH's one leaf, and a plane
        SceneDesc desc = scene_desc();
        desc.root->children.push_back(mesh_object(add_mesh(desc, grid_mesh(rng, 32, 0.6f))));
        desc.root->children.push_back(sphere({16, 16, 0}, 0.5f));  // inside the mesh's box: one leaf
        desc.root->children.push_back(plane({0, 0, 1}, -0.5f));
        return build(std::move(desc));
    };
    auto mesh_and_copy = [&] {  // a mesh and a transformed copy: an instance BVH of two leaves
        SceneDesc desc = scene_desc();
        const int id = add_mesh(desc, grid_mesh(rng, 32, 0.6f));
        desc.root->children.push_back(mesh_object(id));
        desc.root->children.push_back(transform(Mat4::translate({4, 3, 1.5f}) * Mat4::scale({0.5f, 0.5f, 1}), mesh_object(id)));
        desc.root->children.push_back(sphere({16, 16, 2}, 3));
        return build(std::move(desc));
    };
    auto many_meshes = [&] {
        SceneDesc desc = scene_desc();
        for (int i = 0; i < 24; ++i) {
            TriangleMesh mesh = grid_mesh(rng, 6, 0.6f);
            const Vec3f offset{static_cast<float>(i % 6) * 6.5f, static_cast<float>(i / 6) * 6.5f, u01(rng)};
            for (Vec3f& position : mesh.positions) position = position + offset;
            desc.root->children.push_back(mesh_object(add_mesh(desc, std::move(mesh))));
        }
        return build(std::move(desc));
    };
    auto many_copies = [&] {
        SceneDesc desc = scene_desc();
        const int id = add_mesh(desc, grid_mesh(rng, 8, 0.6f));
        for (int i = 0; i < 64; ++i) {
            const Vec3f offset{static_cast<float>(i % 8) * 4.0f, static_cast<float>(i / 8) * 4.0f, u01(rng)};
            desc.root->children.push_back(transform(Mat4::translate(offset) * Mat4::scale({0.5f, 0.5f, 1}), mesh_object(id)));
        }
        return build(std::move(desc));
    };
    const Scene scenes[5] = {mesh_alone(), mesh_and_others(), mesh_and_copy(), many_meshes(), many_copies()};
    // The first two share the walk (every object in one leaf); the others trace packet by packet.
    for (int i = 0; i < 5; ++i) ASSERT_EQ(scenes[i].instance_bvh.nodes[0].count != 0, i < 2) << "scene " << i;
    int hit_count = 0, total = 0;
    for (const Scene& scene : scenes)
        for (PacketIsa isa : packet_isas()) {
            const PacketTracer tracer(scene, isa);
            const int lanes = tracer.lanes();
            for (int block = 0; block < 200; ++block) {
                const int full = kMaxSharedPackets * lanes;
                const int count = block % 4 == 3 ? 1 + block % full : full;
                const Vec3f origin{4 + 16 * u01(rng), 4 + 16 * u01(rng), 4 + 20 * u01(rng)};
                const Vec3f centre{0.7f + 0.6f * u01(rng), 0.7f + 0.6f * u01(rng), -1};
                // A pixel's width from 1e-4 (far narrower than a leaf) to 0.05 (a small image).
                const float pixel = std::pow(10.0f, -4 + 2.7f * u01(rng));
                Ray rays[kMaxSharedPackets * kMaxPacketLanes];
                for (int k = 0; k < count; ++k) {
                    // Packets of 4 pixels by lanes / 4, side by side in the block, as the renderer makes them.
                    const int packet = k / lanes, within = k % lanes;
                    const int x = (packet % 2) * 4 + within % 4, y = (packet / 2) * (lanes / 4) + within / 4;
                    rays[k] = {origin, centre + Vec3f{static_cast<float>(x), static_cast<float>(y), 0} * pixel};
                }
                if (block % 10 == 7) rays[count - 1].origin.x += 1e-3f;  // one ray from elsewhere: no sharing
                if (block % 10 == 8) rays[count / 2].direction.x = -rays[count / 2].direction.x;  // one goes the other way
                Hit hits[kMaxSharedPackets * kMaxPacketLanes];
                tracer.intersect_packets(rays, count, 0, hits);
                for (int k = 0; k < count; ++k) {
                    ASSERT_TRUE(is_single_ray_hit(scene, rays[k], hits[k])) << packet_isa_name(isa);
                    ++total;
                    hit_count += hits[k].is_hit();
                }
            }
        }
    EXPECT_GT(hit_count, total / 2);
    EXPECT_LT(hit_count, total);
}

// A ray whose direction holds a NaN is outside every query's contract (scenes give finite
// directions), but it must not bring the kernels down: it misses, its any-hit query finds
// nothing, and the other rays of its packet or block get their single-ray answers. Camera,
// shadow and ambient-occlusion packets (and camera blocks), with a NaN in one ray's direction
// or in every ray's, in one component or in all three.
TEST(PacketIntersect, ARayWithANanDirectionMissesAndLeavesTheOtherRaysAlone) {
    std::mt19937 rng(60);
    std::uniform_real_distribution<float> u01(0, 1);
    SceneDesc desc = scene_desc();
    desc.root->children.push_back(mesh_object(add_mesh(desc, grid_mesh(rng, 48, 0.3f))));
    const Scene scene = build(std::move(desc));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    int hit_count = 0, total = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        const int lanes = tracer.lanes();
        for (int block = 0; block < 120; ++block) {
            const int count = block % 2 ? kMaxSharedPackets * lanes : lanes;
            const Vec3f origin{4 + 16 * u01(rng), 4 + 16 * u01(rng), 4 + 20 * u01(rng)};
            const Vec3f centre{0.7f + 0.6f * u01(rng), 0.7f + 0.6f * u01(rng), -1};
            Ray rays[kMaxSharedPackets * kMaxPacketLanes];
            // Camera rays (one origin), shadow rays towards the sun (origins apart, one direction),
            // or ambient-occlusion rays (one origin, every way).
            for (int k = 0; k < count; ++k) {
                const Vec3f step{static_cast<float>(k % 8), static_cast<float>(k / 8), 0};
                const Vec3f any_way{u01(rng) - 0.5f, u01(rng) - 0.5f, u01(rng) - 0.5f};
                rays[k] = block % 6 < 2   ? Ray{origin, centre + step * 1e-3f}
                          : block % 6 < 4 ? Ray{origin + step * 0.1f, centre}
                                          : Ray{Vec3f{origin.x, origin.y, 0.2f}, any_way};
            }
            const int bad = block % count;
            for (int k = 0; k < count; ++k) {
                if (k != bad && block % 5 != 4) continue;  // one ray, or (every fifth block) all of them
                if (block % 4 == 3) {
                    rays[k].direction = {nan, nan, nan};
                } else {
                    rays[k].direction[block % 4] = nan;  // x, y or z
                }
            }
            Hit hits[kMaxSharedPackets * kMaxPacketLanes];
            tracer.intersect_packets(rays, count, 0, hits);
            float t_max[kMaxPacketLanes];
            bool blocked[kMaxPacketLanes];
            for (int k = 0; k < lanes; ++k) t_max[k] = INFINITY;
            const int first = bad / lanes * lanes;  // the any-hit query of the packet that holds the bad ray
            const int in_packet = std::min(lanes, count - first);
            tracer.occluded(rays + first, in_packet, 0, t_max, blocked);
            EXPECT_FALSE(hits[bad].is_hit()) << packet_isa_name(isa) << ", block " << block;
            EXPECT_FALSE(blocked[bad - first]) << packet_isa_name(isa) << ", block " << block;
            for (int k = 0; k < count; ++k) {
                if (k == bad || block % 5 == 4) continue;
                ASSERT_TRUE(is_single_ray_hit(scene, rays[k], hits[k])) << packet_isa_name(isa);
                ++total;
                hit_count += hits[k].is_hit();
            }
            for (int k = 0; k < in_packet; ++k) {
                if (first + k == bad || block % 5 == 4) continue;
                ASSERT_EQ(blocked[k], occluded(scene, rays[first + k], 0, INFINITY)) << packet_isa_name(isa);
            }
        }
    }
    EXPECT_GT(hit_count, total / 2);
}

}  // namespace
}  // namespace raycast
