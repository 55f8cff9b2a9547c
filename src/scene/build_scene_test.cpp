// build_scene (scene/build_scene.h): from a SceneDesc made in code (or, where the file's order of
// transform items matters, from scene text) to the flat scene, checked through intersect() and
// surface_at() against hand-worked hits: non-uniform scales with normals by the inverse
// transpose, the order of composed transforms, t for non-unit directions (course-format.md
// §a "Transform"), one stored copy of a mesh used twice, singular transforms refused with a
// located message, planes moved to world space, and the MaterialIndex of every object.
#include "scene/build_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "base/error.h"
#include "geometry/triangle.h"
#include "scene/intersect_packet.h"
#include "sceneio/load_scene.h"
#include "scene_builders.h"

namespace raycast {
namespace {

using namespace test;  // the scene builders (tests/scene_builders.h)

void expect_vec_near(Vec3f actual, Vec3f expected, float tolerance = 1e-5f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << "x";
    EXPECT_NEAR(actual.y, expected.y, tolerance) << "y";
    EXPECT_NEAR(actual.z, expected.z, tolerance) << "z";
}

SceneDesc scene_with(ObjectDesc root, int materials = 1) {
    SceneDesc desc;
    desc.file = "code.txt";
    CameraDesc camera;
    camera.center = {0, 0, 10};
    camera.angle_degrees = 30;
    camera.width = 8;
    camera.height = 8;
    desc.camera = camera;
    desc.materials.resize(static_cast<size_t>(materials));
    desc.root = std::move(root);
    return desc;
}

// The closest hit along a ray, and what shading sees there.
struct Traced {
    bool hit = false;
    float t = 0;
    Vec3f position, normal;
    uint32_t material = 0, object = 0;
};

Traced trace(const Scene& scene, Vec3f origin, Vec3f direction) {
    const Ray ray{origin, direction};
    Hit hit;
    intersect(scene, ray, 0, hit);
    Traced result;
    if (!hit.is_hit()) return result;
    const SurfacePoint surface = surface_at(scene, ray, hit);
    result = {true, hit.t, surface.position, surface.normal, surface.material, hit.object};
    return result;
}

TEST(BuildSceneTest, NonUniformlyScaledSphereHitAndNormalByInverseTranspose) {
    // Scale 2 1 1 of the unit sphere: the ellipsoid x²/4 + y² + z² = 1.
    const Scene scene = build_scene(scene_with(transform(Mat4::scale({2, 1, 1}), sphere({0, 0, 0}, 1))), {});
    ASSERT_EQ(scene.object_from_world.size(), 1u);
    // Ray down −z at x = 1: 1/4 + z² = 1, z = √0.75; t = 5 − √0.75 = 4.1339746.
    // Normal: the gradient (x/2, 2y, 2z) = (0.5, 0, 1.7320508), normalised by √3.25:
    // (0.2773501, 0, 0.9607689). (M⁻¹)ᵀ of the object normal (0.5, 0, √0.75) gives the same:
    // diag(0.5, 1, 1)·(0.5, 0, 0.866) = (0.25, 0, 0.866), normalised.
    Traced hit = trace(scene, {1, 0, 5}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 4.1339746f, 1e-5);
    expect_vec_near(hit.position, {1, 0, 0.8660254f});
    expect_vec_near(hit.normal, {0.2773501f, 0, 0.9607689f});
    // Off both axes, at (0.6, 0.3): 0.09 + 0.09 + z² = 1, z = √0.82 = 0.9055385; gradient ∝ (x/4, y, z).
    hit = trace(scene, {0.6f, 0.3f, 5}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 5 - 0.9055385f, 1e-5);
    const double g[3] = {0.15, 0.3, std::sqrt(0.82)};
    const double g_len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    expect_vec_near(hit.normal, {static_cast<float>(g[0] / g_len), static_cast<float>(g[1] / g_len),
                                 static_cast<float>(g[2] / g_len)});
    // The ellipsoid reaches x = ±2 (a ray at x = 1.9 hits, one at x = 2.1 misses) but only y = ±1.
    EXPECT_TRUE(trace(scene, {1.9f, 0, 5}, {0, 0, -1}).hit);
    EXPECT_FALSE(trace(scene, {2.1f, 0, 5}, {0, 0, -1}).hit);
    EXPECT_FALSE(trace(scene, {0, 1.1f, 5}, {0, 0, -1}).hit);
    // From the side: hits x = 2 at t = 3.
    hit = trace(scene, {5, 0, 0}, {-1, 0, 0});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 3, 1e-5);
    expect_vec_near(hit.normal, {1, 0, 0});
}

TEST(BuildSceneTest, TIsTheRayParameterForNonUnitDirectionsThroughTransforms) {
    // The same ellipsoid; t scales inversely with the length of the direction, the hit point does not.
    const Scene scene = build_scene(scene_with(transform(Mat4::scale({2, 1, 1}), sphere({0, 0, 0}, 1))), {});
    for (float length_factor : {0.5f, 1.0f, 2.0f, 7.0f}) {
        const Traced hit = trace(scene, {1, 0, 5}, {0, 0, -length_factor});
        ASSERT_TRUE(hit.hit) << length_factor;
        EXPECT_NEAR(hit.t, 4.1339746f / length_factor, 1e-5) << length_factor;
        expect_vec_near(hit.position, {1, 0, 0.8660254f});
        expect_vec_near(hit.normal, {0.2773501f, 0, 0.9607689f});
    }
    // An oblique non-unit direction (3, 0, −4)·0.5 from (−1, 0, 5) towards the untransformed
    // sphere of radius 1 translated to (1, 0, 1): by hand the unit ray (0.6, 0, −0.8) meets it at
    // distance s with |(−2 + 0.6s, 0, 4 − 0.8s)|² = 1: s² − 8.8s + 19 = 0, s = 4.4 − √0.36 = 3.8;
    // with |d| = 2.5 the parameter is t = 3.8/2.5 = 1.52.
    const Scene moved = build_scene(scene_with(transform(Mat4::translate({1, 0, 1}), sphere({0, 0, 0}, 1))), {});
    const Traced hit = trace(moved, {-1, 0, 5}, {1.5f, 0, -2});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 1.52f, 1e-5);
    expect_vec_near(hit.position, {-1 + 1.5f * 1.52f, 0, 5 - 2 * 1.52f});
    expect_vec_near(hit.normal, hit.position - Vec3f{1, 0, 1});
}

TEST(BuildSceneTest, SurfaceOfRevolutionIsPlacedByItsTransformAndCurvesAddNothing) {
    // The cylinder x = 1, y ∈ [−1.5, 1.5] (a cubic Bezier of equally spaced points), stretched
    // ×2 along x and moved to x = 2: an elliptic cylinder with half-axes 2 (x) and 1 (z). A curve
    // beside it is not a surface and adds no instance.
    const Curve cylinder{CurveType::Bezier, {{1, -1.5f, 0}, {1, -0.5f, 0}, {1, 0.5f, 0}, {1, 1.5f, 0}}};
    const Scene scene = build_scene(
        scene_with(group({curve_object(cylinder),
                          transform(Mat4::translate({2, 0, 0}) * Mat4::scale({2, 1, 1}), rev_surface(cylinder))})),
        {});
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_EQ(scene.instances[0].kind, ShapeKind::RevSurface);
    // The instance box is the cylinder's: x ∈ [0, 4], y ∈ [−1.5, 1.5], z ∈ [−1, 1] (plus a pad of 1/65536).
    const Bounds3f box = scene.instance_bvh.nodes[0].bounds;
    expect_vec_near(box.lower, {0, -1.5f, -1}, 1e-3f);
    expect_vec_near(box.upper, {4, 1.5f, 1}, 1e-3f);
    // Front (z = 1) and side (x = 4), with normals along the axes.
    Traced hit = trace(scene, {2, 0, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 9, 1e-5);
    expect_vec_near(hit.normal, {0, 0, 1});
    hit = trace(scene, {10, 0.5f, 0}, {-2, 0, 0});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 3, 1e-5);
    expect_vec_near(hit.normal, {1, 0, 0});
    // At the object's θ = 45° the point is (2 + √2, y, √2/2); the object normal (cos θ, 0, sin θ)
    // goes through the inverse transpose, diag(1/2, 1, 1): (1, 0, 2)/√5.
    hit = trace(scene, {2 + std::sqrt(2.0f), 0, 10}, {0, -0.1f, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 10 - std::sqrt(0.5f), 1e-5);
    expect_vec_near(hit.normal, Vec3f{1, 0, 2} * (1 / std::sqrt(5.0f)));
    // Shadow rays: from the axis outwards, the wall is 2 away.
    EXPECT_TRUE(occluded(scene, {{2, 0, 0}, {1, 0, 0}}, 0, 2.5f));
    EXPECT_FALSE(occluded(scene, {{2, 0, 0}, {1, 0, 0}}, 0, 1.5f));
    // Above the open top, nothing.
    EXPECT_FALSE(trace(scene, {2, 1.6f, 10}, {0, 0, -1}).hit);
}

TEST(BuildSceneTest, NestedTransformsComposeOuterTimesInner) {
    // Outer Translate 3 0 0 around inner ZRotate 90: the sphere at (1, 0, 0) is rotated to (0, 1, 0)
    // first, then moved to (3, 1, 0).
    const ObjectDesc ball = sphere({1, 0, 0}, 0.5f);
    const Scene scene =
        build_scene(scene_with(transform(Mat4::translate({3, 0, 0}), transform(Mat4::rotate_z(90), ball))), {});
    Traced hit = trace(scene, {3, 1, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 9.5f, 1e-5);
    // Off-centre by 0.4 in x: z = √(0.25 − 0.16) = 0.3, t = 9.7, normal (0.4, 0, 0.3)/0.5.
    hit = trace(scene, {3.4f, 1, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 9.7f, 1e-5);
    expect_vec_near(hit.normal, {0.8f, 0, 0.6f});
    EXPECT_FALSE(trace(scene, {0, 4, 10}, {0, 0, -1}).hit);
    // The other nesting rotates the moved sphere: (1, 0, 0) → (4, 0, 0) → (0, 4, 0).
    const Scene other =
        build_scene(scene_with(transform(Mat4::rotate_z(90), transform(Mat4::translate({3, 0, 0}), ball))), {});
    EXPECT_FALSE(trace(other, {3, 1, 10}, {0, 0, -1}).hit);
    hit = trace(other, {0, 4, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 9.5f, 1e-5);
}

const char* const kCameraAndMaterials =
    "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 8 height 8 }\n"
    "Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }\n"
    "Materials { numMaterials 3\n"
    "  Material { diffuseColor 1 0 0 }\n"
    "  Material { diffuseColor 0 1 0 }\n"
    "  PhongMaterial { diffuseColor 0 0 1 specularColor 1 1 1 }\n"
    "}\n";

TEST(BuildSceneTest, TransformItemsFromTheFileApplyTheLastListedFirst) {
    // course-format.md: M = T1·T2·…: `Translate 3 0 0 ZRotate 90` rotates first, then translates,
    // so the sphere at (1, 0, 0) ends at (3, 1, 0) (scene04's Translate-then-Scale reads the same way).
    const std::string text = std::string(kCameraAndMaterials) +
                             "Group { numObjects 2\n"
                             "  MaterialIndex 0\n"
                             "  Transform { Translate 3 0 0 ZRotate 90 Sphere { center 1 0 0 radius 0.5 } }\n"
                             "  Transform { ZRotate 90 Translate 3 0 0 Sphere { center 1 0 0 radius 0.5 } }\n"
                             "}\n";
    const Scene scene = build_scene(load_scene_text(text, "order.txt"), {});
    Traced hit = trace(scene, {3, 1, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.object, 0u);
    EXPECT_NEAR(hit.t, 9.5f, 1e-5);
    hit = trace(scene, {0, 4, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.object, 1u);
    EXPECT_NEAR(hit.t, 9.5f, 1e-5);
    // Nothing at (4, 0, 0), where translating without rotating would put the sphere.
    EXPECT_FALSE(trace(scene, {4, 0, 10}, {0, 0, -1}).hit);
}

TEST(BuildSceneTest, MeshUsedByTwoTransformsIsStoredOnce) {
    SceneDesc desc = scene_with(group({transform(Mat4::translate({-3, 0, 0}), mesh_object(0)),
                                       transform(Mat4::translate({3, 0, 0}) * Mat4::scale({0.5f, 0.5f, 0.5f}),
                                                 mesh_object(0)),
                                       mesh_object(0)}));
    desc.meshes.push_back({"cube.obj", cube_mesh()});
    desc.meshes.push_back({"unused.obj", cube_mesh()});  // never referenced: never built
    const Scene scene = build_scene(std::move(desc), {});
    ASSERT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.meshes[0].triangle_count, 12u);
    ASSERT_EQ(scene.instances.size(), 3u);
    for (const Instance& inst : scene.instances) {
        EXPECT_EQ(inst.kind, ShapeKind::Mesh);
        EXPECT_EQ(inst.shape, 0u);
    }
    EXPECT_EQ(scene.object_from_world.size(), 2u);  // the third use has no transform
    EXPECT_EQ(scene.instances[2].transform, kNoTransform);
    // Each copy is where its transform puts it: front faces z = 1, z = 0.5 and z = 1.
    Traced hit = trace(scene, {-3, 0.2f, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.object, 0u);
    EXPECT_NEAR(hit.t, 9, 1e-5);
    expect_vec_near(hit.normal, {0, 0, 1});
    hit = trace(scene, {3, 0.2f, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.object, 1u);
    EXPECT_NEAR(hit.t, 9.5f, 1e-5);
    EXPECT_FALSE(trace(scene, {3.7f, 0, 10}, {0, 0, -1}).hit);  // the half-size copy reaches x = 3.5
    hit = trace(scene, {0, 0.2f, 10}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_EQ(hit.object, 2u);
    EXPECT_NEAR(hit.t, 9, 1e-5);
}

TEST(BuildSceneTest, TwoDifferentMeshesAreStoredSeparately) {
    SceneDesc desc = scene_with(group({mesh_object(1), transform(Mat4::translate({0, 3, 0}), mesh_object(0))}));
    desc.meshes.push_back({"a.obj", cube_mesh()});
    TriangleMesh one_triangle;
    one_triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    one_triangle.indices = {0, 1, 2};
    desc.meshes.push_back({"b.obj", one_triangle});
    const Scene scene = build_scene(std::move(desc), {});
    ASSERT_EQ(scene.meshes.size(), 2u);
    // Meshes are stored in the order they are first used.
    EXPECT_EQ(scene.meshes[scene.instances[0].shape].triangle_count, 1u);
    EXPECT_EQ(scene.meshes[scene.instances[1].shape].triangle_count, 12u);
}

// A flat n-by-n grid of squares over [-1, 1]² at z = 0, two triangles each: enough triangles
// for a mesh BVH of several levels.
TriangleMesh grid_mesh(int n) {
    TriangleMesh mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            mesh.positions.push_back({2.0f * static_cast<float>(i) / static_cast<float>(n) - 1,
                                      2.0f * static_cast<float>(j) / static_cast<float>(n) - 1, 0});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = static_cast<uint32_t>(j * (n + 1) + i), b = a + 1,
                           c = a + static_cast<uint32_t>(n + 1), d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    return mesh;
}

// A leaf of the instance BVH tests its instances in turn, each culled by the nearest hit so far:
// the ball is tested before the mesh inside it, whichever comes first in the file, so that a ray
// that meets the ball stops at the mesh's root. The hit is the ball's either way.
TEST(BuildSceneTest, ABallIsTestedBeforeTheMeshInsideItWhateverTheFileOrder) {
    auto build_in_order = [](bool mesh_first) {
        std::vector<ObjectDesc> objects;
        objects.push_back(mesh_object(0));
        objects.push_back(sphere({0, 0, 0}, 3));
        if (!mesh_first) std::swap(objects[0], objects[1]);
        SceneDesc desc = scene_with(group(std::move(objects)));
        desc.meshes.push_back({"grid.obj", grid_mesh(16)});
        return build_scene(std::move(desc), {});
    };
    const Scene mesh_first = build_in_order(true), ball_first = build_in_order(false);
    ASSERT_EQ(mesh_first.instances[0].kind, ShapeKind::Mesh);
    ASSERT_EQ(mesh_first.instances[1].kind, ShapeKind::Sphere);
    for (const BvhNode& node : mesh_first.instance_bvh.nodes) {
        if (!node.is_leaf()) continue;
        const auto first = mesh_first.instance_bvh.prim_order.begin() + node.first;
        const std::vector<uint32_t> leaf(first, first + node.count);
        if (leaf.size() == 2) {
            EXPECT_EQ(leaf, (std::vector<uint32_t>{1, 0})) << "the ball first";
        }
    }

    const Ray ray{{0.1f, 0.2f, 10}, {0, 0, -1}};
    Hit from_mesh_first, from_ball_first;
    TraceCounters mesh_first_counters, ball_first_counters;
    intersect(mesh_first, ray, 0, from_mesh_first, &mesh_first_counters);
    intersect(ball_first, ray, 0, from_ball_first, &ball_first_counters);
    EXPECT_EQ(from_mesh_first.object, 1u);
    EXPECT_EQ(from_ball_first.object, 0u);
    // The ball's near side: z = sqrt(9 - 0.1² - 0.2²), from z = 10.
    EXPECT_NEAR(from_mesh_first.t, 10 - std::sqrt(9 - 0.05f), 1e-5);
    EXPECT_EQ(from_mesh_first.t, from_ball_first.t);
    // Only the mesh's root was opened: as many boxes tested as the ball-first scene tests.
    EXPECT_EQ(mesh_first_counters.nodes_visited, ball_first_counters.nodes_visited);

    // Without the ball in the way, the same ray searches deeper into the mesh.
    Hit mesh_only;
    TraceCounters mesh_only_counters;
    intersect(mesh_first, Ray{{0.1f, 0.2f, 2}, {0, 0, -1}}, 0, mesh_only, &mesh_only_counters);
    EXPECT_EQ(mesh_only.object, 0u);
    EXPECT_GT(mesh_only_counters.nodes_visited, mesh_first_counters.nodes_visited);
}

// A scene of one mesh in world space sends its single rays straight to the mesh's kernel
// (SoleMesh): every hit, count and any-hit answer must be the two-level walk's, and any other
// scene must take the walk.
TEST(BuildSceneTest, AWorldSpaceMeshAloneIsTracedStraightThroughItsKernelWithTheWalksAnswers) {
    TriangleMesh ball = sphere_mesh({0, 0, 0}, 1, 12, 16);  // closed: it has cones
    for (Vec3f& p : ball.positions) p = p * (1 + 0.2f * std::sin(5 * p.x) * std::cos(3 * p.y));
    SceneDesc desc = scene_with(mesh_object(0));
    desc.meshes.push_back({"ball.obj", ball});
    const Scene scene = build_scene(std::move(desc), {});
    ASSERT_NE(scene.sole_mesh.intersect, nullptr);
    ASSERT_NE(scene.sole_mesh.occluded, nullptr);
    ASSERT_FALSE(scene.meshes[0].cones.empty());
    EXPECT_EQ(scene.sole_mesh.instance, 0u);
    EXPECT_EQ(scene.sole_mesh.shape, 0u);

    const uint8_t skip[] = {1}, test_every_face[] = {0};
    int hits = 0, blocked = 0, skipped_through = 0;
    for (const Vec3f origin : {Vec3f{0.3f, 0.2f, 4}, Vec3f{-3, 1, 0.5f}, Vec3f{0.1f, 0, 0}})
        for (int i = 0; i < 400; ++i) {
            const float a = 0.0157f * static_cast<float>(i), b = 0.0311f * static_cast<float>(i);
            const Ray ray{origin, Vec3f{std::cos(a) * std::sin(b), std::sin(a) * std::sin(b), std::cos(b)} - origin * 0.2f};
            Hit straight, walked;
            TraceCounters straight_counts, walked_counts;
            intersect(scene, ray, 0, straight, &straight_counts);
            intersect_two_level(scene, ray, 0, walked, &walked_counts);
            EXPECT_TRUE(straight.t == walked.t && straight.u == walked.u && straight.v == walked.v &&
                        straight.object == walked.object && straight.prim == walked.prim &&
                        straight.leaf == walked.leaf && straight.lane == walked.lane)
                << "ray " << i << " from (" << origin.x << ", " << origin.y << ", " << origin.z << ")";
            EXPECT_EQ(straight_counts.nodes_visited, walked_counts.nodes_visited) << "ray " << i;
            hits += straight.is_hit() ? 1 : 0;
            for (const float t_max : {0.5f, 3.0f, INFINITY})
                for (const uint8_t* skipping : {static_cast<const uint8_t*>(nullptr), skip, test_every_face}) {
                    const bool answer = occluded(scene, ray, 1e-3f, t_max, skipping);
                    EXPECT_EQ(answer, occluded_two_level(scene, ray, 1e-3f, t_max, skipping)) << "ray " << i;
                    blocked += answer ? 1 : 0;
                    if (skipping == skip && !answer && occluded(scene, ray, 1e-3f, t_max)) ++skipped_through;
                }
        }
    // The rays both hit and missed, were blocked and not, and skipping back faces let some through.
    EXPECT_GT(hits, 100);
    EXPECT_LT(hits, 1200);
    EXPECT_GT(blocked, 100);
    EXPECT_GT(skipped_through, 0);

    // Every other scene takes the two-level walk.
    auto sole = [](ObjectDesc root) {
        SceneDesc other = scene_with(std::move(root));
        other.meshes.push_back({"cube.obj", cube_mesh()});
        return build_scene(std::move(other), {}).sole_mesh.intersect != nullptr;
    };
    EXPECT_TRUE(sole(mesh_object(0)));
    EXPECT_TRUE(sole(group({mesh_object(0)})));
    EXPECT_FALSE(sole(group({mesh_object(0), plane({0, 1, 0}, -5)})));
    EXPECT_FALSE(sole(group({mesh_object(0), sphere({3, 0, 0}, 1)})));
    EXPECT_FALSE(sole(group({mesh_object(0), mesh_object(0)})));
    EXPECT_FALSE(sole(transform(Mat4::translate({1, 0, 0}), mesh_object(0))));
    EXPECT_FALSE(sole(sphere({0, 0, 0}, 1)));
    SceneDesc empty_mesh = scene_with(mesh_object(0));
    empty_mesh.meshes.push_back({"empty.obj", TriangleMesh{}});
    EXPECT_EQ(build_scene(std::move(empty_mesh), {}).sole_mesh.intersect, nullptr);
}

const char* const kSingularMessage =
    "this transform cannot be inverted (it squashes space flat): check for a zero scale, or scales whose product is 0 "
    "in float";

// Found by fuzz_render_pipeline (fuzz/regressions/fuzz_render_pipeline-degenerate-triangle-hit): a
// triangle on one line, (0,0,0) (1,1,1) (2,2,2), seen from a point on that line. The watertight
// test's edge functions come out 0, 0 and a rounding error for some rays through the triangle's
// box, which made a "hit" at a vertex the ray never meets; the sphere behind was hidden.
TEST(BuildSceneTest, ATriangleWithNoAreaIsNeverHitEvenFromAPointOnItsLine) {
    const Vec3f eye{-2.30940104f, -2.30940104f, -2.30940104f};
    TriangleMesh line_mesh;
    line_mesh.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    line_mesh.indices = {0, 1, 2};
    SceneDesc desc = scene_with(group({triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), mesh_object(0),
                                       sphere({1.155f, 1.305f, 3.704f}, 0.3f)}));
    desc.meshes.push_back(MeshDesc{"line.obj", line_mesh});
    const Scene scene = build(std::move(desc));
    ASSERT_TRUE(is_degenerate_triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
    // Towards points of the box [0, 2]³ off the line, among them three where the old scene "hit"
    // the triangle (t 1.07, 0.81, 1.19); the first meets the sphere further on, about t = 1.45
    // (its centre is at t = 1.5, and the direction is 5.2 long).
    for (const Vec3f target : {Vec3f{0, 0.1f, 1.7f}, Vec3f{0, 0.1f, 1.8f}, Vec3f{0, 0.3f, 1.3f}, Vec3f{1, 1.5f, 0.5f}}) {
        const Traced traced = trace(scene, eye, target - eye);
        EXPECT_FALSE(traced.hit && traced.object < 2) << target.x << " " << target.y << " " << target.z;
    }
    EXPECT_TRUE(trace(scene, eye, Vec3f{0, 0.1f, 1.7f} - eye).hit);
    EXPECT_EQ(trace(scene, eye, Vec3f{0, 0.1f, 1.7f} - eye).object, 2u);
    EXPECT_FALSE(occluded(scene, Ray{eye, Vec3f{0, 0.1f, 1.8f} - eye}, 0, 1.0f));
}

// The errors build_scene refuses `desc` with; none (and a test failure) when it accepts it.
std::vector<Diagnostic> refusal(SceneDesc desc) {
    try {
        build_scene(std::move(desc), {});
    } catch (const InputError& e) {
        return e.diagnostics();
    }
    ADD_FAILURE() << "accepted";
    return {};
}

// Two scales of 1e20 make a product float cannot hold (infinity), which cannot be inverted
// either: said as the scale past the limit that it is, not as a zero scale.
TEST(BuildSceneTest, AScaleProductPastFloatIsNamedAsAScale) {
    const std::vector<Diagnostic> outer = refusal(scene_with(group({transform(
        Mat4::scale({1e20f, 1e20f, 1e20f}),
        transform(Mat4::scale({1e20f, 1e20f, 1e20f}), sphere({0, 0, 0}, 1), {"big.txt", 3, 5}), {"big.txt", 2, 1})})));
    // The outer 1e20 is already past the limit: the error is there, and the inner not reached.
    ASSERT_EQ(outer.size(), 1u);
    EXPECT_EQ(outer[0].location.line, 2);
    const std::vector<Diagnostic> product = refusal(scene_with(group({transform(
        Mat4::scale({1e10f, 1e10f, 1e10f}),
        transform(Mat4::scale({1e30f, 1e30f, 1e30f}), sphere({0, 0, 0}, 1e-30f), {"big.txt", 3, 5}),
        {"big.txt", 2, 1})})));
    ASSERT_EQ(product.size(), 1u);
    EXPECT_EQ(product[0].location.line, 3);
    EXPECT_EQ(product[0].message,
              "this transform (with those around it) scales by more than float holds, beyond raycast's limit of 1e+18 "
              "(float arithmetic would underflow): give the objects in it larger coordinates and it a smaller scale");
}

TEST(BuildSceneTest, SingularTransformIsAnInputErrorAtTheTransform) {
    const SceneDesc desc =
        scene_with(group({sphere({0, 0, 0}, 1),
                          transform(Mat4::scale({1, 0, 1}), sphere({0, 0, 0}, 1), {"flat.txt", 7, 3})}));
    try {
        build_scene(desc, {});
        FAIL() << "a zero scale was accepted";
    } catch (const InputError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u);
        const Diagnostic& d = e.diagnostics()[0];
        EXPECT_EQ(d.severity, Severity::Error);
        EXPECT_EQ(d.message, kSingularMessage);
        EXPECT_EQ(d.location.file, "flat.txt");
        EXPECT_EQ(d.location.line, 7);
        EXPECT_EQ(d.location.column, 3);
        EXPECT_EQ(std::string(e.what()), std::string("flat.txt:7:3: error: ") + kSingularMessage + "\n");
    }
}

// A transformed object is tested in its own space, so its own coordinates are held to the limit
// of 1e18 (base/limits.h) as well as its world ones: each kind of object given at 1e20 and scaled
// by 1e-5 is refused at the object, and the same at 1e10 is built.
TEST(BuildSceneTest, ObjectsPastTheCoordinateLimitInTheirOwnSpaceAreRefused) {
    const std::string remedy = ", beyond raycast's limit of 1e+18 (float arithmetic would overflow): give it smaller "
                               "coordinates and its Transform a larger scale";
    for (const float size : {1e20f, 1e10f}) {
        const Curve profile{CurveType::Bezier, {{size, -size, 0}, {size, 0, 0}, {size, 0, 0}, {size, size, 0}}};
        ObjectDesc mesh = mesh_object(0);
        const std::pair<const char*, ObjectDesc> objects[] = {
            {"sphere", sphere({0, 0, 0}, size)},
            {"triangle", triangle({-size, -size, 0}, {size, -size, 0}, {0, size, 0})},
            {"mesh", mesh},
            {"surface of revolution", rev_surface(profile)},
        };
        for (const auto& [name, object] : objects) {
            SCOPED_TRACE(std::string(name) + " of size " + std::to_string(size));
            ObjectDesc located = object;
            located.location = {"big.txt", 4, 9};
            SceneDesc desc = scene_with(group({transform(Mat4::scale({1e-5f, 1e-5f, 1e-5f}), located)}));
            desc.meshes.push_back({"big.obj", sphere_mesh({0, 0, 0}, size, 4, 8)});
            if (size < 1e18f) {
                EXPECT_EQ(build_scene(std::move(desc), {}).instances.size(), 1u);
                continue;
            }
            const std::vector<Diagnostic> errors = refusal(std::move(desc));
            ASSERT_EQ(errors.size(), 1u);
            const Diagnostic& d = errors[0];
            EXPECT_EQ(d.location.line, 4);
            EXPECT_EQ(d.location.column, 9);
            EXPECT_EQ(d.message.rfind("this object reaches coordinates of 1e+20 in its own space (before its Transform)",
                                      0),
                      0u)
                << d.message;
            EXPECT_EQ(d.message.substr(d.message.size() - remedy.size()), remedy);
        }
    }
}

// In an object's own space a ray's direction is M⁻¹d, squared in the tests: a transform (with
// those around it) may scale by 1e-18 to 1e18, and past that it is refused at the transform.
TEST(BuildSceneTest, TransformsScalingPastTheLimitAreRefused) {
    const std::pair<float, const char*> cases[] = {
        {1e19f, "this transform (with those around it) scales by 1e+19, beyond raycast's limit of 1e+18 (float "
                "arithmetic would underflow): give the objects in it larger coordinates and it a smaller scale"},
        {1e-19f, "this transform (with those around it) scales by 1e-19, below raycast's limit of 1e-18 (float "
                 "arithmetic would overflow): give the objects in it smaller coordinates and it a larger scale"},
        {1e17f, nullptr},
        {1e-17f, nullptr},
    };
    for (const auto& [factor, message] : cases) {
        SCOPED_TRACE(factor);
        // Split over two transforms: the limit is on their product.
        const float half = std::sqrt(factor);
        SceneDesc desc = scene_with(group({transform(
            Mat4::scale({half, half, half}),
            transform(Mat4::rotate_z(30) * Mat4::scale({half, half, half}), sphere({0, 0, 0}, 1 / factor)),
            {"scaled.txt", 3, 5})}));
        if (!message) {
            EXPECT_EQ(build_scene(std::move(desc), {}).instances.size(), 1u);
            continue;
        }
        const std::vector<Diagnostic> errors = refusal(std::move(desc));
        ASSERT_EQ(errors.size(), 1u);
        EXPECT_EQ(errors[0].message, message);
    }
}

TEST(BuildSceneTest, EverySingularTransformIsReportedIncludingRankDeficientMatrices) {
    // Rows (1 2 3), (4 5 6), (5 7 9): the third is the sum of the first two, no zero anywhere.
    const float rows[16] = {1, 2, 3, 0, 4, 5, 6, 0, 5, 7, 9, 0, 0, 0, 0, 1};
    const SceneDesc desc = scene_with(group({
        transform(Mat4::from_rows(rows), sphere({0, 0, 0}, 1), {"m.txt", 2, 1}),
        // Invertible outside, singular inside: the product is singular.
        transform(Mat4::translate({1, 2, 3}), transform(Mat4::scale({0, 0, 0}), plane({0, 1, 0}, 0), {"m.txt", 4, 5}),
                  {"m.txt", 3, 1}),
    }));
    try {
        build_scene(desc, {});
        FAIL() << "singular transforms were accepted";
    } catch (const InputError& e) {
        ASSERT_EQ(e.diagnostics().size(), 2u);
        EXPECT_EQ(e.diagnostics()[0].message, kSingularMessage);
        EXPECT_EQ(e.diagnostics()[0].location.line, 2);
        EXPECT_EQ(e.diagnostics()[1].message, kSingularMessage);
        EXPECT_EQ(e.diagnostics()[1].location.line, 4);
        EXPECT_EQ(e.diagnostics()[1].location.column, 5);
    }
    // The identity as a "transform" is fine, and so is a tiny but regular scale.
    EXPECT_NO_THROW(build_scene(scene_with(transform(Mat4::identity(), sphere({0, 0, 0}, 1))), {}));
    EXPECT_NO_THROW(build_scene(scene_with(transform(Mat4::scale({1e-3f, 1e-3f, 1e-3f}), sphere({0, 0, 0}, 1))), {}));
}

TEST(BuildSceneTest, MissingCameraOrImageSizeIsAnInputError) {
    SceneDesc no_camera = scene_with(sphere({0, 0, 0}, 1));
    no_camera.camera.reset();
    try {
        build_scene(no_camera, {});
        FAIL();
    } catch (const InputError& e) {
        ASSERT_EQ(e.diagnostics().size(), 1u);
        EXPECT_EQ(e.diagnostics()[0].message, "the scene has no camera");
    }
    SceneDesc no_size = scene_with(sphere({0, 0, 0}, 1));
    no_size.camera->width = 0;
    no_size.camera->height = 0;
    EXPECT_THROW(build_scene(no_size, {}), InputError);
    // The options' size fills in (and overrides) the camera's.
    SceneBuildOptions options;
    options.width = 12;
    options.height = 6;
    const Scene scene = build_scene(no_size, options);
    EXPECT_EQ(scene.camera.width, 12);
    EXPECT_EQ(scene.camera.height, 6);
}

TEST(BuildSceneTest, PlanesAreMovedToWorldSpace) {
    // The floor y = −2 (scene01's plane) under three transforms.
    const ObjectDesc floor = plane({0, 1, 0}, -2);
    // Translate 0 5 0: y = 3. From (0, 10, 0) straight down: t = 7.
    Scene scene = build_scene(scene_with(transform(Mat4::translate({0, 5, 0}), floor)), {});
    Traced hit = trace(scene, {0.5f, 10, -0.25f}, {0, -1, 0});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 7, 1e-5);
    expect_vec_near(hit.normal, {0, 1, 0});
    // Scale 1 2 1: y = −4; the normal (M⁻ᵀn = (0, 0.5, 0)) comes out unit. With direction (0, −2, 0), t = 7.
    scene = build_scene(scene_with(transform(Mat4::scale({1, 2, 1}), floor)), {});
    hit = trace(scene, {0, 10, 0}, {0, -2, 0});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 7, 1e-5);
    expect_vec_near(hit.position, {0, -4, 0});
    expect_vec_near(hit.normal, {0, 1, 0});
    // Translate 0 0 1, XRotate 90: the rotation takes +y to +z, so y = −2 becomes z = −2, then z = −1.
    scene = build_scene(scene_with(transform(Mat4::translate({0, 0, 1}) * Mat4::rotate_x(90), floor)), {});
    hit = trace(scene, {0.3f, 0.2f, 5}, {0, 0, -1});
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 6, 1e-5);
    expect_vec_near(hit.normal, {0, 0, 1});
}

// Rotations by multiples of 90 degrees must be exact: with cos 90° = 6.1e-17 (its double value)
// the world plane's normal would keep a y component of 6e-17 and a ray parallel to the plane
// would hit it near t = 1.6e17 instead of missing it (a background pixel would show the plane).
TEST(BuildSceneTest, RayParallelToAPlaneRotatedByNinetyDegreesMissesIt) {
    const Scene scene =
        build_scene(scene_with(transform(Mat4::translate({0, 0, 1}) * Mat4::rotate_x(90), plane({0, 1, 0}, -2))), {});
    ASSERT_EQ(scene.planes.size(), 1u);
    EXPECT_EQ(scene.planes[0].normal.y, 0.0f);
    EXPECT_FALSE(trace(scene, {0, 10, 0}, {0, -1, 0}).hit);  // z = 0 never reaches the plane z = −1
}

TEST(BuildSceneTest, TransformedPlaneHoldsExactlyThePointsThatMapBackOntoTheObjectPlane) {
    // A general transform; a world point p is on the plane iff n·(M⁻¹p) = d.
    const Mat4 m = Mat4::translate({1, -2, 3}) * Mat4::rotate({1, 2, 3}, 35) * Mat4::scale({2, 0.5f, 3});
    const Plane object_plane{{0.6f, 0, 0.8f}, 1.5f};
    const Scene scene = build_scene(scene_with(transform(m, plane(object_plane.normal, object_plane.offset))), {});
    ASSERT_EQ(scene.planes.size(), 1u);
    const Mat4 object_from_world = inverse(m);
    int hits = 0;
    for (const Vec3f direction : {Vec3f{0, 0, -1}, Vec3f{1, -1, -0.5f}, Vec3f{-0.3f, 2, 0.7f}, Vec3f{0.2f, 0.1f, 1}}) {
        for (const Vec3f origin : {Vec3f{0, 0, 10}, Vec3f{-5, 3, 1}}) {
            Traced hit = trace(scene, origin, direction);
            Traced back = trace(scene, origin, -direction);
            if (!hit.hit) hit = back;
            if (!hit.hit) continue;
            ++hits;
            const Vec3f p = transform_point(object_from_world, hit.position);
            EXPECT_NEAR(dot(object_plane.normal, p), object_plane.offset, 1e-4);
            // The normal is perpendicular to the plane: any two world points on it differ along it.
            const Vec3f q = transform_point(m, p + Vec3f{0.8f, 3, -0.6f});  // another object-plane point
            EXPECT_NEAR(dot(hit.normal, q - hit.position), 0, 1e-4);
            EXPECT_NEAR(length(hit.normal), 1, 1e-6);
        }
    }
    EXPECT_GE(hits, 4);
}

TEST(BuildSceneTest, EveryObjectGetsTheMaterialIndexInForceWhereItAppears) {
    // course-format.md §a: MaterialIndex is not scoped by groups; scene04's inner group leaves its
    // material current for the outer group. Objects count in file order.
    const std::string text = std::string(kCameraAndMaterials) +
                             "Group { numObjects 4\n"
                             "  MaterialIndex 1\n"
                             "  Sphere { center -3 0 0 radius 0.5 }\n"
                             "  Group { numObjects 1 MaterialIndex 2 Sphere { center -1 0 0 radius 0.5 } }\n"
                             "  Sphere { center 1 0 0 radius 0.5 }\n"
                             "  MaterialIndex 0\n"
                             "  Transform { Translate 3 0 0 Sphere { center 0 0 0 radius 0.5 } }\n"
                             "}\n";
    const Scene scene = build_scene(load_scene_text(text, "materials.txt"), {});
    ASSERT_EQ(scene.instances.size(), 4u);
    const uint32_t expected[4] = {1, 2, 2, 0};
    const float xs[4] = {-3, -1, 1, 3};
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(scene.instances[static_cast<size_t>(i)].material, expected[i]) << i;
        const Traced hit = trace(scene, {xs[i], 0, 10}, {0, 0, -1});
        ASSERT_TRUE(hit.hit) << i;
        EXPECT_EQ(hit.object, static_cast<uint32_t>(i));
        EXPECT_EQ(hit.material, expected[i]) << i;
    }
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[1].diffuse, (Vec3f{0, 1, 0}));
    EXPECT_EQ(scene.materials[2].specular, (Vec3f{1, 1, 1}));
}

TEST(BuildSceneTest, MaterialsAndLightsAreCopiedWithDefaultsByConventions) {
    SceneDesc desc = scene_with(group({sphere({0, 0, 0}, 1, 1), sphere({3, 0, 0}, 1, 0)}), 2);
    desc.materials[0].diffuse = {0.1f, 0.2f, 0.3f};
    desc.materials[0].shininess = 20;  // given
    // materials[1] gives no shininess: 0 in the course, 1 for MIT 6.837.
    LightDesc light;
    light.kind = LightDesc::Kind::Directional;
    light.direction = {0, -3, -4};  // normalised by the build
    light.color = {0.5f, 0.25f, 1};
    desc.lights.push_back(light);
    LightDesc point;
    point.kind = LightDesc::Kind::Point;
    point.position = {1, 2, 3};
    desc.lights.push_back(point);
    desc.background = {0.1f, 0.7f, 0.2f};

    const Scene course = build_scene(desc, {});
    EXPECT_EQ(course.instances[0].material, 1u);
    EXPECT_EQ(course.instances[1].material, 0u);
    EXPECT_EQ(course.materials[0].diffuse, (Vec3f{0.1f, 0.2f, 0.3f}));
    EXPECT_EQ(course.materials[0].shininess, 20);
    EXPECT_EQ(course.materials[1].shininess, 0);
    ASSERT_EQ(course.lights.size(), 2u);
    EXPECT_EQ(course.lights[0].kind, Light::Kind::Directional);
    expect_vec_near(course.lights[0].direction, {0, -0.6f, -0.8f});
    EXPECT_EQ(course.lights[0].color, (Vec3f{0.5f, 0.25f, 1}));
    EXPECT_EQ(course.lights[1].kind, Light::Kind::Point);
    EXPECT_EQ(course.lights[1].position, (Vec3f{1, 2, 3}));
    EXPECT_EQ(course.background, (Vec3f{0.1f, 0.7f, 0.2f}));

    SceneBuildOptions mit;
    mit.conventions = Conventions::mit6837();
    const Scene mit_scene = build_scene(desc, mit);
    EXPECT_EQ(mit_scene.materials[0].shininess, 20);
    EXPECT_EQ(mit_scene.materials[1].shininess, 1);
    EXPECT_EQ(mit_scene.camera.pixel_offset, 0.5f);  // the conventions reach the camera
}

// surface_points finds many hits' points at once, in SIMD for triangles of flat meshes: each
// must be surface_at's bit for bit, whatever the lanes' order, for a tilted mesh (no normal
// component zero), the same mesh moved by a transform, a mesh with vertex normals, and the other
// shapes, every one with its own material.
TEST(BuildSceneTest, SurfacePointsOfManyHitsAreEachSurfaceAtBitForBit) {
    TriangleMesh bumpy = grid_mesh(8);
    for (size_t i = 0; i < bumpy.positions.size(); ++i)
        bumpy.positions[i].z = 0.3f * std::sin(1.7f * static_cast<float>(i)) + 0.1f * bumpy.positions[i].x;
    TriangleMesh smooth = grid_mesh(4);
    for (Vec3f& p : smooth.positions) p.x -= 2.5f;  // moved without a transform
    smooth.normals = {{0.1f, 0.2f, 1}, {-0.3f, 0, 1}, {0, 0.4f, 0.9f}};
    for (size_t t = 0; t < smooth.indices.size() / 3; ++t)
        smooth.normal_indices.insert(smooth.normal_indices.end(), {0, 1, 2});
    SceneDesc desc = scene_with(group({mesh_object(0, 1),
                                       transform(Mat4::translate({2.5f, 0, 0}) * Mat4::scale({1, 1.5f, 1}),
                                                 mesh_object(0, 2)),
                                       mesh_object(1, 3),
                                       sphere({0, 2.5f, 0}, 0.8f, 4), triangle({-3, -3, 0}, {-1, -2, 0.5f}, {-2, -1.5f, 1}, 5),
                                       plane({0, 0.1f, 1}, -2, 0)}),
                                6);
    desc.meshes.push_back({"bumpy.obj", bumpy});
    desc.meshes.push_back({"smooth.obj", smooth});
    const Scene scene = build_scene(std::move(desc), {});
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
            const Ray ray{{0.3f, -0.2f, 10}, normalize(Vec3f{(static_cast<float>(x) - 19.5f) * 0.011f,
                                                             (static_cast<float>(y) - 19.5f) * 0.011f, -1})};
            Hit hit;
            intersect(scene, ray, 0, hit);
            if (!hit.is_hit()) continue;
            rays.push_back(ray);
            hits.push_back(hit);
        }
    ASSERT_GT(hits.size(), 1000u);
    std::vector<int> kinds(6, 0);
    int mismatches = 0;
    for (size_t first = 0; first < hits.size(); first += kMaxPacketLanes) {
        const int count = static_cast<int>(std::min<size_t>(kMaxPacketLanes, hits.size() - first));
        int lanes[kMaxPacketLanes];
        for (int j = 0; j < count; ++j) lanes[j] = count - 1 - j;  // lane j is hit count − 1 − j
        SurfaceLanes out;
        surface_points(scene, &rays[first], &hits[first], lanes, count, out);
        for (int j = 0; j < count; ++j) {
            const size_t k = first + static_cast<size_t>(lanes[j]);
            const SurfacePoint expected = surface_at(scene, rays[k], hits[k]);
            const SurfacePoint got = out.at(j);
            if (std::memcmp(&got.position, &expected.position, sizeof got.position) != 0 ||
                std::memcmp(&got.normal, &expected.normal, sizeof got.normal) != 0 ||
                std::memcmp(&got.geometric_normal, &expected.geometric_normal, sizeof got.geometric_normal) != 0 ||
                std::memcmp(&got.geometry_scale, &expected.geometry_scale, sizeof got.geometry_scale) != 0 ||
                got.material != expected.material)
                ++mismatches;
            ++kinds[expected.material];
        }
    }
    EXPECT_EQ(mismatches, 0);
    for (int material = 0; material < 6; ++material) EXPECT_GT(kinds[static_cast<size_t>(material)], 10) << material;
}

// A flat mesh of triangles 8e9 across (cross products 1e19, past float when squared) and one 1e-12
// across (squared below it): surface_points, in SIMD, and surface_at give each hit the same bits,
// a unit normal (they once gave zero, and the triangles were drawn black), and the corners'
// largest coordinate as the geometry's scale, whatever the position of the hit.
TEST(BuildSceneTest, SurfacePointsOfHugeAndTinyTrianglesHaveUnitNormals) {
    for (const float size : {4e9f, 1e-12f}) {
        SCOPED_TRACE(size);
        TriangleMesh mesh = grid_mesh(4);  // over [-1, 1]², z = 0
        for (Vec3f& p : mesh.positions) p = Vec3f{p.x, p.y, 0.2f * p.x} * size;
        SceneDesc desc = scene_with(group({mesh_object(0, 0)}), 1);
        desc.meshes.push_back({"mesh.obj", mesh});
        const Scene scene = build_scene(std::move(desc), {});
        std::vector<Ray> rays;
        std::vector<Hit> hits;
        for (int i = 0; i < 2 * kMaxPacketLanes; ++i) {
            const Ray ray{Vec3f{0.1f, 0.05f, 10} * size, normalize(Vec3f{static_cast<float>(i % 5) * 0.02f - 0.04f,
                                                                          static_cast<float>(i / 5) * 0.01f - 0.03f, -1})};
            Hit hit;
            intersect(scene, ray, 0, hit);
            ASSERT_TRUE(hit.is_hit()) << i;
            rays.push_back(ray);
            hits.push_back(hit);
        }
        int lanes[kMaxPacketLanes];
        for (int j = 0; j < kMaxPacketLanes; ++j) lanes[j] = j;
        for (size_t first = 0; first < hits.size(); first += kMaxPacketLanes) {
            SurfaceLanes out;
            surface_points(scene, &rays[first], &hits[first], lanes, kMaxPacketLanes, out);
            for (int j = 0; j < kMaxPacketLanes; ++j) {
                const SurfacePoint expected = surface_at(scene, rays[first + j], hits[first + j]);
                const SurfacePoint got = out.at(j);
                EXPECT_EQ(std::memcmp(&got.normal, &expected.normal, sizeof got.normal), 0) << j;
                EXPECT_EQ(std::memcmp(&got.geometric_normal, &expected.geometric_normal, sizeof got.normal), 0) << j;
                EXPECT_EQ(got.geometry_scale, expected.geometry_scale) << j;
                // The plane z = 0.2 x: normal (-0.2, 0, 1) / |(-0.2, 0, 1)|.
                EXPECT_NEAR(got.normal.x, -0.2f / std::sqrt(1.04f), 1e-6f) << j;
                EXPECT_NEAR(got.normal.z, 1 / std::sqrt(1.04f), 1e-6f) << j;
                const GroupTriangle corners = group_triangle(&scene.meshes[0].groups[hits[first + j].leaf], hits[first + j].lane);
                EXPECT_EQ(got.geometry_scale,
                          std::max({max_abs(corners.p0), max_abs(corners.p1), max_abs(corners.p2)})) << j;
            }
        }
    }
}

}  // namespace
}  // namespace raycast
