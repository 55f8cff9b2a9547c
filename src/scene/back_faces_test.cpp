// Tests for skipping back faces in any-hit queries (scene/back_faces.h): which meshes count as
// closed, that a node's cone never skips a triangle that faces the ray, that rays starting and
// ending outside a closed mesh get the same answers with and without skipping on every path,
// and which instances, cameras and lights allow it.
#include "scene/back_faces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/triangle.h"
#include "scene/build_scene.h"
#include "scene/camera.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"
#include "scene_builders.h"
#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // tests/scene_builders.h and tests/trace_test_support.h

// A closed UV sphere with every vertex moved along its radius by up to `bumpiness` of it: closed,
// outward, with faces turned every way around each vertex.
TriangleMesh bumpy_sphere(std::mt19937& rng, Vec3f centre, float radius, int rings, int segments, float bumpiness) {
    std::uniform_real_distribution<float> u(-1, 1);
    TriangleMesh mesh = sphere_mesh(centre, radius, rings, segments);
    for (Vec3f& p : mesh.positions) p = centre + (p - centre) * (1 + bumpiness * u(rng));
    return mesh;
}

TEST(MeshIsClosed, EveryEdgeUsedOnceEachWayIsClosedAndAnOpenOrInconsistentMeshIsNot) {
    EXPECT_TRUE(mesh_is_closed(cube_mesh(), 1));
    EXPECT_TRUE(mesh_is_closed(sphere_mesh({0, 0, 0}, 1, 7, 9), 2));
    std::mt19937 rng(3);
    EXPECT_FALSE(mesh_is_closed(grid_mesh(rng, 4, 0.1f), 1));  // a height field has a rim

    TriangleMesh missing = cube_mesh();  // one face's triangle gone: a hole
    missing.indices.resize(missing.indices.size() - 3);
    EXPECT_FALSE(mesh_is_closed(missing, 1));

    TriangleMesh flipped = cube_mesh();  // one triangle wound the other way: its edges run twice one way
    std::swap(flipped.indices[1], flipped.indices[2]);
    EXPECT_FALSE(mesh_is_closed(flipped, 1));

    TriangleMesh two = cube_mesh();  // two closed pieces are closed
    const uint32_t offset = static_cast<uint32_t>(two.positions.size());
    for (Vec3f p : cube_mesh().positions) two.positions.push_back(p + Vec3f{5, 0, 0});
    for (uint32_t i : cube_mesh().indices) two.indices.push_back(i + offset);
    EXPECT_TRUE(mesh_is_closed(two, 1));

    TriangleMesh fin = cube_mesh();  // a triangle and its reverse: no boundary between them
    fin.positions.push_back({3, 0, 0});
    fin.indices.insert(fin.indices.end(), {0, 1, 8, 1, 0, 8});
    EXPECT_TRUE(mesh_is_closed(fin, 1));

    EXPECT_FALSE(mesh_is_closed(TriangleMesh{}, 1));  // nothing: nothing to skip
}

// Every triangle under a node's child (its leaves' groups), as its stored corners.
void gather_triangles(const MeshShape& shape, uint32_t ref, std::vector<GroupTriangle>& out) {
    if (is_wide_leaf(ref)) {
        for (const GroupBlock* group = shape.groups.data() + (ref & kWidePayloadMask);; group = next_group(group)) {
            for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) out.push_back(group_triangle(group, lane));
            if (group_ends_leaf(group)) return;
        }
    }
    const WideBvhNode& node = shape.bvh.nodes[ref];
    for (uint32_t slot = 0; slot < node.child_count; ++slot) gather_triangles(shape, node.child[slot], out);
}

// n·d in double for a triangle's (unnormalised) normal: its sign is exact for float corners
// unless the triangle is a sliver, which build_normal_cones never lets a cone hold.
double facing(const GroupTriangle& t, Vec3f d) {
    const double e1[3] = {double(t.p1.x) - t.p0.x, double(t.p1.y) - t.p0.y, double(t.p1.z) - t.p0.z};
    const double e2[3] = {double(t.p2.x) - t.p0.x, double(t.p2.y) - t.p0.y, double(t.p2.z) - t.p0.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    return n[0] * d.x + n[1] * d.y + n[2] * d.z;
}

float length_as_kernels(Vec3f d) { return std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z); }

TEST(NormalCones, AChildIsSkippedOnlyForDirectionsAllItsTrianglesFaceAwayFrom) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1, 1);
    int skipped = 0, near_edge = 0, tested = 0;
    for (int mesh_index = 0; mesh_index < 4; ++mesh_index) {
        const float bumpiness = mesh_index == 0 ? 0.0f : 0.02f * static_cast<float>(mesh_index);
        const Scene scene = scene_of_mesh(bumpy_sphere(rng, {u(rng), u(rng), u(rng)}, 1 + 3 * std::fabs(u(rng)),
                                                       10 + 9 * mesh_index, 12 + 11 * mesh_index, bumpiness),
                                          2);
        const MeshShape& shape = scene.meshes[0];
        ASSERT_EQ(shape.cones.size(), shape.bvh.nodes.size());
        for (uint32_t node = 0; node < shape.bvh.nodes.size(); ++node) {
            const NodeCones& cones = shape.cones[node];
            for (uint32_t slot = 0; slot < shape.bvh.nodes[node].child_count; ++slot) {
                std::vector<GroupTriangle> triangles;
                gather_triangles(shape, shape.bvh.nodes[node].child[slot], triangles);
                const Vec3f axis{float(cones.axis[0][slot]), float(cones.axis[1][slot]), float(cones.axis[2][slot])};
                for (int k = 0; k < 40; ++k) {
                    // Directions around the axis, most near the edge of what the cone allows,
                    // of lengths from 1e-3 to 1e3.
                    Vec3f d = normalize(axis) + Vec3f{u(rng), u(rng), u(rng)} * (k < 10 ? 1.0f : 0.05f * float(k % 10));
                    d = d * std::pow(10.0f, 3 * u(rng));
                    const float length = length_as_kernels(d);
                    if (!faces_away(cones, slot, d, length)) continue;
                    ++skipped;
                    const float dot = axis.x * d.x + axis.y * d.y + axis.z * d.z;
                    if (dot < (float(cones.reach[slot]) + 2) * length) ++near_edge;
                    for (const GroupTriangle& t : triangles) {
                        ++tested;
                        ASSERT_GT(facing(t, d), 0) << "node " << node << " slot " << slot << " triangle " << t.id;
                    }
                }
            }
        }
    }
    // The cones are not vacuous, and the directions probed their edges.
    EXPECT_GT(skipped, 2000);
    EXPECT_GT(near_edge, 100);
    EXPECT_GT(tested, 20000);
}

TEST(NormalCones, OnlyClosedMeshesHaveThemAndAChildWithASliverCannotBeSkipped) {
    std::mt19937 rng(5);
    EXPECT_TRUE(scene_of_mesh(grid_mesh(rng, 6, 0.2f)).meshes[0].cones.empty());
    EXPECT_FALSE(scene_of_mesh(cube_mesh()).meshes[0].cones.empty());
    // A closed mesh with a sliver (a corner 1e-12 off its opposite edge's line, so |n| is 2e-12
    // of |e1||e2|): its leaf, and so the root's every child that holds it, get kNoCone.
    TriangleMesh tent;
    tent.positions = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1e-12f, 0}, {0.5f, 0.3f, 1}};
    tent.indices = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3};
    const Scene scene = scene_of_mesh(tent);
    ASSERT_TRUE(mesh_is_closed(tent, 1));
    const MeshShape& shape = scene.meshes[0];
    ASSERT_FALSE(shape.cones.empty());
    bool sliver_seen = false;
    for (uint32_t slot = 0; slot < shape.bvh.nodes[0].child_count; ++slot) {
        std::vector<GroupTriangle> triangles;
        gather_triangles(shape, shape.bvh.nodes[0].child[slot], triangles);
        for (const GroupTriangle& t : triangles)
            if (t.id == 0) {
                sliver_seen = true;
                EXPECT_EQ(shape.cones[0].reach[slot], kNoCone);
            }
    }
    EXPECT_TRUE(sliver_seen);
}

// Rays that start and end outside closed meshes: shadow rays from points just off one's surface
// on the outside towards the sun or a light outside every box, and rays between random points
// outside the boxes. Skipping changes none of their answers, on any path, with meshes turned
// inside out too (a ray enters those through faces that face away from it, and leaves through
// faces that face it).
TEST(BackFaceSkipping, RaysBetweenPointsOutsideAClosedMeshGetTheSameAnswersOnEveryPath) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    SceneDesc desc = scene_desc();
    desc.root->children.push_back(mesh_object(add_mesh(desc, bumpy_sphere(rng, {0, 0, 0}, 2, 40, 50, 0.06f))));
    desc.root->children.push_back(mesh_object(add_mesh(desc, bumpy_sphere(rng, {3.5f, 1, 0}, 1, 20, 24, 0.1f))));
    desc.root->children.push_back(mesh_object(add_mesh(desc, cube_mesh())));  // inside the big sphere
    desc.root->children.push_back(
        mesh_object(add_mesh(desc, inside_out(bumpy_sphere(rng, {-3.5f, -1, 0.5f}, 1.2f, 20, 24, 0.1f)))));
    TriangleMesh hollow = inside_out(bumpy_sphere(rng, {0, -3.8f, 0}, 1.1f, 16, 20, 0.05f));  // a shell: the
    const TriangleMesh outer = bumpy_sphere(rng, {0, -3.8f, 0}, 1.4f, 16, 20, 0.05f);         // outer side out,
    const uint32_t base = static_cast<uint32_t>(hollow.positions.size());                      // the inner in
    hollow.positions.insert(hollow.positions.end(), outer.positions.begin(), outer.positions.end());
    for (uint32_t i : outer.indices) hollow.indices.push_back(base + i);
    desc.root->children.push_back(mesh_object(add_mesh(desc, hollow)));
    const Scene scene = scene_with(std::move(desc));
    for (const MeshShape& mesh : scene.meshes) ASSERT_FALSE(mesh.cones.empty());
    const std::vector<uint8_t> all(scene.instances.size(), 1);
    int blocked_count = 0, total = 0;
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        for (int packet = 0; packet < 400; ++packet) {
            const int count = 1 + packet % tracer.lanes();
            Ray rays[kMaxPacketLanes];
            float t_max[kMaxPacketLanes];
            bool may_skip[kMaxPacketLanes];
            const Vec3f sun = normalize(Vec3f{u(rng), u(rng), u(rng)});
            const Vec3f light = normalize(Vec3f{u(rng), u(rng), u(rng)}) * 9.0f;  // outside every box
            const Vec3f centre = normalize(Vec3f{u(rng), u(rng), u(rng)}) * 2.0f;
            for (int k = 0; k < count; ++k) {
                // A point of the big sphere's surface near `centre`, found by a ray from outside,
                // moved off it towards the outside (as a shadow ray leaves a camera hit).
                const Vec3f towards = normalize(centre + Vec3f{u(rng), u(rng), u(rng)} * 0.3f);
                const Ray probe{towards * 6.0f, -towards};
                Hit hit;
                intersect(scene, probe, 0, hit);
                ASSERT_TRUE(hit.is_hit());
                const SurfacePoint surface = surface_at(scene, probe, hit);
                const Vec3f outward = dot(surface.geometric_normal, probe.direction) < 0 ? surface.geometric_normal
                                                                                         : -surface.geometric_normal;
                const Vec3f origin = surface.position + outward * 1e-4f;
                switch (packet % 3) {
                    case 0:
                        rays[k] = {origin, sun};
                        t_max[k] = INFINITY;
                        break;
                    case 1:
                        rays[k] = {origin, normalize(light - origin)};
                        t_max[k] = length(light - origin);
                        break;
                    default: {  // between two points outside the boxes, or from one on for ever
                        const Vec3f from = normalize(Vec3f{u(rng), u(rng), u(rng)}) * (7 + u01(rng));
                        const Vec3f to = normalize(Vec3f{u(rng), u(rng), u(rng)}) * (7 + u01(rng));
                        const float scale = 0.5f + u01(rng);
                        rays[k] = {from, (to - from) * scale};
                        t_max[k] = k % 2 ? INFINITY : 1 / scale;
                    }
                }
                may_skip[k] = k % 5 != 4;
            }
            bool blocked[kMaxPacketLanes];
            tracer.occluded(rays, count, 0, t_max, blocked, {all.data(), may_skip});
            for (int k = 0; k < count; ++k) {
                const bool expected = occluded(scene, rays[k], 0, t_max[k]);
                ASSERT_EQ(blocked[k], expected) << packet_isa_name(isa) << ", packet " << packet << ", lane " << k << ", "
                                                << describe(rays[k], 0) << ", t_max " << t_max[k];
                ASSERT_EQ(occluded(scene, rays[k], 0, t_max[k], all.data()), expected)
                    << "one by one, packet " << packet << ", lane " << k;
                blocked_count += expected;
                ++total;
            }
        }
    }
    EXPECT_GT(blocked_count, total / 10);
    EXPECT_LT(blocked_count, total * 9 / 10);
}

// A ray from inside a closed mesh leaves through a back face: testing every face finds it,
// skipping does not (which is why the caller must vouch for both ends). This is what shows that
// each path skips at all. The sphere is smooth, so that every leaf near where the rays leave
// faces the way they go (a leaf with a face turned against them is tested, and may block).
TEST(BackFaceSkipping, ARayLeavingAClosedMeshFromInsideIsBlockedOnlyWithoutSkipping) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1, 1);
    const Scene scene = scene_of_mesh(sphere_mesh({0, 0, 0}, 2, 30, 40));
    const std::vector<uint8_t> all(1, 1);
    for (PacketIsa isa : packet_isas()) {
        const PacketTracer tracer(scene, isa);
        Ray rays[kMaxPacketLanes];
        float t_max[kMaxPacketLanes];
        bool may_skip[kMaxPacketLanes], blocked[kMaxPacketLanes];
        const int count = tracer.lanes();
        const Vec3f direction = normalize(Vec3f{u(rng), u(rng), u(rng)});
        for (int k = 0; k < count; ++k) {
            rays[k] = {Vec3f{u(rng), u(rng), u(rng)} * 0.5f, direction};
            t_max[k] = INFINITY;
            may_skip[k] = k % 2 == 0;
        }
        tracer.occluded(rays, count, 0, t_max, blocked, {all.data(), may_skip});
        for (int k = 0; k < count; ++k) {
            EXPECT_TRUE(occluded(scene, rays[k], 0, t_max[k]));
            EXPECT_EQ(occluded(scene, rays[k], 0, t_max[k], all.data()), false) << "lane " << k;
            EXPECT_EQ(blocked[k], !may_skip[k]) << packet_isa_name(isa) << ", lane " << k;
        }
    }
}

Camera camera_at(Vec3f center) {
    CameraDesc desc = perspective(center, normalize(-center), {0, 1, 0}, 40, 16, 16);
    return make_camera(desc, 16, 16, Conventions::course());
}

TEST(BackFacesSkippable, OnlyUntransformedClosedMeshesWithTheCameraAndTheLightOutsideTheirBoxes) {
    SceneDesc desc = scene_desc();
    const int cube = add_mesh(desc, cube_mesh());  // [-1, 1]³
    std::mt19937 rng(2);
    const int open = add_mesh(desc, grid_mesh(rng, 3, 0.1f));
    desc.root->children.push_back(mesh_object(cube));                                          // 0: skippable
    desc.root->children.push_back(transform(Mat4::translate({5, 0, 0}), mesh_object(cube)));  // 1: transformed
    desc.root->children.push_back(mesh_object(open));                                          // 2: not closed
    desc.root->children.push_back(sphere({0, 5, 0}, 1));                                       // 3: not a mesh
    const Scene scene = scene_with(std::move(desc));
    Light sun;
    sun.kind = Light::Kind::Directional;
    sun.direction = normalize(Vec3f{0, -1, -1});
    const std::vector<uint8_t> expected{1, 0, 0, 0};
    const SkippableBackFaces for_sun = back_faces_skippable(scene, camera_at({0, 0, 10}), sun);
    EXPECT_EQ(for_sun.instances, expected);
    EXPECT_EQ(for_sun.light_clearance, INFINITY);
    EXPECT_TRUE(back_faces_skippable(scene, camera_at({0.5f, 0.5f, 0.5f}), sun).instances.empty());  // inside the box
    // Just outside the box is outside for the camera (exactly on a face is not: a strict test);
    // a light needs a thousandth of the largest magnitude about (here 1e-2 of 10).
    EXPECT_EQ(back_faces_skippable(scene, camera_at({0, 0, 1.0001f}), sun).instances, expected);
    Light lamp;
    lamp.kind = Light::Kind::Point;
    lamp.position = {0, 3, 0};
    const SkippableBackFaces for_lamp = back_faces_skippable(scene, camera_at({0, 0, 10}), lamp);
    EXPECT_EQ(for_lamp.instances, expected);
    // 2 outside the box (its bounds are padded by a few ulps), less 1e-5 of the magnitude, 10.
    EXPECT_NEAR(for_lamp.light_clearance, 2 - 1e-4f, 1e-6f);
    lamp.position = {0, 0.5f, 0};  // inside
    EXPECT_TRUE(back_faces_skippable(scene, camera_at({0, 0, 10}), lamp).instances.empty());
    lamp.position = {0, 1.005f, 0};  // outside, but by less than the margin
    EXPECT_TRUE(back_faces_skippable(scene, camera_at({0, 0, 10}), lamp).instances.empty());
    lamp.position = {0, 1.02f, 0};
    EXPECT_EQ(back_faces_skippable(scene, camera_at({0, 0, 10}), lamp).instances, expected);

    // Cameras whose rays do not all start at one point outside, from t = 0: none.
    Camera lens = camera_at({0, 0, 10});
    lens.lens_radius = 0.1f;
    EXPECT_TRUE(back_faces_skippable(scene, lens, sun).instances.empty());
    Camera late = camera_at({0, 0, 10});
    late.t_min = 0.5f;
    EXPECT_TRUE(back_faces_skippable(scene, late, sun).instances.empty());
    Camera orthographic = camera_at({0, 0, 10});
    orthographic.projection = Camera::Projection::Orthographic;
    EXPECT_TRUE(back_faces_skippable(scene, orthographic, sun).instances.empty());
    Camera lost = camera_at({0, 0, 10});
    lost.center = {NAN, 0, 10};
    EXPECT_TRUE(back_faces_skippable(scene, lost, sun).instances.empty());
}

TEST(EndsClearOfBoxes, AShadowRayEndsWithinThreeOffsetsAndATenThousandthOfItsLengthOfTheLight) {
    SkippableBackFaces skippable;
    skippable.instances = {1};
    EXPECT_TRUE(ends_clear_of_boxes(skippable, 1, INFINITY));  // a sun: the ray goes on for ever
    skippable.light_clearance = 1;
    EXPECT_TRUE(ends_clear_of_boxes(skippable, 0.3f, 1000));    // 0.9 + 0.01 < 1
    EXPECT_FALSE(ends_clear_of_boxes(skippable, 0.33f, 1000));  // 0.99 + 0.01
    EXPECT_FALSE(ends_clear_of_boxes(skippable, 0.1f, 1e5f));   // 0.3 + 1
    EXPECT_FALSE(ends_clear_of_boxes(skippable, NAN, 1));
    EXPECT_FALSE(ends_clear_of_boxes(skippable, 0.1f, NAN));
}

TEST(OriginOnCameraSide, TheShadowRayMustLeaveThePlaneOnTheSideTheCameraRayCameFrom) {
    const Vec3f n{0, 0, 1};
    EXPECT_TRUE(origin_on_camera_side(n, {0, 1, 1}, {0, 0, 1}));     // both above
    EXPECT_TRUE(origin_on_camera_side(n, {0, 1, -1}, {0, 1, -1}));   // both below
    EXPECT_FALSE(origin_on_camera_side(n, {0, 1, -1}, {0, 0, 1}));   // light below, camera above
    EXPECT_FALSE(origin_on_camera_side(n, {0, 1, 1}, {0, 1, -1}));   // light above, camera below
    EXPECT_TRUE(origin_on_camera_side(n, {0, 1, 0}, {0, 0, 1}));     // a light in the plane: moved up, as offset_ray_origin_by moves it
    EXPECT_FALSE(origin_on_camera_side(n, {0, 1, 0}, {0, 0, -1}));
    EXPECT_FALSE(origin_on_camera_side(n, {0, 1, 1}, {0, 1, 0}));    // a camera ray along the plane
    EXPECT_FALSE(origin_on_camera_side(n, {0, 1, 1}, {0, 0, NAN}));
    // A normal not of unit length: the ray would start that length times its offset off the hit.
    EXPECT_FALSE(origin_on_camera_side({0, 0, 1e-24f}, {0, 1, 1}, {0, 0, 1}));
    EXPECT_FALSE(origin_on_camera_side({0, 0, 0.7f}, {0, 1, 1}, {0, 0, 1}));
    EXPECT_TRUE(origin_on_camera_side({0, 0, 0.75f}, {0, 1, 1}, {0, 0, 1}));
}

}  // namespace
}  // namespace raycast
