// The Whitted ray tracer of the Shaded mode (render/integrator.h) against answers worked out by
// hand: a mirror returns exactly the colour along the mirror direction; a glass slab lets a ray
// out parallel to itself, shifted by t·sin(θi − θt)/cos θt; total internal reflection sends
// nothing through; the bounce limit and the weight cutoff stop recursion where they should;
// point-light attenuation; transparent shadows; the ray budget; and Snell's law itself.
#include "render/integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/render.h"
#include "render/shade.h"
#include "scene/build_scene.h"
#include "scene_builders.h"

namespace raycast {
namespace {

using namespace test;  // the scene builders (tests/scene_builders.h)

constexpr float kPi = 3.14159265358979f;

void expect_vec_near(Vec3f actual, Vec3f expected, float tolerance = 1e-6f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << "x";
    EXPECT_NEAR(actual.y, expected.y, tolerance) << "y";
    EXPECT_NEAR(actual.z, expected.z, tolerance) << "z";
}

MaterialDesc glass(Vec3f transparent, float index, Vec3f reflective = {0, 0, 0}) {
    MaterialDesc m = material({0, 0, 0});
    m.transparent = transparent;
    m.reflective = reflective;
    m.index_of_refraction = index;
    return m;
}

MaterialDesc mirror(Vec3f reflective, Vec3f kd = {0, 0, 0}) {
    MaterialDesc m = material(kd);
    m.reflective = reflective;
    return m;
}

SceneDesc scene_of(ObjectDesc root, std::vector<MaterialDesc> materials, Vec3f background, Vec3f ambient,
                   std::vector<LightDesc> lights = {}) {
    SceneDesc desc;
    desc.file = "t.txt";
    CameraDesc camera;
    camera.center = {0, 0, 10};
    camera.angle_degrees = 30;
    camera.width = camera.height = 8;
    desc.camera = camera;
    desc.background = background;
    desc.ambient = ambient;
    desc.materials = std::move(materials);
    desc.lights = std::move(lights);
    desc.has_lights_block = true;
    desc.root = std::move(root);
    return desc;
}

RenderOptions tracing(int bounces, float weight_cutoff = 0) {
    RenderOptions options;
    options.bounces = bounces;
    options.weight_cutoff = weight_cutoff;
    return options;
}

// The colour along `ray` traced from t > 0, with its ray tree and counts.
struct Traced {
    Vec3f color;
    RayTree tree;
    RayCounts counts;
};

Traced trace(const Scene& scene, const RenderOptions& options, const Ray& ray) {
    Traced traced;
    Hit hit;
    intersect(scene, ray, 0, hit);
    traced.color = radiance_along(scene, options, ray, hit, &traced.counts, &traced.tree);
    return traced;
}

// The record of the first ray of `kind` at `depth`, or null.
const RayRecord* find_ray(const RayTree& tree, RayKind kind, int depth) {
    for (const RayRecord& r : tree.rays)
        if (r.kind == kind && r.depth == depth) return &r;
    return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Optics.

TEST(OpticsTest, TheMirrorDirectionReflectsAboutTheNormalOnEitherSide) {
    // d = (1, −1, 0)/√2 onto the floor y = 0: it leaves as (1, 1, 0)/√2.
    const Vec3f d = normalize(Vec3f{1, -1, 0});
    expect_vec_near(mirror_direction(d, {0, 1, 0}), normalize(Vec3f{1, 1, 0}));
    expect_vec_near(mirror_direction(d, {0, -1, 0}), normalize(Vec3f{1, 1, 0}));
    // Straight down comes straight back up.
    expect_vec_near(mirror_direction({0, -1, 0}, {0, 1, 0}), {0, 1, 0});
}

TEST(OpticsTest, RefractionFollowsSnellsLaw) {
    // 30° into glass of index 1.5: sin θt = 0.5/1.5 = 1/3, so the direction is (1/3, −√8/3, 0).
    Vec3f t;
    ASSERT_TRUE(refract_direction({0.5f, -std::sqrt(0.75f), 0}, {0, 1, 0}, 1, 1.5f, t));
    expect_vec_near(t, {1.0f / 3, -std::sqrt(8.0f) / 3, 0});
    // The normal's side does not matter.
    Vec3f t2;
    ASSERT_TRUE(refract_direction({0.5f, -std::sqrt(0.75f), 0}, {0, -1, 0}, 1, 1.5f, t2));
    expect_vec_near(t2, t);
    // Equal indices: straight through.
    ASSERT_TRUE(refract_direction(normalize(Vec3f{1, -2, 3}), {0, 1, 0}, 1.3f, 1.3f, t));
    expect_vec_near(t, normalize(Vec3f{1, -2, 3}));
    // Normal incidence: straight through too.
    ASSERT_TRUE(refract_direction({0, -1, 0}, {0, 1, 0}, 1, 2, t));
    expect_vec_near(t, {0, -1, 0});
}

TEST(OpticsTest, TotalInternalReflectionBeyondTheCriticalAngle) {
    // From glass (1.5) into vacuum the critical angle is asin(1/1.5) = 41.81°.
    Vec3f t;
    for (const float degrees : {41.0f, 41.7f}) {
        const float a = degrees * kPi / 180;
        EXPECT_TRUE(refract_direction({std::sin(a), std::cos(a), 0}, {0, 1, 0}, 1.5f, 1, t)) << degrees;
        EXPECT_NEAR(t.x, 1.5f * std::sin(a), 1e-5f) << degrees;  // sin θt = 1.5 sin θi
    }
    for (const float degrees : {41.9f, 60.0f, 89.0f}) {
        const float a = degrees * kPi / 180;
        EXPECT_FALSE(refract_direction({std::sin(a), std::cos(a), 0}, {0, 1, 0}, 1.5f, 1, t)) << degrees;
    }
}

// ---------------------------------------------------------------------------------------------
// Mirrors.

TEST(WhittedTest, AMirrorReturnsExactlyTheColourAlongTheMirrorDirection) {
    // A floor mirror y = −1 (reflectiveColor (0.5, 1, 0.25), black otherwise) and a sphere lit by
    // ambient light only, so it is a flat kd = (0.2, 0.4, 0.6) wherever it is seen.
    const Vec3f reflective{0.5f, 1, 0.25f};
    const Scene scene = build(scene_of(group({plane({0, 1, 0}, -1, 0), sphere({0, 1, -4}, 1, 1)}),
                                       {mirror(reflective), material({0.2f, 0.4f, 0.6f})}, {0.3f, 0.3f, 0.3f},
                                       {1, 1, 1}));
    // A ray down onto the mirror at (0, −1, −2), whose mirror image heads for the sphere's centre.
    const Vec3f hit_point{0, -1, -2};
    const Vec3f eye{0, 1, 0};
    const Ray ray{eye, normalize(hit_point - eye)};
    const Traced traced = trace(scene, tracing(1), ray);
    // Colour = ambient·kd of the mirror (0) + reflective ⊙ (what the mirrored ray sees).
    const Vec3f mirrored = mirror_direction(ray.direction, {0, 1, 0});
    Hit seen;
    intersect(scene, {hit_point, mirrored}, 0, seen);
    ASSERT_TRUE(seen.is_hit());
    EXPECT_EQ(seen.object, 1u);  // the sphere
    expect_vec_near(traced.color, reflective * Vec3f{0.2f, 0.4f, 0.6f});
    // The tree: the camera ray, then one reflected ray along the mirror direction from the hit.
    ASSERT_EQ(traced.tree.rays.size(), 2u);
    const RayRecord& reflected = traced.tree.rays[1];
    EXPECT_EQ(reflected.kind, RayKind::Reflected);
    EXPECT_EQ(reflected.parent, 0);
    expect_vec_near(reflected.direction, mirrored);
    expect_vec_near(reflected.origin, hit_point, 1e-4f);
    EXPECT_GT(reflected.origin.y, -1.0f);  // on the side it leaves towards
    expect_vec_near(reflected.multiplier, reflective);
    EXPECT_EQ(traced.counts.secondary, 1u);

    // A mirror ray that misses brings the background back, times the mirror's colour.
    const Traced sky = trace(scene, tracing(1), {{0, 1, 0}, normalize(Vec3f{0, -1, 1})});
    expect_vec_near(sky.color, reflective * Vec3f{0.3f, 0.3f, 0.3f});
    // Without bounces the mirror shows only its own shading: black.
    expect_vec_near(trace(scene, tracing(0), ray).color, {0, 0, 0});
}

// Two facing mirrors z = 0 and z = 2, each with local colour c = kd·ambient = 0.1 and
// reflectiveColor r = 0.5 (grey). A ray straight up the z axis from z = 1 bounces between them:
// colour = c + r(c + r(c + …)) = c·(1 + r + … + r^N) with N the bounces.
Scene hall_of_mirrors() {
    const Vec3f r{0.5f, 0.5f, 0.5f};
    return build(scene_of(group({plane({0, 0, 1}, 0, 0), plane({0, 0, -1}, -2, 0)}),
                          {mirror(r, {0.1f, 0.1f, 0.1f})}, {0, 0, 0}, {1, 1, 1}));
}

TEST(WhittedTest, TheBounceLimitStopsRecursionAtExactlyThatDepth) {
    const Scene scene = hall_of_mirrors();
    const Ray ray{{0, 0, 1}, {0, 0, 1}};
    for (int bounces = 0; bounces <= 6; ++bounces) {
        const Traced traced = trace(scene, tracing(bounces), ray);
        float expected = 0, power = 1;
        for (int k = 0; k <= bounces; ++k, power *= 0.5f) expected += 0.1f * power;
        expect_vec_near(traced.color, {expected, expected, expected});
        EXPECT_EQ(traced.counts.secondary, static_cast<uint64_t>(bounces)) << bounces;
        // The deepest ray says why it stopped.
        const RayRecord* last = find_ray(traced.tree, bounces == 0 ? RayKind::Camera : RayKind::Reflected, bounces);
        ASSERT_NE(last, nullptr);
        EXPECT_NE(last->note.find("bounce limit"), std::string::npos) << last->note;
    }
}

TEST(WhittedTest, TheWeightCutoffStopsRecursionWhereThePathWeightFallsBelowIt) {
    // The weight after k reflections is |r|^k = (√0.75)^k = 0.866^k: 0.75, 0.65, 0.5625, 0.487 …
    const Scene scene = hall_of_mirrors();
    const Ray ray{{0, 0, 1}, {0, 0, 1}};
    struct Case {
        float cutoff;
        int rays;  // reflections traced: those whose weight is at least the cutoff
    };
    for (const Case c : {Case{0.9f, 0}, Case{0.866f, 1}, Case{0.7f, 2}, Case{0.5f, 4}, Case{0.1f, 16}}) {
        const Traced traced = trace(scene, tracing(100, c.cutoff), ray);
        EXPECT_EQ(traced.counts.secondary, static_cast<uint64_t>(c.rays)) << c.cutoff;
        float expected = 0, power = 1;
        for (int k = 0; k <= c.rays; ++k, power *= 0.5f) expected += 0.1f * power;
        expect_vec_near(traced.color, {expected, expected, expected}, 1e-6f);
        for (const RayRecord& r : traced.tree.rays) EXPECT_GE(r.weight, c.cutoff) << c.cutoff;
    }
}

// ---------------------------------------------------------------------------------------------
// Glass.

// A slab of glass (index 1.5, transparentColor 1) between z = 0 and z = −1, as two planes whose
// normals point out of it.
Scene glass_slab(Vec3f background) {
    return build(scene_of(group({plane({0, 0, 1}, 0, 0), plane({0, 0, -1}, 1, 0)}), {glass({1, 1, 1}, 1.5f)},
                          background, {0, 0, 0}));
}

TEST(WhittedTest, ARayThroughAGlassSlabLeavesParallelToItselfShiftedByTheComputedAmount) {
    const Scene scene = glass_slab({0.3f, 0.5f, 0.7f});
    for (const float degrees : {0.0f, 10.0f, 30.0f, 60.0f}) {
        SCOPED_TRACE(degrees);
        const float incidence = degrees * kPi / 180;
        const Vec3f d{std::sin(incidence), 0, -std::cos(incidence)};
        const Ray ray{{0, 0, 5}, d};
        const Traced traced = trace(scene, tracing(2), ray);
        // Entering, then leaving: two transmitted rays, the second back in vacuum.
        const RayRecord* inside = find_ray(traced.tree, RayKind::Transmitted, 1);
        const RayRecord* outside = find_ray(traced.tree, RayKind::Transmitted, 2);
        ASSERT_NE(inside, nullptr);
        ASSERT_NE(outside, nullptr);
        EXPECT_EQ(inside->index_of_refraction, 1.5f);
        EXPECT_EQ(outside->index_of_refraction, 1.0f);
        // Inside, Snell: sin θt = sin θi / 1.5.
        const float sin_t = std::sin(incidence) / 1.5f;
        EXPECT_NEAR(inside->direction.x, sin_t, 1e-6f);
        // Out again, parallel to the incoming ray ...
        expect_vec_near(outside->direction, d, 1e-6f);
        // ... shifted sideways by thickness·sin(θi − θt)/cos θt, measured across the ray.
        const float theta_t = std::asin(sin_t);
        const float shift = std::sin(incidence - theta_t) / std::cos(theta_t);
        const Vec3f offset = outside->origin - ray.origin;
        // (Within 2e-4: each surface moves the new ray's origin off it by its rounding bound.)
        EXPECT_NEAR(length(cross(offset, d)), shift, 2e-4f);
        // Nothing absorbs or reflects: the background comes through unchanged.
        expect_vec_near(traced.color, {0.3f, 0.5f, 0.7f});
    }
}

TEST(WhittedTest, TotalInternalReflectionSendsNoTransmittedRay) {
    const Scene scene = glass_slab({0.3f, 0.5f, 0.7f});
    // From inside the slab towards its top face at 60° from the normal: beyond the critical 41.8°.
    const float a = 60 * kPi / 180;
    const Traced tir = trace(scene, tracing(5), {{0, 0, -0.5f}, {std::sin(a), 0, std::cos(a)}});
    EXPECT_EQ(tir.counts.secondary, 0u);
    EXPECT_TRUE(tir.tree.rays[0].total_internal_reflection);
    expect_vec_near(tir.color, {0, 0, 0});  // black glass, nothing reflected, nothing through
    // At 30° the ray gets out, bent to sin θt = 1.5·sin 30° = 0.75, and sees the background.
    const float b = 30 * kPi / 180;
    const Traced out = trace(scene, tracing(5), {{0, 0, -0.5f}, {std::sin(b), 0, std::cos(b)}});
    EXPECT_EQ(out.counts.secondary, 1u);
    EXPECT_FALSE(out.tree.rays[0].total_internal_reflection);
    EXPECT_NEAR(out.tree.rays[1].direction.x, 0.75f, 1e-6f);
    expect_vec_near(out.color, {0.3f, 0.5f, 0.7f});
}

TEST(WhittedTest, ReflectedAndTransmittedColoursAddUpWithTheirMultipliers) {
    // A glass sphere with both colours, in front of a background: at the centre of its front face
    // the ray enters straight; the mirror ray goes straight back (to the background), the
    // transmitted one crosses the sphere and leaves straight through the back (background again).
    const Vec3f reflective{0.25f, 0.25f, 0.25f}, transparent{0.5f, 0.5f, 0.5f};
    const Scene scene = build(scene_of(sphere({0, 0, 0}, 1, 0), {glass(transparent, 1.5f, reflective)},
                                       {0.2f, 0.4f, 0.8f}, {0, 0, 0}));
    const Traced traced = trace(scene, tracing(2), {{0, 0, 10}, {0, 0, -1}});
    // front: r·B + t·(inside: r·(back at the front face … cut at depth 2) + t·B)
    //   depth 1 inside ray hits the back face: its reflected child (depth 2) meets the front face
    //   from inside and stops there (bounce limit) with local colour 0; its transmitted child
    //   leaves into the background.
    const Vec3f background{0.2f, 0.4f, 0.8f};
    const Vec3f inside = reflective * Vec3f{0, 0, 0} + transparent * background;
    expect_vec_near(traced.color, reflective * background + transparent * inside);
    EXPECT_EQ(traced.counts.secondary, 4u);  // reflected, transmitted; inside: reflected, transmitted
}

// ---------------------------------------------------------------------------------------------
// Lights and shadows.

// Found through the generated scenes (one of them made a transparent-shadow walk of 65,536 rays
// for one camera sample, the budget's limit, and took 1.6 s for 8x6 pixels): new rays
// were moved off a surface along its shading normal, which on a mesh with vertex normals may point
// to the other side of the triangle; the shadow ray then met the same triangle again, and again,
// each time filtered by its transparentColor. Here the triangle lies in z = 0 facing +z, its vertex
// normal (-0.6, 0, 0.8) leans away from a light that grazes the plane from above: each shadow ray
// must leave upwards and meet nothing, one ray per pixel.
TEST(WhittedTest, ShadowRaysLeaveASmoothMeshOnTheSideOfItsTriangle) {
    SceneDesc desc = scene_of(mesh_object(0), {glass({0.5f, 0.5f, 0.5f}, 1)}, {0, 0, 0}, {0, 0, 0},
                              {directional({-1, 0, -0.1f}, {1, 1, 1})});
    TriangleMesh mesh;
    mesh.positions = {{-10, -10, 0}, {10, -10, 0}, {0, 10, 0}};
    mesh.indices = {0, 1, 2};
    mesh.normals = {{-0.6f, 0, 0.8f}};
    mesh.normal_indices = {0, 0, 0};
    desc.meshes.push_back(MeshDesc{"leaning.obj", mesh});
    const Scene scene = build(std::move(desc));
    RenderOptions options;
    options.shadows = true;
    options.transparent_shadows = true;
    RenderStats stats;
    render_image(scene, options, &stats);
    EXPECT_EQ(stats.hits, 64u);  // the 8x8 camera sees nothing but the triangle
    EXPECT_EQ(stats.shadow_rays, 64u);
    EXPECT_EQ(stats.truncated_samples, 0u);
}

// A shadow ray only takes a light's share away: none is traced towards a light that adds nothing
// (behind the surface, no highlight), in rendering as in explain, and the colour is the same.
TEST(WhittedTest, NoShadowRayGoesTowardsALightThatAddsNothing) {
    // The unit sphere's pole (0, 0, 1) seen from above, N = V = +z. One light shines on it from
    // above (to the light: +z), the other from below (to the light: −z, so N·L = −1 and
    // R = 2·(−1)·N − L = −z, V·R = −1: no diffuse, no highlight).
    const Scene scene = build(scene_of(sphere({0, 0, 0}, 1, 0), {material({0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 20)},
                                       {0, 0, 0}, {0, 0, 0},
                                       {directional({0, 0, -1}, {1, 1, 1}), directional({0, 0, 1}, {1, 1, 1})}));
    RenderOptions options;
    options.shadows = true;
    const Traced traced = trace(scene, options, {{0, 0, 5}, {0, 0, -1}});
    expect_vec_near(traced.color, {1, 1, 1});  // kd·1 + ks·1 from the light above, nothing from below
    EXPECT_EQ(traced.counts.shadow, 1u);
    const RayRecord& pole = traced.tree.rays[0];
    ASSERT_EQ(pole.lights.size(), 2u);
    EXPECT_TRUE(pole.lights[0].shadow_ray);
    EXPECT_FALSE(pole.lights[1].shadow_ray);
    expect_vec_near(pole.lights[1].contribution, {0, 0, 0});
    int shadow_records = 0;
    for (const RayRecord& r : traced.tree.rays) shadow_records += r.kind == RayKind::Shadow ? 1 : 0;
    EXPECT_EQ(shadow_records, 1);
    // The whole image: every visible point faces the light above (N·L > 0); the one below adds
    // nothing around the pole (only near the outline can its highlight reach the camera).
    RenderStats stats;
    render_image(scene, options, &stats);
    EXPECT_GT(stats.hits, 0u);
    EXPECT_GE(stats.shadow_rays, stats.hits);
    EXPECT_LT(stats.shadow_rays, 2 * stats.hits);
}

TEST(WhittedTest, PointLightAttenuationDividesByTheQuadraticInTheDistance) {
    // The unit sphere's pole (0, 0, 1) seen from above, lit by a point light 4 above it: N·L = 1.
    for (const Vec3f a : {Vec3f{1, 0, 0}, Vec3f{1, 0.5f, 0}, Vec3f{0, 0, 0.25f}, Vec3f{0.5f, 0.25f, 0.125f}}) {
        LightDesc light = point_light({0, 0, 5}, {0.8f, 0.8f, 0.8f});
        light.attenuation = a;
        const Scene scene = build(scene_of(sphere({0, 0, 0}, 1, 0), {material({1, 1, 1})}, {0, 0, 0}, {0, 0, 0}, {light}));
        const float expected = 0.8f / (a.x + a.y * 4 + a.z * 16);
        expect_vec_near(trace(scene, tracing(0), {{0, 0, 10}, {0, 0, -1}}).color, {expected, expected, expected}, 1e-6f);
    }
}

// A floor y = 0 under a light straight above it, with a transparent object in between.
Scene filtered_light(ObjectDesc between) {
    MaterialDesc floor = material({1, 1, 1});
    return build(scene_of(group({plane({0, 1, 0}, 0, 0), std::move(between)}),
                          {floor, glass({0.5f, 0.25f, 1}, 1.0f)}, {0, 0, 0}, {0, 0, 0},
                          {directional({0, -1, 0}, {1, 1, 1})}));
}

TEST(WhittedTest, TransparentShadowsFilterTheLightByEverySurfaceCrossed) {
    Hit floor_hit;
    // The floor point (0.01, 0, 0.01) is lit with N·L = 1 and kd = 1: colour = what gets through.
    RenderOptions opaque = tracing(0);
    opaque.shadows = true;
    RenderOptions filtered = opaque;
    filtered.transparent_shadows = true;
    // A sheet y = 2 (one surface): the light times (0.5, 0.25, 1).
    const Scene sheet = filtered_light(plane({0, 1, 0}, 2, 1));
    const Ray from_floor{{0.01f, 1e-3f, 0.01f}, {0, -1, 0}};
    intersect(sheet, from_floor, 0, floor_hit);
    ASSERT_TRUE(floor_hit.is_hit());
    EXPECT_EQ(floor_hit.object, 0u);
    expect_vec_near(radiance_along(sheet, filtered, from_floor, floor_hit), {0.5f, 0.25f, 1});
    expect_vec_near(radiance_along(sheet, opaque, from_floor, floor_hit), {0, 0, 0});  // MIT's opaque shadows
    // A ball (two surfaces, in and out): the square of the colour.
    const Scene ball = filtered_light(sphere({0, 2, 0}, 0.5f, 1));
    Hit ball_floor;
    intersect(ball, from_floor, 0, ball_floor);
    ASSERT_EQ(ball_floor.object, 0u);
    expect_vec_near(radiance_along(ball, filtered, from_floor, ball_floor), {0.25f, 0.0625f, 1});
}

// ---------------------------------------------------------------------------------------------
// Ambient occlusion.

TEST(AmbientOcclusionTest, UnderACeilingTheOpenShareIsTheSquareOfHeightOverDistance) {
    // A floor y = 0 under a ceiling y = h. A ray at angle θ from the normal meets the ceiling at
    // h / cos θ, within reach D when cos θ > h/D; cosine-distributed, P(cos θ ≤ c) = c², so the
    // share that escapes is (h/D)². With h = 1 and D = 2: 0.25; D = 4: 0.0625.
    const Scene scene = build(scene_of(group({plane({0, 1, 0}, 0, 0), plane({0, -1, 0}, -1, 0)}),
                                       {material({1, 1, 1})}, {0, 0, 0}, {0, 0, 0}));
    for (const float distance : {2.0f, 4.0f}) {
        RenderOptions options;
        options.mode = RenderMode::AmbientOcclusion;
        options.ao_distance = distance;
        options.ao_samples = 4096;
        RayCounts counts;
        const Ray down{{0, 0.5f, 0}, {0, -1, 0}};
        Hit hit;
        intersect(scene, down, 0, hit);
        ASSERT_EQ(hit.object, 0u);
        const Vec3f grey = radiance_along(scene, options, down, hit, &counts);
        const float expected = (1 / distance) * (1 / distance);
        // 4096 rays: the standard error is √(p(1−p)/4096) ≤ 0.0068; allow 4 of them.
        EXPECT_NEAR(grey.x, expected, 0.027f) << distance;
        EXPECT_EQ(grey.x, grey.y);
        EXPECT_EQ(grey.x, grey.z);
        EXPECT_EQ(counts.occlusion, 4096u);
    }
}

TEST(AmbientOcclusionTest, TheDefaultReachIsATenthOfTheSceneDiagonal) {
    // Spheres at the origin and at (10, 0, 0), radius 1: the box is 12 × 2 × 2, diagonal √152.
    const Scene spheres = build(scene_of(group({sphere({0, 0, 0}, 1, 0), sphere({10, 0, 0}, 1, 0)}),
                                         {material({1, 1, 1})}, {0, 0, 0}, {0, 0, 0}));
    RenderOptions options;
    options.mode = RenderMode::AmbientOcclusion;
    // (The boxes are padded by 1/65536 of their coordinates, so not exactly.)
    EXPECT_NEAR(make_integrator(spheres, options).ao_distance, std::sqrt(152.0f) / 10, 1e-4f);
    options.ao_distance = 3;
    EXPECT_EQ(make_integrator(spheres, options).ao_distance, 3.0f);
    // Planes alone have no size: the rays look without limit.
    const Scene floor = build(scene_of(plane({0, 1, 0}, 0, 0), {material({1, 1, 1})}, {0, 0, 0}, {0, 0, 0}));
    options.ao_distance = 0;
    EXPECT_TRUE(std::isinf(make_integrator(floor, options).ao_distance));
    // An open floor is fully open, whatever the samples say; a miss is black.
    const Ray down{{0.3f, 2, 0.1f}, {0, -1, 0}};
    Hit hit;
    intersect(floor, down, 0, hit);
    expect_vec_near(radiance_along(floor, options, down, hit), {1, 1, 1});
    expect_vec_near(radiance_along(floor, options, {{0, 2, 0}, {0, 1, 0}}, Hit{}), {0, 0, 0});
}

TEST(AmbientOcclusionTest, TheImageIsTheSameOnAnyThreadsAndPacketsAndCountsEveryRay) {
    SceneDesc desc = scene_of(group({plane({0, 1, 0}, -1, 0), sphere({0, 0, 0}, 1, 0), sphere({1.5f, -0.5f, 1}, 0.5f, 0)}),
                              {material({1, 1, 1})}, {0, 0, 0}, {0, 0, 0});
    desc.camera->width = 24;
    desc.camera->height = 20;
    const Scene scene = build(std::move(desc));
    RenderOptions options;
    options.mode = RenderMode::AmbientOcclusion;
    options.threads = 1;
    options.packet_isa = PacketIsa::None;
    RenderStats reference_stats;
    const ImageRgb8 reference = render_image_rgb8(scene, options, &reference_stats);
    EXPECT_EQ(reference_stats.occlusion_rays, reference_stats.hits * 16);
    EXPECT_EQ(reference_stats.rays, reference_stats.primary_rays + reference_stats.occlusion_rays);
    options.threads = 3;
    options.packet_isa = best_packet_isa();
    options.tile_size = 5;
    EXPECT_TRUE(render_image_rgb8(scene, options).rgb == reference.rgb);
    // Somewhere (where the balls meet the floor) it is dark, elsewhere wholly open.
    uint8_t darkest = 255, lightest = 0;
    for (size_t i = 0; i < reference.rgb.size(); ++i) {
        darkest = std::min(darkest, reference.rgb[i]);
        lightest = std::max(lightest, reference.rgb[i]);
    }
    EXPECT_LT(darkest, 128);
    EXPECT_EQ(lightest, 255);
}

// ---------------------------------------------------------------------------------------------
// The ray budget.

TEST(WhittedTest, ARayTreeThatDoublesEveryBounceStopsAtTheBudgetAndSaysSo) {
    // Six planes round a box, each both mirror and glass: every hit spawns two rays, and a ray
    // that leaves the box still meets the other (infinite) planes, so the tree doubles each bounce.
    MaterialDesc both = glass({1, 1, 1}, 1.0f, {1, 1, 1});
    std::vector<ObjectDesc> walls;
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {-1.0f, 1.0f}) {
            Vec3f n{0, 0, 0};
            n[axis] = side;
            walls.push_back(plane(n, 2, 0));
        }
    SceneDesc desc = scene_of(group(walls), {both}, {0, 0, 0}, {0, 0, 0});
    desc.camera->center = {0.1f, 0.2f, 0.3f};
    desc.camera->direction = {0.13f, 0.21f, -1};  // no ray parallel to a wall
    desc.camera->width = desc.camera->height = 2;
    const Scene scene = build(std::move(desc));
    RenderOptions options = tracing(kMaxBounces, 0);
    options.threads = 2;
    RenderStats stats;
    render_image(scene, options, &stats);
    EXPECT_EQ(stats.truncated_samples, 4u);
    EXPECT_EQ(stats.primary_rays, 4u);
    EXPECT_EQ(stats.rays, 4u * (1 + kMaxRaysPerSample));
}

}  // namespace
}  // namespace raycast
