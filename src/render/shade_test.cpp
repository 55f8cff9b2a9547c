// Shading (render/shade.h) against values worked out by hand from the course's Phong formula
// (course-format.md §e, §f): I = Σ c_light ⊙ (kd·max(0, L·N) + ks·max(0, V·R)^s), R = 2(L·N)N − L,
// no gate of the specular term by L·N, no falloff for point lights, directional lights given by
// the way they travel; MIT 6.837's Blinn variants; the ambient rules and the back-face rules of
// Conventions; and offset_ray_origin, which must let a shadow ray leave its own surface at every
// scene scale. These are the numbers every pixel of a shaded image is made of.
#include "render/shade.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "render/integrator.h"
#include "scene/build_scene.h"
#include "scene_builders.h"

namespace raycast {
namespace {

using namespace test;  // the scene builders (tests/scene_builders.h)

void expect_vec_near(Vec3f actual, Vec3f expected, float tolerance = 1e-6f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << "x";
    EXPECT_NEAR(actual.y, expected.y, tolerance) << "y";
    EXPECT_NEAR(actual.z, expected.z, tolerance) << "z";
}

Material phong(Vec3f kd, Vec3f ks, float shininess) {
    Material m;
    m.diffuse = kd;
    m.specular = ks;
    m.shininess = shininess;
    return m;
}

// ---------------------------------------------------------------------------------------------
// reflect_light: one light, before its colour.

// N = +z throughout; L = (0, 0.6, 0.8) is 36.87° off the normal: N·L = 0.8 and its mirror image is
// R = 2·0.8·N − L = (0, −0.6, 0.8).
const Vec3f kN{0, 0, 1};
const Vec3f kL{0, 0.6f, 0.8f};

TEST(ReflectLightTest, DiffuseIsKdTimesTheClampedCosine) {
    const Material m = phong({0.2f, 0.4f, 0.6f}, {0, 0, 0}, 0);
    // kd·0.8, whatever the viewer.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, kN), {0.16f, 0.32f, 0.48f});
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, {0, -0.6f, 0.8f}), {0.16f, 0.32f, 0.48f});
    // Straight overhead: kd; grazing (L·N = 0) and from below: 0.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kN, kN), {0.2f, 0.4f, 0.6f});
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, {1, 0, 0}, kN), {0, 0, 0});
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, {0, 0.6f, -0.8f}, kN), {0, 0, 0});
    // The Blinn models share the diffuse term.
    expect_vec_near(reflect_light(m, SpecularModel::BlinnClampedByNdotL, kN, kL, kN), {0.16f, 0.32f, 0.48f});
    expect_vec_near(reflect_light(m, SpecularModel::BlinnTimesNdotL, kN, kL, kN), {0.16f, 0.32f, 0.48f});
}

TEST(ReflectLightTest, PhongSpecularIsKsTimesVdotRToTheShininess) {
    const Material m = phong({0, 0, 0}, {1, 0.5f, 0.25f}, 2);
    // V = R: V·R = 1, so ks.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, {0, -0.6f, 0.8f}), {1, 0.5f, 0.25f});
    // V = N: V·R = 0.8, 0.8² = 0.64.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, kN), {0.64f, 0.32f, 0.16f});
    // V = L: V·R = −0.36 + 0.64 = 0.28, 0.28² = 0.0784.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, kL), {0.0784f, 0.0392f, 0.0196f});
    // V·R < 0 clamps to 0: V = (0, 0.96, 0.28): V·R = −0.576 + 0.224 < 0.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, {0, 0.96f, 0.28f}), {0, 0, 0});
    // Shininess 20 at V = N: 0.8^20 = 0.011529215.
    const Material shiny = phong({0, 0, 0}, {1, 1, 1}, 20);
    expect_vec_near(reflect_light(shiny, SpecularModel::Phong, kN, kL, kN), {0.011529215f, 0.011529215f, 0.011529215f});
    // Diffuse and specular add: kd 0.5 at V = N gives 0.4 + 0.64·ks.
    const Material both = phong({0.5f, 0.5f, 0.5f}, {1, 0.5f, 0.25f}, 2);
    expect_vec_near(reflect_light(both, SpecularModel::Phong, kN, kL, kN), {1.04f, 0.72f, 0.56f});
}

TEST(ReflectLightTest, PhongSpecularIsNotGatedByNdotL) {
    // The light is below the surface: L = (0, 0.8, −0.6), N·L = −0.6, so no diffuse.
    // R = 2·(−0.6)·N − L = (0, −0.8, −0.6). A viewer above the surface at V = (0, −0.96, 0.28)
    // (V·N = 0.28 > 0) sees V·R = 0.768 − 0.168 = 0.6 > 0: the course's formula gives ks·0.6.
    const Material m = phong({1, 1, 1}, {1, 0.5f, 0.25f}, 1);
    const Vec3f below{0, 0.8f, -0.6f}, viewer{0, -0.96f, 0.28f};
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, below, viewer), {0.6f, 0.3f, 0.15f});
    // MIT's clamped Blinn gives nothing there, and neither does Blinn × N·L.
    expect_vec_near(reflect_light(m, SpecularModel::BlinnClampedByNdotL, kN, below, viewer), {0, 0, 0});
    expect_vec_near(reflect_light(m, SpecularModel::BlinnTimesNdotL, kN, below, viewer), {0, 0, 0});
}

TEST(ReflectLightTest, BlinnModelsMatchHandValues) {
    const Material m = phong({0, 0, 0}, {1, 0.5f, 0.25f}, 2);
    // V = N: H = normalize(L + V) = (0, 0.6, 1.8)/√3.6, N·H = 1.8/√3.6, (N·H)² = 3.24/3.6 = 0.9.
    expect_vec_near(reflect_light(m, SpecularModel::BlinnClampedByNdotL, kN, kL, kN), {0.9f, 0.45f, 0.225f});
    // Times N·L = 0.8: 0.72.
    expect_vec_near(reflect_light(m, SpecularModel::BlinnTimesNdotL, kN, kL, kN), {0.72f, 0.36f, 0.18f});
    // V the mirror direction (0, −0.6, 0.8): H = N, so (N·H)^s = 1: ks, and ks·0.8.
    expect_vec_near(reflect_light(m, SpecularModel::BlinnClampedByNdotL, kN, kL, {0, -0.6f, 0.8f}), {1, 0.5f, 0.25f});
    expect_vec_near(reflect_light(m, SpecularModel::BlinnTimesNdotL, kN, kL, {0, -0.6f, 0.8f}), {0.8f, 0.4f, 0.2f});
    // Phong at the same V = N gave 0.64: the models really differ.
    expect_vec_near(reflect_light(m, SpecularModel::Phong, kN, kL, kN), {0.64f, 0.32f, 0.16f});
    // Light exactly grazing (N·L = 0): the clamped model gives no highlight at all.
    const Vec3f grazing{0, 1, 0};
    expect_vec_near(reflect_light(m, SpecularModel::BlinnClampedByNdotL, kN, grazing, kN), {0, 0, 0});
    expect_vec_near(reflect_light(m, SpecularModel::BlinnTimesNdotL, kN, grazing, kN), {0, 0, 0});
}

// reflects_no_light: where a shadow ray could change nothing.

TEST(ReflectsNoLightTest, ALightBehindTheSurfaceWithNoHighlightGivesNothing) {
    // L = (0, 0, −1) straight below the surface, V = N: R = 2·(−1)·N − L = (0, 0, −1), V·R = −1.
    const Vec3f below{0, 0, -1};
    const Material m = phong({1, 1, 1}, {1, 1, 1}, 10);
    for (SpecularModel model :
         {SpecularModel::Phong, SpecularModel::BlinnClampedByNdotL, SpecularModel::BlinnTimesNdotL}) {
        EXPECT_TRUE(reflects_no_light(m, model, kN, below, kN)) << static_cast<int>(model);
        expect_vec_near(reflect_light(m, model, kN, below, kN), {0, 0, 0});
    }
    // A shininess of 0 makes the highlight ks·0⁰ = ks everywhere: the light adds something.
    const Material flat = phong({1, 1, 1}, {1, 1, 1}, 0);
    EXPECT_FALSE(reflects_no_light(flat, SpecularModel::Phong, kN, below, kN));
    expect_vec_near(reflect_light(flat, SpecularModel::Phong, kN, below, kN), {1, 1, 1});
    // Lit from above (N·L = 0.8) or showing the highlight of a light below (V·R = 0.6, the test
    // above): something.
    EXPECT_FALSE(reflects_no_light(m, SpecularModel::Phong, kN, kL, kN));
    EXPECT_FALSE(reflects_no_light(m, SpecularModel::Phong, kN, {0, 0.8f, -0.6f}, {0, -0.96f, 0.28f}));
}

TEST(ReflectsNoLightTest, IsTrueOnlyWhereBothTermsAreZero) {
    // Random unit vectors and materials, for every model: wherever it says "nothing", the terms
    // are exactly zero; and it says so at about a quarter of them (lights behind, no highlight).
    uint32_t state = 12345;
    const auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return static_cast<float>(state >> 8) / 16777216.0f;
    };
    const auto unit = [&] {
        for (;;) {
            const Vec3f v{2 * next() - 1, 2 * next() - 1, 2 * next() - 1};
            if (dot(v, v) > 0.01f && dot(v, v) <= 1) return normalize(v);
        }
    };
    for (SpecularModel model :
         {SpecularModel::Phong, SpecularModel::BlinnClampedByNdotL, SpecularModel::BlinnTimesNdotL}) {
        int nothing = 0;
        const int trials = 20000;
        for (int i = 0; i < trials; ++i) {
            const Material m = phong({next(), next(), next()}, {next(), next(), next()}, next() < 0.1f ? 0 : 100 * next());
            const Vec3f n = unit(), l = unit(), v = unit();
            if (!reflects_no_light(m, model, n, l, v)) continue;
            ++nothing;
            const LightReflection terms = reflect_light_terms(m, model, n, l, v);
            ASSERT_EQ(terms.diffuse, (Vec3f{0, 0, 0})) << static_cast<int>(model) << " trial " << i;
            ASSERT_EQ(terms.specular, (Vec3f{0, 0, 0})) << static_cast<int>(model) << " trial " << i;
        }
        EXPECT_GT(nothing, trials / 8) << static_cast<int>(model);
    }
}

// ---------------------------------------------------------------------------------------------
// shade: whole scenes.

SceneDesc desc_with(ObjectDesc root, std::vector<MaterialDesc> materials, std::vector<LightDesc> lights) {
    SceneDesc desc;
    desc.file = "shade.txt";
    CameraDesc camera;
    camera.center = {0, 0, 10};
    camera.angle_degrees = 30;
    camera.width = 4;
    camera.height = 4;
    desc.camera = camera;
    desc.materials = std::move(materials);
    desc.lights = std::move(lights);
    desc.has_lights_block = !desc.lights.empty();
    desc.root = std::move(root);
    return desc;
}

// The colour seen along a ray (which must hit something).
Vec3f shade_along(const Scene& scene, Vec3f origin, Vec3f direction, bool shadows = false) {
    const Ray ray{origin, direction};
    Hit hit;
    intersect(scene, ray, 0, hit);
    EXPECT_TRUE(hit.is_hit());
    if (!hit.is_hit()) return {-1, -1, -1};
    RenderOptions options;
    options.shadows = shadows;
    return radiance_along(scene, options, ray, hit);
}

// The unit sphere at the origin seen from (0, 0, 5) straight down −z: the hit is (0, 0, 1), N = V = +z.
Vec3f shade_sphere_pole(std::vector<MaterialDesc> materials, std::vector<LightDesc> lights) {
    const Scene scene = build(desc_with(sphere({0, 0, 0}, 1), std::move(materials), std::move(lights)));
    return shade_along(scene, {0, 0, 5}, {0, 0, -1});
}

TEST(ShadeTest, PointLightHasNoFalloff) {
    // Light at (0, 3, 5): from (0, 0, 1) the offset is (0, 3, 4), distance 5, L = (0, 0.6, 0.8), N·L = 0.8.
    // kd (0.5, 1, 0.25)·0.8 = (0.4, 0.8, 0.2), times the colour (1, 0.5, 2): (0.4, 0.4, 0.4).
    const std::vector<MaterialDesc> kd = {material({0.5f, 1, 0.25f})};
    expect_vec_near(shade_sphere_pole(kd, {point_light({0, 3, 5}, {1, 0.5f, 2})}), {0.4f, 0.4f, 0.4f});
    // Ten times as far in the same direction (distance 50): the same colour.
    expect_vec_near(shade_sphere_pole(kd, {point_light({0, 30, 41}, {1, 0.5f, 2})}), {0.4f, 0.4f, 0.4f});
    // MIT 6.837's attenuation, when a file gives it: 1/(c + l·d + q·d²) = 1/(1 + 0 + 0.04·25) = 1/2.
    LightDesc attenuated = point_light({0, 3, 5}, {1, 0.5f, 2});
    attenuated.attenuation = {1, 0, 0.04f};
    expect_vec_near(shade_sphere_pole(kd, {attenuated}), {0.2f, 0.2f, 0.2f});
}

TEST(ShadeTest, DirectionalLightDirectionIsTheWayTheLightTravels) {
    const std::vector<MaterialDesc> kd = {material({0.5f, 1, 0.25f})};
    // Travelling (0, −0.6, −0.8) (down and away from the viewer): L = (0, 0.6, 0.8), N·L = 0.8.
    expect_vec_near(shade_sphere_pole(kd, {directional({0, -0.6f, -0.8f}, {1, 1, 1})}), {0.4f, 0.8f, 0.2f});
    // Not unit length: normalised, the same light.
    expect_vec_near(shade_sphere_pole(kd, {directional({0, -3, -4}, {1, 1, 1})}), {0.4f, 0.8f, 0.2f});
    // Travelling the other way, it lights the far side only.
    expect_vec_near(shade_sphere_pole(kd, {directional({0, 0.6f, 0.8f}, {1, 1, 1})}), {0, 0, 0});
}

TEST(ShadeTest, LightsAreSummed) {
    // kd 0.5, ks 0.25, s = 2, seen along −z at the pole (V = N = +z).
    // Light 1, directional travelling (0, −0.6, −0.8), white: 0.5·0.8 + 0.25·0.8² = 0.56.
    // Light 2, point at (0, 0, 11), colour (0.5, 0, 1): L = N, V·R = 1: (0.5 + 0.25)·colour = (0.375, 0, 0.75).
    const std::vector<MaterialDesc> m = {material({0.5f, 0.5f, 0.5f}, {0.25f, 0.25f, 0.25f}, 2)};
    const LightDesc one = directional({0, -0.6f, -0.8f}, {1, 1, 1});
    const LightDesc two = point_light({0, 0, 11}, {0.5f, 0, 1});
    expect_vec_near(shade_sphere_pole(m, {one}), {0.56f, 0.56f, 0.56f});
    expect_vec_near(shade_sphere_pole(m, {two}), {0.375f, 0, 0.75f});
    expect_vec_near(shade_sphere_pole(m, {one, two}), {0.935f, 0.56f, 1.31f});
    // No lights and no ambient: black.
    expect_vec_near(shade_sphere_pole(m, {}), {0, 0, 0});
}

TEST(ShadeTest, CourseModelLightsTheHighlightOfALightBelowTheSurface) {
    // The floor y = 0 seen from (0, 1, 1) along (0, −1, −1): hit (0, 0, 0), N = +y, V = (0, 1, 1)/√2.
    // The light travels (0, 0.6, 0.8) (upwards), so L = (0, −0.6, −0.8) is below the floor: N·L = −0.6.
    // R = 2·(−0.6)·N − L = (0, −0.6, 0.8); V·R = (−0.6 + 0.8)/√2 = 0.14142136 > 0.
    // kd 1, ks 1, s = 1: diffuse 0 and specular 0.14142136, which the course's formula keeps.
    const SceneDesc desc = desc_with(plane({0, 1, 0}, 0), {material({1, 1, 1}, {1, 1, 1}, 1)},
                                     {directional({0, 0.6f, 0.8f}, {1, 1, 1})});
    const float expected = 0.2f / std::sqrt(2.0f);
    expect_vec_near(shade_along(build(desc), {0, 1, 1}, {0, -1, -1}), {expected, expected, expected});
    // With MIT's clamped Blinn model the same point is black.
    Conventions blinn;
    blinn.specular = SpecularModel::BlinnClampedByNdotL;
    expect_vec_near(shade_along(build(desc, blinn), {0, 1, 1}, {0, -1, -1}), {0, 0, 0});
}

TEST(ShadeTest, AmbientLightFollowsTheConventions) {
    const Vec3f kd{0.2f, 0.4f, 0.6f};
    SceneDesc desc = desc_with(sphere({0, 0, 0}, 1), {material(kd)}, {});
    const auto pole = [&](const SceneDesc& d, Conventions c) { return shade_along(build(d, c), {0, 0, 5}, {0, 0, -1}); };
    // The course: no ambient term unless a file gives one (the handout's scenes never do).
    expect_vec_near(pole(desc, Conventions::course()), {0, 0, 0});
    // MIT 6.837: a scene without a Lights block is lit by ambient 1 1 1, so it shows kd...
    expect_vec_near(pole(desc, Conventions::mit6837()), kd);
    // ...but one with a Lights block (even an empty one) is not.
    SceneDesc with_block = desc;
    with_block.has_lights_block = true;
    expect_vec_near(pole(with_block, Conventions::mit6837()), {0, 0, 0});
    // A given ambientLight multiplies kd, under either convention.
    SceneDesc ambient = desc;
    ambient.ambient = Vec3f{0.5f, 0.5f, 1};
    expect_vec_near(pole(ambient, Conventions::course()), {0.1f, 0.2f, 0.6f});
    expect_vec_near(pole(ambient, Conventions::mit6837()), {0.1f, 0.2f, 0.6f});
    // Ambient plus a light: kd·ambient + kd·N·L, N·L = 0.8 for a light travelling (0, −0.6, −0.8).
    ambient.lights.push_back(directional({0, -0.6f, -0.8f}, {1, 1, 1}));
    ambient.has_lights_block = true;
    expect_vec_near(pole(ambient, Conventions::course()), {0.1f + 0.16f, 0.2f + 0.32f, 0.6f + 0.48f});
}

TEST(ShadeTest, BackFacesFollowTheConventions) {
    // A triangle in z = 0 wound clockwise as seen from the camera at +z: its normal is −z
    // (cross((0, 2, 0), (2, 0, 0)) = (0, 0, −4)), so the viewer at +z sees its back.
    // Light A travels −z (L = +z, the viewer's side), red; light B travels +z (L = −z), green.
    // kd 1, ambient 0.25.
    const Vec3f a{-1, -1, 0}, b{-1, 1, 0}, c{1, -1, 0};
    const std::vector<LightDesc> lights = {directional({0, 0, -1}, {1, 0, 0}), directional({0, 0, 1}, {0, 1, 0})};
    SceneDesc back = desc_with(triangle(a, b, c), {material({1, 1, 1})}, lights);
    back.ambient = Vec3f{0.25f, 0.25f, 0.25f};
    SceneDesc front = back;
    front.root = triangle(a, c, b);  // normal +z
    const Vec3f origin{-0.5f, -0.5f, 5}, down{0, 0, -1};

    // Course: the normal as the geometry gives it (−z): lit by B only: (0.25, 1.25, 0.25).
    expect_vec_near(shade_along(build(back), origin, down), {0.25f, 1.25f, 0.25f});
    // black_back_faces: black, ambient included.
    Conventions black;
    black.black_back_faces = true;
    expect_vec_near(shade_along(build(back, black), origin, down), {0, 0, 0});
    expect_vec_near(shade_along(build(back, Conventions::mit6837()), origin, down), {0, 0, 0});
    // shade_back_faces: the normal is turned towards the viewer (+z): lit by A only: (1.25, 0.25, 0.25).
    Conventions flip;
    flip.shade_back_faces = true;
    expect_vec_near(shade_along(build(back, flip), origin, down), {1.25f, 0.25f, 0.25f});
    // Both set (MIT with -shade_back): shading the back face wins.
    Conventions both = Conventions::mit6837();
    both.shade_back_faces = true;
    expect_vec_near(shade_along(build(back, both), origin, down), {1.25f, 0.25f, 0.25f});
    // A front face is never affected.
    for (const Conventions& conv : {Conventions::course(), black, flip, both})
        expect_vec_near(shade_along(build(front, conv), origin, down), {1.25f, 0.25f, 0.25f});
    // A sphere seen from inside is a back face too.
    SceneDesc inside = desc_with(sphere({0, 0, 0}, 2), {material({1, 1, 1})}, lights);
    expect_vec_near(shade_along(build(inside, black), {0, 0, 0}, {0, 0, -1}), {0, 0, 0});
    expect_vec_near(shade_along(build(inside, flip), {0, 0, 0}, {0, 0, -1}), {1, 0, 0});
    expect_vec_near(shade_along(build(inside), {0, 0, 0}, {0, 0, -1}), {0, 1, 0});
}

TEST(ShadeTest, ShadowsRemoveOnlyLightsThatSomethingBlocks) {
    // The floor y = 0 and a unit sphere at (0, 2, 0) above the origin. The ray from (0, 3, 8) along
    // (0, −3, −8) passes 1.87 from the sphere's centre, so it reaches the floor at the origin (N = +y).
    const auto floor_point = [](std::vector<LightDesc> lights, bool shadows) {
        SceneDesc desc = desc_with(group({plane({0, 1, 0}, 0), sphere({0, 2, 0}, 1)}), {material({0.5f, 0.5f, 0.5f})},
                                   std::move(lights));
        desc.ambient = Vec3f{0.1f, 0.1f, 0.1f};
        return shade_along(build(desc), {0, 3, 8}, {0, -3, -8}, shadows);
    };
    // A point light straight above at (0, 10, 0): N·L = 1, so 0.05 + 0.5 lit and only the ambient 0.05 in shadow.
    const LightDesc above = point_light({0, 10, 0}, {1, 1, 1});
    expect_vec_near(floor_point({above}, false), {0.55f, 0.55f, 0.55f});
    expect_vec_near(floor_point({above}, true), {0.05f, 0.05f, 0.05f});
    // A directional light from straight above is blocked the same way.
    expect_vec_near(floor_point({directional({0, -1, 0}, {1, 1, 1})}, true), {0.05f, 0.05f, 0.05f});
    // A point light between the floor and the sphere (at y = 0.5) is not blocked by what lies beyond it.
    expect_vec_near(floor_point({point_light({0, 0.5f, 0}, {1, 1, 1})}, true), {0.55f, 0.55f, 0.55f});
    // Two lights, one blocked: only the other counts. Light at (0, 0.5, 0.5) is 45° off: N·L = 0.7071068.
    const LightDesc side = point_light({0, 0.5f, 0.5f}, {1, 1, 1});
    expect_vec_near(floor_point({above, side}, true), {0.05f + 0.5f * 0.70710678f, 0.05f + 0.5f * 0.70710678f,
                                                     0.05f + 0.5f * 0.70710678f});
    // The top of the sphere itself is not shadowed by its own surface.
    SceneDesc desc = desc_with(group({plane({0, 1, 0}, 0), sphere({0, 2, 0}, 1)}), {material({0.5f, 0.5f, 0.5f})},
                               {above});
    const Scene scene = build(desc);
    expect_vec_near(shade_along(scene, {0, 10, 0.5f}, {0, -1, 0}, true), shade_along(scene, {0, 10, 0.5f}, {0, -1, 0}, false));
    EXPECT_GT(shade_along(scene, {0, 10, 0.5f}, {0, -1, 0}, true).x, 0.4f);
}

// ---------------------------------------------------------------------------------------------
// offset_ray_origin

TEST(OffsetRayOriginTest, MovesATinyStepAlongTheNormalTowardsTheGivenSide) {
    const Vec3f p{1, 2, 3}, n{0, 0, 1};
    const float scale = ray_travel_scale({0, 0, 0}, {0, 0, 1}, 3);
    EXPECT_EQ(scale, 3.0f);
    const Vec3f up = offset_ray_origin(p, n, {0.3f, 0, 0.5f}, scale);
    const Vec3f down = offset_ray_origin(p, n, {0.3f, 0, -0.5f}, scale);
    EXPECT_GT(up.z, 3.0f);
    EXPECT_LT(down.z, 3.0f);
    EXPECT_EQ(up.x, 1.0f);
    EXPECT_EQ(up.y, 2.0f);
    // The step is a small multiple of the rounding error of the coordinates (about 2.4e-7 at 3),
    // far below anything visible.
    EXPECT_LT(up.z - 3.0f, 1e-4f);
    // The same whether the normal points to the side or away from it.
    const Vec3f flipped = offset_ray_origin(p, -n, {0.3f, 0, 0.5f}, scale);
    EXPECT_EQ(flipped.z, up.z);
    // At the origin it still moves (a tiny absolute floor).
    EXPECT_GT(offset_ray_origin({0, 0, 0}, n, n, 0).z, 0.0f);
}

TEST(OffsetRayOriginTest, TheStepGrowsWithTheRayThatFoundThePoint) {
    // (0.1, 0, 0) found from (0, 0, 100) along (0.001, 0, −1) at t = 100: the numbers were near 100.
    EXPECT_FLOAT_EQ(ray_travel_scale({0, 0, 100}, {0.001f, 0, -1}, 100), 200.0f);
    // A negative t (orthographic cameras that see behind themselves) counts by its size.
    EXPECT_FLOAT_EQ(ray_travel_scale({0, 0, 1}, {0, 0, 2}, -3), 7.0f);
    const Vec3f n{0, 0, 1}, p{0.1f, 0, 0};
    // 16 ulps of 200 (ulp 1.5e-5) and 64 of 0.1 (ulp 7.5e-9): 2.4e-4 + 4.8e-7.
    EXPECT_NEAR(offset_ray_origin(p, n, n, 200).z, 16 * 1.52587891e-5f + 64 * 7.4505806e-9f, 1e-9f);
    EXPECT_GT(offset_ray_origin(p, n, n, 200).z, 100 * offset_ray_origin(p, n, n, 0).z);
}

// ray_offset_distance finds ulps from bit patterns and maxima by comparisons, not through
// std::nextafter and std::fmax (library calls): the same floats, worked out here the library way
// for ordinary, tiny, huge, zero, infinite and NaN coordinates.
TEST(OffsetRayOriginTest, TheStepIsTheLibraryFormulaForEveryKindOfFloat) {
    const auto library_ulp = [](float x) {
        x = std::fabs(x);
        return std::nextafter(x, INFINITY) - x;
    };
    const auto library_max_abs = [](Vec3f v) {
        return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float values[] = {0.0f, -0.0f, 1e-45f, 1e-38f, 0.1f, -3.0f, 200.0f, 1e38f, -3.4e38f, INFINITY, -INFINITY, nan};
    const auto same = [](float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); };
    for (float a : values)
        for (float b : values) {
            const Vec3f p{a, b, 0.5f}, q{0.25f, a, b};
            EXPECT_TRUE(same(max_abs(p), library_max_abs(p))) << a << ", " << b;
            EXPECT_TRUE(same(max_abs(q), library_max_abs(q))) << a << ", " << b;
            const float expected_scale = library_max_abs(p) + std::fabs(b) * library_max_abs(q);
            EXPECT_TRUE(same(ray_travel_scale(p, q, b), std::isfinite(expected_scale) ? expected_scale : 0.0f))
                << a << ", " << b;
            const float expected = 64 * library_ulp(library_max_abs(p)) + 16 * library_ulp(b) + 1e-30f;
            EXPECT_TRUE(same(ray_offset_distance(p, b), expected)) << a << ", " << b;
        }
    // Both NaN: NaN, as std::fmax gives.
    EXPECT_TRUE(std::isnan(max_abs({nan, nan, nan})));
}

// Unit vector perpendicular to n.
Vec3f tangent_of(Vec3f n) {
    const Vec3f other = std::fabs(n.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
    return normalize(cross(n, other));
}

TEST(OffsetRayOriginTest, ShadowRaysDoNotReHitTheirOwnSurfaceAtAnyScale) {
    // For each scale s from 1e-3 to 1e4: one convex object (a sphere, an ellipsoid, a cube mesh,
    // a tilted plane) placed about 5s from the origin. Every shadow ray that leaves a hit point on
    // the lit side (N·L > 0) stays outside a convex object, so occluded() must say no, from grazing
    // (N·L = 0.02) to straight out. Without the offset a good share of these rays re-hit the surface.
    int rays = 0, raw_self_hits = 0;
    for (int e = -3; e <= 4; ++e) {
        const float s = std::pow(10.0f, static_cast<float>(e));
        const Vec3f place = s * Vec3f{3, -2, 4.5f};
        std::vector<ObjectDesc> objects;
        objects.push_back(transform(Mat4::translate(place), sphere({0, 0, 0}, s)));
        objects.push_back(transform(Mat4::translate(place) * Mat4::rotate({1, 1, 0}, 30) *
                                        Mat4::scale({2 * s, s, 0.5f * s}),
                                    sphere({0, 0, 0}, 1)));
        ObjectDesc mesh_object;
        mesh_object.kind = ObjectDesc::Kind::TriangleMesh;
        mesh_object.mesh = 0;
        mesh_object.material = 0;
        objects.push_back(transform(Mat4::translate(place) * Mat4::rotate({0, 1, 1}, 20) * Mat4::scale({s, s, s}),
                                    mesh_object));
        const Vec3f plane_normal = normalize(Vec3f{0.2f, 0.9f, 0.3f});
        objects.push_back(plane(plane_normal, dot(plane_normal, place)));
        for (size_t k = 0; k < objects.size(); ++k) {
            SceneDesc desc = desc_with(objects[k], {material({1, 1, 1})}, {});
            desc.meshes.push_back({"cube.obj", cube_mesh()});
            const Scene scene = build(desc);
            // Rays from a viewpoint outside the object, near it and 300 times as far, towards
            // points spread over it: the far one finds points only as accurate as its long rays.
            for (const float far : {1.0f, 300.0f})
            for (int i = -3; i <= 3; ++i)
                for (int j = -3; j <= 3; ++j) {
                    const Vec3f target = place + s * Vec3f{0.3f * static_cast<float>(i), 0.3f * static_cast<float>(j),
                                                           0.1f * static_cast<float>(i * j)};
                    const Vec3f eye = place + far * s * Vec3f{1.5f, 2.5f, 6};
                    const Ray ray{eye, normalize(target - eye)};
                    Hit hit;
                    intersect(scene, ray, 0, hit);
                    if (!hit.is_hit()) continue;
                    const SurfacePoint surface = surface_at(scene, ray, hit);
                    const Vec3f n = dot(surface.normal, ray.direction) < 0 ? surface.normal : -surface.normal;
                    const Vec3f t = tangent_of(n);
                    const Vec3f t2 = cross(n, t);
                    for (float cosine : {1.0f, 0.5f, 0.1f, 0.02f})
                        for (const Vec3f side : {t, -t, t2, -t2}) {
                            const float sine = std::sqrt(1 - cosine * cosine);
                            const Vec3f to_light = normalize(cosine * n + sine * side);
                            const Vec3f origin = offset_ray_origin(
                                surface.position, n, to_light, ray_travel_scale(ray.origin, ray.direction, hit.t));
                            ++rays;
                            EXPECT_FALSE(occluded(scene, {origin, to_light}, 0, INFINITY))
                                << "scale " << s << " object " << k << " cosine " << cosine << " far " << far;
                            // The step stays tiny next to the object, or next to the ray's length.
                            EXPECT_LT(length(origin - surface.position), 1e-4f * s * far);
                            if (occluded(scene, {surface.position, to_light}, 0, INFINITY)) ++raw_self_hits;
                        }
                }
        }
    }
    EXPECT_GT(rays, 5000);
    // The test is not vacuous: from the raw hit points many of these shadow rays do hit the surface.
    EXPECT_GT(raw_self_hits, rays / 20);
}

}  // namespace
}  // namespace raycast
