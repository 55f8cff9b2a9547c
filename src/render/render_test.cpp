// render_image (render/render.h) on small scenes built in code or read with load_scene_text.
// The image must not depend on how it was made: every SIMD packet width this CPU runs, one ray at
// a time, any thread count and tile size, a crop window, all give the same pixels, and with one
// sample per pixel those are exactly camera_ray + intersect + shade per pixel (brute force).
// Also: supersampling (deterministic, and only edges change), shadows, the debug modes (normals,
// depth, material, cost) at hand-checked pixels, the background, MIT's pixel centres, and no
// NaN or infinity even with degenerate geometry.
#include "render/render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/shade.h"
#include "scene/build_scene.h"
#include "sceneio/load_scene.h"
#include "scene_builders.h"
#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // the scene builders (tests/scene_builders.h)

// ---------------------------------------------------------------------------------------------
// Scene building blocks.

CameraDesc camera(Vec3f center, Vec3f direction, float angle, int w, int h) {
    return perspective(center, direction, {0, 1, 0}, angle, w, h);
}

// A unit sphere of triangles (sphere_mesh) with smooth vertex normals, so that the barycentric
// u, v of every hit show in the shading.
TriangleMesh smooth_sphere_mesh(int stacks, int slices) {
    TriangleMesh mesh = sphere_mesh({0, 0, 0}, 1, stacks, slices);
    mesh.normals = mesh.positions;
    mesh.normal_indices = mesh.indices;
    return mesh;
}

// A wavy height field of (n − 1)² quads over [−3, 3]², no normals.
TriangleMesh terrain_mesh(int n) {
    TriangleMesh mesh;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x = -3 + 6 * static_cast<float>(i) / static_cast<float>(n - 1);
            const float z = -3 + 6 * static_cast<float>(j) / static_cast<float>(n - 1);
            mesh.positions.push_back({x, 0.3f * std::sin(2 * x) * std::cos(1.5f * z), z});
        }
    const auto at = [n](int i, int j) { return static_cast<uint32_t>(i * n + j); };
    for (int i = 0; i + 1 < n; ++i)
        for (int j = 0; j + 1 < n; ++j)
            mesh.indices.insert(mesh.indices.end(),
                                {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    return mesh;
}

// Meshes only: a smooth sphere mesh, the cube twice and a wavy terrain, 37×29 (not a multiple of
// any packet block), a tilted camera, a point and a directional light, specular highlights.
Scene mesh_scene() {
    SceneDesc desc;
    desc.file = "meshes.txt";
    desc.camera = camera({1, 2.5f, 8}, {-0.1f, -0.3f, -1}, 35, 37, 29);
    desc.background = {0.1f, 0.2f, 0.7f};
    desc.materials = {material({0.8f, 0.6f, 0.4f}, {0.7f, 0.7f, 0.7f}, 20), material({0.2f, 0.7f, 0.3f}),
                      material({0.5f, 0.5f, 0.9f}, {0.3f, 0.3f, 0.3f}, 4)};
    desc.lights = {directional({-0.5f, -0.5f, -1}, {0.6f, 0.6f, 0.6f}), point_light({0, 5, 5}, {0.8f, 0.8f, 0.4f})};
    desc.has_lights_block = true;
    desc.meshes.push_back({"sphere.obj", smooth_sphere_mesh(12, 16)});
    desc.meshes.push_back({"cube.obj", cube_mesh()});
    desc.meshes.push_back({"terrain.obj", terrain_mesh(16)});
    desc.root = group({mesh_object(0, 0), mesh_object(2, 1),
                       transform(Mat4::translate({1.8f, 0.2f, 0.5f}) * Mat4::rotate({1, 1, 0}, 30) *
                                     Mat4::scale({0.5f, 0.5f, 0.5f}),
                                 mesh_object(1, 2)),
                       transform(Mat4::translate({-2, 0.6f, -1}) * Mat4::rotate_y(40), mesh_object(1, 2))});
    return build(std::move(desc));
}

// Spheres on a floor, as a scene file (scene01 with more colour and a second light).
const char* const kSpheresText = R"(PerspectiveCamera {
    center 0 0 10
    direction 0 0 -1
    up 0 1 0
    angle 30
    width 37
    height 29
}
Lights {
    numLights 2
    PointLight { position 0 5 5 color 0.9 0.9 0.9 }
    DirectionalLight { direction -0.5 -0.3 -1 color 0.3 0.2 0.1 }
}
Background { color 0.1 0.7 0.2 }
Materials {
    numMaterials 3
    PhongMaterial { diffuseColor 1 0 0 specularColor 1 1 1 shininess 20 }
    Material { diffuseColor 0 1 0 }
    Material { diffuseColor 0 0 1 specularColor 0.5 0.5 0.5 shininess 4 }
}
Group {
    numObjects 6
    MaterialIndex 0
    Sphere { center 0 0 0 radius 1 }
    MaterialIndex 1
    Sphere { center 1 1 1 radius 0.75 }
    Sphere { center -1 -1 1 radius 0.75 }
    MaterialIndex 2
    Sphere { center -1 1 -1 radius 0.75 }
    Sphere { center 1 -1 -1 radius 0.75 }
    Plane { normal 0 1 0 offset -2 }
}
)";

Scene spheres_scene(Conventions conventions = Conventions::course()) {
    return build(load_scene_text(kSpheresText, "spheres.txt"), conventions);
}

// Transforms of every kind of shape, nested, with one mesh used twice.
Scene transformed_scene() {
    SceneDesc desc;
    desc.file = "transformed.txt";
    desc.camera = camera({0.5f, 1, 9}, {-0.05f, -0.1f, -1}, 32, 37, 29);
    desc.background = {0, 0, 0};
    desc.materials = {material({0.9f, 0.3f, 0.3f}, {1, 1, 1}, 16), material({0.3f, 0.9f, 0.3f}),
                      material({0.4f, 0.4f, 0.9f}, {0.5f, 0.5f, 0.5f}, 8)};
    desc.lights = {directional({-0.2f, -0.4f, -0.8f}, {0.8f, 0.8f, 0.8f}), point_light({-3, 4, 4}, {0.4f, 0.4f, 0.4f})};
    desc.has_lights_block = true;
    desc.meshes.push_back({"cube.obj", cube_mesh()});
    desc.meshes.push_back({"sphere.obj", smooth_sphere_mesh(8, 10)});
    desc.root = group({
        transform(Mat4::translate({-1.5f, 0.5f, 0}) * Mat4::rotate_z(30) * Mat4::scale({1, 0.3f, 0.6f}),
                  sphere({0, 0, 0}, 1, 0)),
        transform(Mat4::translate({1.5f, -0.5f, -1}) * Mat4::rotate({1, 1, 1}, 25) * Mat4::scale({0.6f, 0.6f, 0.6f}),
                  mesh_object(0, 1)),
        transform(Mat4::translate({0, 1.5f, -2}) * Mat4::rotate_y(45) * Mat4::scale({0.4f, 1, 0.4f}), mesh_object(0, 2)),
        transform(Mat4::rotate_x(-10), plane({0, 1, 0}, -1.5f, 1)),
        transform(Mat4::translate({0.5f, -1, 1}), triangle({0, 0, 0}, {1, 0, 0.2f}, {0.3f, 1, 0}, 0)),
        transform(Mat4::translate({-1, -1, 1}), transform(Mat4::scale({0.5f, 0.7f, 0.5f}), mesh_object(1, 2))),
    });
    return build(std::move(desc));
}

// ---------------------------------------------------------------------------------------------
// Helpers.

RenderOptions options_with(PacketIsa isa = best_packet_isa()) {
    RenderOptions options;
    options.packet_isa = isa;
    return options;
}

// Float images compared bit for bit (NaN-safe), reporting the first difference.
::testing::AssertionResult same_floats(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        return ::testing::AssertionFailure() << "sizes " << a.width << "x" << a.height << " and " << b.width << "x"
                                             << b.height;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const Vec3f p = a.at(x, y), q = b.at(x, y);
            if (std::memcmp(&p, &q, sizeof p) != 0)
                return ::testing::AssertionFailure() << "pixel (" << x << ", " << y << "): (" << p.x << ", " << p.y
                                                     << ", " << p.z << ") vs (" << q.x << ", " << q.y << ", " << q.z
                                                     << ")";
        }
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult same_bytes(const Image& a, const Image& b) {
    const ImageRgb8 p = quantize(a), q = quantize(b);
    if (p.width != q.width || p.height != q.height) return ::testing::AssertionFailure() << "sizes differ";
    for (size_t i = 0; i < p.rgb.size(); ++i)
        if (p.rgb[i] != q.rgb[i])
            return ::testing::AssertionFailure() << "byte " << i << " (pixel (" << (i / 3) % static_cast<size_t>(p.width)
                                                 << ", " << (i / 3) / static_cast<size_t>(p.width)
                                                 << ")): " << int{p.rgb[i]} << " vs " << int{q.rgb[i]};
    return ::testing::AssertionSuccess();
}

// The image as the course's main loop makes it: one ray per pixel, no packets, no tiles.
// With spp > 1, each pixel is its samples' colours summed in sample order and divided by their
// count, sample s's ray being camera_ray's at the pixel's point moved by pixel_sample_offset − ½.
Image brute_force(const Scene& scene, bool shadows, int spp = 1) {
    const Camera& cam = scene.camera;
    RenderOptions options;
    options.shadows = shadows;
    Image image(cam.width, cam.height);
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            if (spp == 1) {
                const Ray ray = camera_ray(cam, static_cast<float>(x) + cam.pixel_offset, static_cast<float>(y) + cam.pixel_offset);
                Hit hit;
                intersect(scene, ray, cam.t_min, hit);
                image.at(x, y) = radiance_along(scene, options, ray, hit);
                continue;
            }
            Vec3f sum;
            for (int s = 0; s < spp; ++s) {
                const Vec2f offset = pixel_sample_offset(static_cast<uint32_t>(y * cam.width + x), s, spp);
                const Ray ray = camera_ray(cam, static_cast<float>(x) + cam.pixel_offset + (offset.x - 0.5f),
                                           static_cast<float>(y) + cam.pixel_offset + (offset.y - 0.5f));
                Hit hit;
                intersect(scene, ray, cam.t_min, hit);
                const Vec3f color = radiance_along(scene, options, ray, hit);
                sum = s == 0 ? color : sum + color;
            }
            image.at(x, y) = sum / static_cast<float>(spp);
        }
    return image;
}

int count_hits(const Image& image, Vec3f background) {
    int n = 0;
    for (const Vec3f& p : image.pixels) n += p != background ? 1 : 0;
    return n;
}

// ---------------------------------------------------------------------------------------------
// The same image whichever way it is made.

TEST(RenderTest, EveryPacketIsaGivesTheSameImageAsSingleRays) {
    const std::vector<PacketIsa> isas = packet_isas();
    ASSERT_GE(isas.size(), 2u) << "at least None and one packet kernel";
    EXPECT_TRUE(packet_isa_available(PacketIsa::None));
    EXPECT_TRUE(packet_isa_available(PacketIsa::Portable));
    EXPECT_TRUE(packet_isa_available(best_packet_isa()));
    Scene scenes[4] = {mesh_scene(), spheres_scene(), transformed_scene(), mesh_scene()};
    // The fourth sees through a thin lens: every ray of a packet has its own origin.
    scenes[3].camera.lens_radius = 0.15f;
    scenes[3].camera.focus_distance = 8;
    const char* const names[4] = {"meshes", "spheres", "transformed", "meshes through a lens"};
    for (int k = 0; k < 4; ++k)
    for (const int spp : {1, 4}) {
        const Scene& scene = scenes[k];
        for (RenderMode mode : {RenderMode::Shaded, RenderMode::Normals, RenderMode::Depth, RenderMode::Material,
                                RenderMode::AmbientOcclusion}) {
            RenderOptions single = options_with(PacketIsa::None);
            single.mode = mode;
            single.samples_per_pixel = spp;
            RenderStats stats;
            const Image reference = render_image(scene, single, &stats);
            EXPECT_EQ(stats.traversal, "single-ray");
            // The scene is really in view: a good share of the pixels hit something.
            EXPECT_GT(stats.hits, stats.primary_rays / 4) << names[k];
            EXPECT_LT(stats.hits, stats.primary_rays) << names[k];
            for (PacketIsa isa : isas) {
                if (isa == PacketIsa::None) continue;
                RenderOptions packets = options_with(isa);
                packets.mode = mode;
                packets.samples_per_pixel = spp;
                RenderStats packet_stats;
                const Image image = render_image(scene, packets, &packet_stats);
                EXPECT_EQ(packet_stats.traversal, std::string("packet-") + packet_isa_name(isa));
                EXPECT_EQ(packet_stats.hits, stats.hits);
                EXPECT_TRUE(same_bytes(image, reference))
                    << names[k] << " " << packet_isa_name(isa) << " mode " << static_cast<int>(mode) << " spp " << spp;
                EXPECT_TRUE(same_floats(image, reference))
                    << names[k] << " " << packet_isa_name(isa) << " mode " << static_cast<int>(mode) << " spp " << spp;
            }
        }
    }
}

// Shadow rays from a packet's hits are traced as packets too (trace_camera_shadows): the image
// and the shadow-ray count are those of single rays, for every kernel, with 1 or 4 samples, and
// past the 64 lights whose answers a packet keeps (the rest are traced one by one).
TEST(RenderTest, ShadowPacketsGiveTheSameImageAndCountsAsSingleRays) {
    Scene many_lights = spheres_scene();
    while (many_lights.lights.size() < 70) many_lights.lights.push_back(many_lights.lights[many_lights.lights.size() % 2]);
    for (auto& light : many_lights.lights) light.color = light.color * (1.0f / 35);
    const Scene scenes[3] = {mesh_scene(), transformed_scene(), std::move(many_lights)};
    const char* const names[3] = {"meshes", "transformed", "70 lights"};
    for (int k = 0; k < 3; ++k)
        for (const int spp : {1, 4}) {
            RenderOptions single = options_with(PacketIsa::None);
            single.samples_per_pixel = spp;
            const Image unshadowed = render_image(scenes[k], single);
            single.shadows = true;
            RenderStats stats;
            const Image reference = render_image(scenes[k], single, &stats);
            // Something casts a shadow; a hit sends at most one ray per light (none towards a
            // light that adds nothing there).
            EXPECT_FALSE(same_bytes(reference, unshadowed)) << names[k];
            EXPECT_GT(stats.shadow_rays, 0u) << names[k];
            EXPECT_LE(stats.shadow_rays, stats.hits * scenes[k].lights.size()) << names[k];
            for (PacketIsa isa : packet_isas()) {
                if (isa == PacketIsa::None) continue;
                RenderOptions packets = single;
                packets.packet_isa = isa;
                RenderStats packet_stats;
                const Image image = render_image(scenes[k], packets, &packet_stats);
                EXPECT_TRUE(same_floats(image, reference)) << names[k] << " " << packet_isa_name(isa) << " spp " << spp;
                EXPECT_EQ(packet_stats.shadow_rays, stats.shadow_rays) << names[k] << " " << packet_isa_name(isa);
            }
        }
}

// RenderOptions::lights (the viewer's moved lights) in place of the scene's: every path gives
// the image of a scene built with those lights, shadows, back-face skipping and bounces included.
TEST(RenderTest, LightsGivenInTheOptionsAreTheImageOfTheSceneWithThem) {
    for (const bool meshes : {true, false}) {
        const Scene scene = meshes ? mesh_scene() : spheres_scene();
        Scene moved = meshes ? mesh_scene() : spheres_scene();
        for (Light& light : moved.lights) {
            if (light.kind == Light::Kind::Point) light.position = light.position + Vec3f{-3, 1, 2};
            else light.direction = normalize(Vec3f{0.4f, -1, -0.2f});
        }
        for (const int bounces : {0, 2})
            for (const bool shadows : {false, true})
                for (PacketIsa isa : packet_isas()) {
                    SCOPED_TRACE(std::string(meshes ? "meshes" : "spheres") + " " + packet_isa_name(isa) +
                                 (shadows ? " shadows" : "") + " bounces " + std::to_string(bounces));
                    RenderOptions options = options_with(isa);
                    options.shadows = shadows;
                    options.bounces = bounces;
                    const Image reference = render_image(moved, options);
                    EXPECT_FALSE(same_floats(reference, render_image(scene, options)));  // the lights matter
                    options.lights = &moved.lights;
                    EXPECT_TRUE(same_floats(render_image(scene, options), reference));
                }
    }
}

// Floors as students make them, under spheres and a point light: two triangles 4000 across, the
// same from two unit triangles under a Transform scaled 2000 times, and a sphere of radius 2000.
// A hit near the origin is only as accurate as the floor's own numbers (on the triangles, 3e-5 off
// the floor), and with shadow rays offset for the hit's coordinates alone, 3-11% of the floor met
// the floor again and went black, differently on every path (whose box tests passed different
// false hits to the triangle test). Offset for the shape's scale too (SurfacePoint::geometry_scale,
// in world units under a transform), each floor is shadowed as a plane floor is, and every path
// gives the same image: the triangles' the plane's but for pixels where a shadow's edge grazes a
// sphere; the curved sphere's with as many shadowed pixels, give or take a shadow's edge.
TEST(RenderTest, FloorsOfHugeTrianglesAndSpheresAreShadowedAsAPlaneFloor) {
    const auto scene_with_floor = [](ObjectDesc floor) {
        SceneDesc desc;
        desc.file = "floor.txt";
        desc.camera = perspective({0, 6, 12}, {0, -6, -12}, {0, 1, 0}, 32, 96, 96);  // no horizon in view
        desc.materials = {material({0.9f, 0.3f, 0.1f}, {0.8f, 0.8f, 0.8f}, 30), material({0.8f, 0.8f, 0.8f})};
        desc.lights = {point_light({-4, 6, 6}, {0.95f, 0.95f, 0.9f})};
        desc.has_lights_block = true;
        desc.root = group({sphere({0, 0, 0}, 1.2f, 0), sphere({1.3f, -0.7f, 1.8f}, 0.5f, 0), std::move(floor)});
        return build(std::move(desc));
    };
    const float h = -1.2f, r = 2000;
    const auto two_triangles = [](float half, float y) {
        return group({triangle({-half, y, -half}, {-half, y, half}, {half, y, half}, 1),
                      triangle({-half, y, -half}, {half, y, half}, {half, y, -half}, 1)});
    };
    RenderOptions single = options_with(PacketIsa::None);
    single.shadows = true;
    RenderOptions unshadowed = single;
    unshadowed.shadows = false;
    // The pixels that shadows darken.
    const auto shadowed_pixels = [&](const Scene& scene) {
        const Image lit = render_image(scene, unshadowed), shadowed = render_image(scene, single);
        int count = 0;
        for (size_t i = 0; i < lit.pixels.size(); ++i) count += max_abs(lit.pixels[i] - shadowed.pixels[i]) > 1.0f / 255;
        return count;
    };
    const Scene plane_floor = scene_with_floor(plane({0, 1, 0}, h, 1));
    const Image plane_image = render_image(plane_floor, single);
    const int plane_shadowed = shadowed_pixels(plane_floor);
    ASSERT_GT(plane_shadowed, 200);
    const struct {
        const char* name;
        Scene scene;
        bool flat;  // the plane's floor exactly
    } floors[] = {
        {"two triangles", scene_with_floor(two_triangles(r, h)), true},
        {"two unit triangles scaled", scene_with_floor(transform(Mat4::translate({0, h, 0}) * Mat4::scale({r, r, r}),
                                                                 two_triangles(1, 0))),
         true},
        {"a sphere", scene_with_floor(sphere({0, h - r, 0}, r, 1)), false},
    };
    for (const auto& floor : floors) {
        SCOPED_TRACE(floor.name);
        const Image reference = render_image(floor.scene, single);
        for (PacketIsa isa : packet_isas()) {
            RenderOptions packets = single;
            packets.packet_isa = isa;
            EXPECT_TRUE(same_floats(render_image(floor.scene, packets), reference)) << packet_isa_name(isa);
        }
        if (floor.flat) {
            int differ = 0;
            for (size_t i = 0; i < reference.pixels.size(); ++i)
                differ += max_abs(reference.pixels[i] - plane_image.pixels[i]) > 1.0f / 255;
            EXPECT_LE(differ, 5) << "of " << reference.pixels.size();
        }
        EXPECT_NEAR(shadowed_pixels(floor.scene), plane_shadowed, 20) << "of " << reference.pixels.size();
    }
}

// A sphere drawn 1e10 times smaller, or 1e12 times larger, than it is given (the sphere's own
// radius 1e10 under a scale of 1e-10) is the same sphere on every path: its quadratic's product
// left float in object space, and it came out black (SphereTest.HitsWhereTheQuadraticsProduct...).
TEST(RenderTest, ASphereDrawnAtAScaleFarFromItsOwnIsTheSameSphere) {
    const auto scene_with = [](ObjectDesc ball) {
        SceneDesc desc;
        desc.file = "ball.txt";
        desc.camera = perspective({0, 0, 10}, {0, 0, -1}, {0, 1, 0}, 20, 32, 32);
        desc.materials = {material({0.9f, 0.5f, 0.2f}, {0.5f, 0.5f, 0.5f}, 20)};
        desc.lights = {directional({-0.3f, -0.5f, -1}, {1, 1, 1})};
        desc.has_lights_block = true;
        desc.root = group({std::move(ball)});
        return build(std::move(desc));
    };
    RenderOptions single = options_with(PacketIsa::None);
    const Image plain = render_image(scene_with(sphere({0, 0, 0}, 1, 0)), single);
    for (const float scale : {1e10f, 1e-12f}) {
        SCOPED_TRACE(scale);
        const Scene scaled = scene_with(transform(Mat4::scale({1 / scale, 1 / scale, 1 / scale}), sphere({0, 0, 0}, scale, 0)));
        const Image reference = render_image(scaled, single);
        for (PacketIsa isa : packet_isas())
            EXPECT_TRUE(same_floats(render_image(scaled, options_with(isa)), reference)) << packet_isa_name(isa);
        int differ = 0;
        for (size_t i = 0; i < plain.pixels.size(); ++i) differ += max_abs(plain.pixels[i] - reference.pixels[i]) > 1.0f / 255;
        EXPECT_LE(differ, 3) << "of " << plain.pixels.size();  // a pixel or two on the silhouette
    }
}

// A scene whose instance BVH is one leaf is traced without that leaf's box on every path. Here
// the box is too thin for the box test's stand-in for 1/0 (a sphere of radius 1e-45 seen along
// the z axis from 1e18 away): found by fuzz_render_pipeline, where packets missed the sphere that
// single rays (and explain) hit.
TEST(RenderTest, ALoneInstanceIsTestedWithoutItsBoxOnEveryPath) {
    const Scene scene = build(load_scene_text(R"(OrthographicCamera {
    center 0 0 9.99999984e+17 direction 0 0 -1 up 0 1 0 size 1.40129846e-45 width 8 height 6 }
Background { color 0 0 0 }
Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }
Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1.40129846e-45 } }
)", "tiny.txt"));
    RenderOptions single = options_with(PacketIsa::None);
    single.mode = RenderMode::Material;
    const Image reference = render_image(scene, single);
    EXPECT_NE(reference.at(0, 0), (Vec3f{0, 0, 0}));  // the sphere, not the background
    for (PacketIsa isa : packet_isas()) {
        RenderOptions options = single;
        options.packet_isa = isa;
        RenderStats stats;
        const Image image = render_image(scene, options, &stats);
        EXPECT_EQ(stats.hits, stats.primary_rays) << packet_isa_name(isa);
        EXPECT_TRUE(same_floats(image, reference)) << packet_isa_name(isa);
    }
}

// A triangle 1e18 long, seen from near its narrow end (a fuzz finding: docs/reliability.md,
// finding 11). Its watertight test rounds so far off that it reports hits before the ray even
// enters the triangle's box, nearer than the sphere the ray really meets first. Whether such a
// hit was found depended on the order of traversal: where the sphere came first, it culled the
// triangle's leaf; the single-ray and packet paths visit in different orders, and their images
// differed. A hit is now moved up to just before its leaf's box (bvh.h's leaf_floor), on every
// path, as a free triangle in the scene's BVH and as a one-triangle mesh in its own.
TEST(RenderTest, AHitRoundedToBeforeItsBoxIsMovedToItOnEveryPath) {
    const std::string scene_text = R"(PerspectiveCamera {
    center -2.76947713 -2.76947713 -2.76947713 direction 1.76947713 1.76947713 1.76947713
    up 0 1 0 angle 30 width 8 height 6 }
Lights { numLights 1 DirectionalLight { direction -1 -1 -0.3359375 color 0.7 0.5 0.5 } }
Materials { numMaterials 2 Material { diffuseColor 0.2 0.6 0.2 } Material { diffuseColor 0.6 0.2 0.2 } }
Group { numObjects 3
    MaterialIndex 0 SHAPE
    MaterialIndex 1 Sphere { center -1.421875 -1.421875 -1.421875 radius 0.573437512 }
    Plane { normal -0.7109375 -0.7109375 0.9921875 offset -4 } }
)";
    const std::map<std::string, std::string> meshes = {
        {"sliver.obj", "v -1.77734375 -1.77734375 -1.77734375\nv -9e17 -2.109375 -1.77734375\n"
                       "v 10000000 -1.77734375 -1.7578125\nf 1 2 3\n"}};
    SceneLoadOptions load;
    load.in_memory_meshes = &meshes;
    for (const char* shape : {"Triangle { vertex0 -1.77734375 -1.77734375 -1.77734375 vertex1 -9e17 -2.109375 "
                              "-1.77734375 vertex2 10000000 -1.77734375 -1.7578125 }",
                              "TriangleMesh { obj_file sliver.obj }"}) {
        std::string text = scene_text;
        text.replace(text.find("SHAPE"), 5, shape);
        const Scene scene = build(load_scene_text(text, "sliver.txt", load));
        // The ray through pixel (2, 2) meets the sphere at t = 1.867 and enters the triangle's
        // box only at t = 1.936 (where its z reaches -1.777); the triangle's test reports t = 1.78,
        // which moves up to 1.935, behind the sphere.
        const Camera& cam = scene.camera;
        const Ray ray = camera_ray(cam, 2 + cam.pixel_offset, 2 + cam.pixel_offset);
        Hit hit;
        intersect(scene, ray, cam.t_min, hit);
        EXPECT_EQ(hit.object, 1u) << shape;  // the sphere
        EXPECT_NEAR(hit.t, 1.8672f, 1e-3f) << shape;
        RenderOptions single = options_with(PacketIsa::None);
        single.mode = RenderMode::Normals;
        const Image reference = render_image(scene, single);
        for (PacketIsa isa : packet_isas()) {
            RenderOptions options = single;
            options.packet_isa = isa;
            EXPECT_TRUE(same_floats(render_image(scene, options), reference)) << shape << ", " << packet_isa_name(isa);
            // The cost mode's walk counts the nodes it visits, ray by ray; its frame's normals
            // are those of the normals mode's packets (how the fuzzer found it).
            FrameRequest normals;
            normals.normals = true;
            const ImageRgb8 expected = render_image_rgb8(scene, options);
            options.mode = RenderMode::Cost;
            EXPECT_EQ(render_frame_rgb8(scene, options, normals).normals.rgb, expected.rgb)
                << shape << ", " << packet_isa_name(isa);
        }
    }
}

// A floor 2000 wide seen from 0.1 above it: the watertight test's t, a weighted sum of corner
// distances near 1000, is off by up to a few parts in 10^4 near the camera, often nearer than
// where the ray enters the floor's (flat) box. Such a hit is moved up to leaf_floor, not dropped:
// dropping it left a band of background pixels in the floor (3.9% of this image).
TEST(RenderTest, AFloorSeenFromJustAboveHasNoHoles) {
    const std::map<std::string, std::string> meshes = {
        {"floor.obj", "v -1000 0 -1000\nv 1000 0 -1000\nv 1000 0 1000\nv -1000 0 1000\nf 1 3 2\nf 1 4 3\n"}};
    SceneLoadOptions load;
    load.in_memory_meshes = &meshes;
    const Scene scene = build(load_scene_text(R"(PerspectiveCamera {
    center 0 0.1 0 direction 0 -0.5 -1 up 0 1 0 angle 60 width 200 height 150 }
Lights { numLights 1 DirectionalLight { direction -0.3 -1 -0.5 color 0.8 0.8 0.8 } }
Background { color 0.2 0.3 0.8 }
Materials { numMaterials 2 Material { diffuseColor 0.7 0.7 0.7 } Material { diffuseColor 0.8 0.2 0.2 } }
Group { numObjects 2
  MaterialIndex 0 TriangleMesh { obj_file floor.obj }
  MaterialIndex 1 Sphere { center 0.5 0.2 -3 radius 0.2 } }
)", "floor.txt", load));
    RenderOptions single = options_with(PacketIsa::None);
    single.mode = RenderMode::Material;
    const Image reference = render_image(scene, single);
    // The camera looks down at 26.6 degrees and sees 30 degrees up and down: the horizon lies
    // 3.4 degrees below the top edge, and the 120 rows from the bottom see only the floor and
    // the sphere (a miss is black in this mode).
    int misses = 0;
    for (int y = 0; y < 120; ++y)
        for (int x = 0; x < reference.width; ++x) misses += reference.at(x, y) == Vec3f{0, 0, 0};
    EXPECT_EQ(misses, 0);
    EXPECT_EQ(reference.at(100, 149), (Vec3f{0, 0, 0}));  // the top row sees the sky
    for (PacketIsa isa : packet_isas()) {
        RenderOptions options = single;
        options.packet_isa = isa;
        EXPECT_TRUE(same_floats(render_image(scene, options), reference)) << packet_isa_name(isa);
    }
}

// A nearly singular transform (two rows of its Matrix almost alike: its inverse's entries near
// 1e7) rounds the rays it moves into the sphere's space so much that the sphere's test reports
// hits a hair outside the box the sphere has in the world, which one traversal's box tests reach
// and another's do not: shadow and ambient-occlusion images differed by instruction set (found
// by a hunt). Past kMaxPacketCondition every ray is traced alone, so every choice is the same
// code; a well-conditioned transform keeps its packets.
TEST(RenderTest, ANearlySingularTransformGivesTheSameImageOnEveryPath) {
    const auto scene_with_row = [](const char* third) {
        return build(load_scene_text(std::string(R"(PerspectiveCamera { center 0 2 6 direction 0 -0.4 -1 up 0 1 0 angle 50 width 40 height 30 }
Lights { numLights 1 DirectionalLight { direction -0.3 -1 -0.5 color 0.8 0.8 0.8 } }
Materials { numMaterials 1 Material { diffuseColor 0.7 0.6 0.5 } }
Group { numObjects 3 MaterialIndex 0
 Plane { normal 0 1 0 offset -1 }
 Sphere { center 3 0 -3 radius 0.5 }
 Transform { Matrix { 0.5 0.6 0.9 0  0.5 0.6 )") + third + R"( 0  0.3 0.8 -0.8 0  0 0 0 1 } Sphere { center 0 0 0 radius 1 } } }
)", "near_singular.txt"));
    };
    const Scene near_singular = scene_with_row("0.9000001"), ordinary = scene_with_row("0.5");
    EXPECT_GT(near_singular.worst_transform_condition, kMaxPacketCondition);
    EXPECT_LT(ordinary.worst_transform_condition, 100.0f);
    for (const bool ao : {false, true}) {
        RenderOptions single = options_with(PacketIsa::None);
        single.shadows = !ao;
        if (ao) single.mode = RenderMode::AmbientOcclusion;
        const Image reference = render_image(near_singular, single);
        for (PacketIsa isa : packet_isas()) {
            RenderOptions options = single;
            options.packet_isa = isa;
            RenderStats stats;
            EXPECT_TRUE(same_floats(render_image(near_singular, options, &stats), reference))
                << packet_isa_name(isa) << (ao ? " ao" : " shadows");
            EXPECT_EQ(stats.traversal, "single-ray");
            render_image(ordinary, options, &stats);
            EXPECT_EQ(stats.traversal, isa == PacketIsa::None ? std::string("single-ray")
                                                              : std::string("packet-") + packet_isa_name(isa));
        }
    }
}

TEST(RenderTest, OneSamplePerPixelIsExactlyTheCourseMainLoop) {
    // Brute force per pixel (camera_ray at the pixel's point, intersect, shade or background)
    // against the tiled, packeted renderer; samples_per_pixel 1 is also the default.
    for (const Scene& scene : {mesh_scene(), spheres_scene(), transformed_scene()}) {
        for (bool shadows : {false, true}) {
            const Image expected = brute_force(scene, shadows);
            RenderOptions options;  // defaults: 1 sample, best packets
            EXPECT_EQ(options.samples_per_pixel, 1);
            options.shadows = shadows;
            EXPECT_TRUE(same_floats(render_image(scene, options), expected));
            options.samples_per_pixel = 1;
            options.packet_isa = PacketIsa::None;
            EXPECT_TRUE(same_floats(render_image(scene, options), expected));
        }
    }
}

// 64 pixels a side, halved down to 16 while the frame would have fewer than 16 tiles per thread.
TEST(RenderTest, AutomaticTileSizeKeepsSixteenTilesPerThreadDownTo16) {
    EXPECT_EQ(automatic_tile_size(1024, 1024, 2), 64);   // 16 x 16 = 256 tiles for 2 threads
    EXPECT_EQ(automatic_tile_size(1024, 1024, 16), 64);  // 256 = 16 x 16
    EXPECT_EQ(automatic_tile_size(1024, 1024, 17), 32);  // 256 < 272; 32 x 32 = 1024 tiles
    EXPECT_EQ(automatic_tile_size(200, 200, 1), 64);     // 4 x 4 = 16
    EXPECT_EQ(automatic_tile_size(200, 200, 2), 32);     // 16 < 32; 7 x 7 = 49
    EXPECT_EQ(automatic_tile_size(200, 200, 4), 16);     // 49 < 64; 13 x 13 = 169
    EXPECT_EQ(automatic_tile_size(37, 29, 1), 16);       // 1, then 2 x 1, then 16 is the least
    EXPECT_EQ(automatic_tile_size(37, 29, 0), 16);       // no threads counts as one
    EXPECT_EQ(automatic_tile_size(1, 1, 1), 16);
}

TEST(RenderTest, ThreadsAndTileSizesDoNotChangeTheImage) {
    const Scene scenes[2] = {mesh_scene(), transformed_scene()};
    for (const Scene& scene : scenes)
        for (int spp : {1, 4}) {
            RenderOptions options;
            options.samples_per_pixel = spp;
            options.shadows = true;
            options.threads = 1;
            options.tile_size = 16;
            RenderStats reference_stats;
            const Image reference = render_image(scene, options, &reference_stats);
            for (int threads : {1, 2, 3})
                for (int tile : {0, 1, 7, 16, 64}) {  // 0: automatic_tile_size's
                    options.threads = threads;
                    options.tile_size = tile;
                    RenderStats stats;
                    EXPECT_TRUE(same_floats(render_image(scene, options, &stats), reference))
                        << "threads " << threads << " tile " << tile << " spp " << spp;
                    EXPECT_EQ(stats.threads, threads);
                    EXPECT_EQ(stats.rays, reference_stats.rays);
                    EXPECT_EQ(stats.primary_rays, static_cast<uint64_t>(37 * 29 * spp));
                    // rays counts every ray: at most one shadow ray per light from every hit.
                    EXPECT_EQ(stats.shadow_rays, reference_stats.shadow_rays);
                    EXPECT_LE(stats.shadow_rays, scene.lights.size() * stats.hits);
                    EXPECT_EQ(stats.rays, stats.primary_rays + stats.shadow_rays);
                    EXPECT_EQ(stats.hits, reference_stats.hits);
                }
        }
}

TEST(RenderTest, CropWindowGivesTheSamePixelsAsTheFullRender) {
    const Scene scene = transformed_scene();
    const int w = 37, h = 29;
    // CropWindow rows count from the top: rows [3, 11) from the top are rows [18, 26) of the
    // bottom-up image (29 − 11 = 18).
    const CropWindow windows[3] = {{5, 3, 20, 11}, {0, 0, w, h}, {w - 1, 0, w, 1}};
    for (RenderMode mode : {RenderMode::Shaded, RenderMode::Normals, RenderMode::Cost})
        for (int spp : {1, 4}) {
            RenderOptions options;
            options.mode = mode;
            options.samples_per_pixel = spp;
            options.tile_size = 8;
            options.threads = 2;
            const Image full = render_image(scene, options);
            for (const CropWindow& c : windows) {
                RenderOptions crop = options;
                crop.has_crop = true;
                crop.crop = c;
                RenderStats stats;
                const Image part = render_image(scene, crop, &stats);
                ASSERT_EQ(part.width, c.x1 - c.x0);
                ASSERT_EQ(part.height, c.y1 - c.y0);
                EXPECT_EQ(stats.rays, static_cast<uint64_t>(part.width * part.height * spp));
                for (int y = 0; y < part.height; ++y)
                    for (int x = 0; x < part.width; ++x) {
                        const Vec3f p = part.at(x, y), q = full.at(c.x0 + x, h - c.y1 + y);
                        EXPECT_EQ(std::memcmp(&p, &q, sizeof p), 0)
                            << "crop (" << c.x0 << ", " << c.y0 << ", " << c.x1 << ", " << c.y1 << ") pixel (" << x
                            << ", " << y << ") mode " << static_cast<int>(mode) << " spp " << spp;
                    }
            }
        }
}

TEST(RenderTest, EightBitRenderIsTheQuantizedFloatRenderByteForByte) {
    // render_image_rgb8 converts each tile as it finishes; the CLI writes what it returns.
    const Scene scenes[2] = {transformed_scene(), mesh_scene()};
    for (const Scene& scene : scenes)
        for (RenderMode mode :
             {RenderMode::Shaded, RenderMode::Normals, RenderMode::Depth, RenderMode::Material, RenderMode::Cost})
            for (int spp : {1, 4})
                for (PacketIsa isa : {PacketIsa::None, best_packet_isa()})
                    for (bool crop : {false, true}) {
                        RenderOptions options = options_with(isa);
                        options.mode = mode;
                        options.samples_per_pixel = spp;
                        options.tile_size = 7;  // tiles that end mid-block and mid-image
                        options.threads = 3;
                        options.has_crop = crop;
                        options.crop = {3, 2, scene.camera.width - 4, scene.camera.height - 1};
                        RenderStats float_stats, byte_stats;
                        const ImageRgb8 expected = quantize(render_image(scene, options, &float_stats));
                        const ImageRgb8 bytes = render_image_rgb8(scene, options, &byte_stats);
                        const std::string where = "mode " + std::to_string(static_cast<int>(mode)) + " spp " +
                                                  std::to_string(spp) + " isa " + packet_isa_name(isa) +
                                                  (crop ? " crop" : "");
                        ASSERT_EQ(bytes.width, expected.width) << where;
                        ASSERT_EQ(bytes.height, expected.height) << where;
                        EXPECT_TRUE(bytes.rgb == expected.rgb) << where;
                        EXPECT_EQ(byte_stats.rays, float_stats.rays) << where;
                        EXPECT_EQ(byte_stats.hits, float_stats.hits) << where;
                        EXPECT_GT(byte_stats.hits, 0u) << where;
                    }
}

TEST(RenderTest, OnePassMakesTheColourDepthAndNormalsImagesOfItsOwnModes) {
    // -depth FILE -normals FILE: the camera rays are traced once, and each image equals the render
    // of its own mode byte for byte.
    const Scene scenes[2] = {transformed_scene(), mesh_scene()};
    for (const Scene& scene : scenes)
        for (int spp : {1, 4})
            for (bool crop : {false, true}) {
                RenderOptions options = options_with(best_packet_isa());
                options.samples_per_pixel = spp;
                options.shadows = true;
                options.threads = 2;
                options.has_crop = crop;
                options.crop = {3, 2, scene.camera.width - 4, scene.camera.height - 1};
                options.depth_near = crop ? 5 : 0;
                options.depth_far = crop ? 15 : 0;
                FrameRequest all;
                all.depth = all.normals = true;
                RenderStats stats;
                const FrameImages images = render_frame_rgb8(scene, options, all, &stats);
                RenderStats color_stats;
                EXPECT_TRUE(images.color.rgb == render_image_rgb8(scene, options, &color_stats).rgb);
                RenderOptions depth = options, normals = options;
                depth.mode = RenderMode::Depth;
                normals.mode = RenderMode::Normals;
                EXPECT_TRUE(images.depth.rgb == render_image_rgb8(scene, depth).rgb) << "spp " << spp;
                EXPECT_TRUE(images.normals.rgb == render_image_rgb8(scene, normals).rgb) << "spp " << spp;
                // One camera ray per pixel sample, not one per image.
                EXPECT_EQ(stats.primary_rays, color_stats.primary_rays);
                EXPECT_EQ(stats.primary_rays, static_cast<uint64_t>(images.color.width) *
                                                  static_cast<uint64_t>(images.color.height) *
                                                  static_cast<uint64_t>(spp));
            }
    // Only what is asked for is made.
    const Scene scene = transformed_scene();
    FrameRequest depth_only;
    depth_only.color = false;
    depth_only.depth = true;
    const FrameImages images = render_frame_rgb8(scene, RenderOptions{}, depth_only);
    EXPECT_TRUE(images.color.rgb.empty());
    EXPECT_TRUE(images.normals.rgb.empty());
    EXPECT_EQ(images.depth.width, scene.camera.width);
}

// Pixels whose camera rays can all be seen to miss (RenderOptions::skip_empty_windows: a tile,
// or a part of 16x16 pixels, whose bounding planes miss every box and plane of the scene) get the
// miss colour without being traced. Whatever the path, mode, sample count or target, the image
// and every count but window_missed_rays are those of tracing every ray, and windows are skipped.
TEST(RenderTest, WindowsThatSeeNothingChangeNoPixelAndNoCount) {
    // The test scenes seen wider, 96x72, so that much of the frame is background (and sky, for
    // the two with planes).
    auto widened = [](Scene scene, CameraDesc desc) {
        scene.camera = make_camera(desc, desc.width, desc.height, scene.conventions);
        return scene;
    };
    const Scene scenes[3] = {widened(mesh_scene(), camera({1, 2.5f, 8}, {-0.1f, -0.3f, -1}, 70, 96, 72)),
                             widened(spheres_scene(), camera({0, 0, 10}, {0, 0, -1}, 60, 96, 72)),
                             widened(transformed_scene(), camera({0.5f, 1, 9}, {-0.05f, 0.3f, -1}, 64, 96, 72))};
    const char* const names[3] = {"meshes", "spheres on a floor", "transformed, over a tilted plane"};
    struct Variant {
        const char* name;
        void (*set)(RenderOptions&);
    };
    const Variant variants[] = {
        {"default", [](RenderOptions&) {}},
        {"4 samples, 3 threads", [](RenderOptions& o) { o.samples_per_pixel = 4; o.threads = 3; }},
        {"single rays, shadows", [](RenderOptions& o) { o.packet_isa = PacketIsa::None; o.shadows = true; }},
        {"shadows, tiles of 16", [](RenderOptions& o) { o.shadows = true; o.tile_size = 16; }},
        {"tiles of 40", [](RenderOptions& o) { o.tile_size = 40; }},
        {"tiles of 7, 2 threads", [](RenderOptions& o) { o.tile_size = 7; o.threads = 2; }},
        {"normals", [](RenderOptions& o) { o.mode = RenderMode::Normals; }},
        {"depth", [](RenderOptions& o) { o.mode = RenderMode::Depth; }},
        {"ambient occlusion", [](RenderOptions& o) { o.mode = RenderMode::AmbientOcclusion; o.ao_samples = 4; }},
        {"material, 4 samples", [](RenderOptions& o) { o.mode = RenderMode::Material; o.samples_per_pixel = 4; }},
        {"crop", [](RenderOptions& o) { o.has_crop = true; o.crop = {5, 3, 90, 60}; }},
    };
    for (int k = 0; k < 3; ++k) {
        for (const Variant& variant : variants) {
            RenderOptions traced;
            variant.set(traced);
            traced.skip_empty_windows = false;
            RenderOptions skipped = traced;
            skipped.skip_empty_windows = true;
            RenderStats traced_stats, skipped_stats;
            const Image reference = render_image(scenes[k], traced, &traced_stats);
            const Image image = render_image(scenes[k], skipped, &skipped_stats);
            EXPECT_TRUE(same_floats(image, reference)) << names[k] << ", " << variant.name;
            EXPECT_EQ(traced_stats.window_missed_rays, 0u);
            EXPECT_GT(skipped_stats.window_missed_rays, skipped_stats.primary_rays / 20) << names[k] << ", " << variant.name;
            EXPECT_LT(skipped_stats.window_missed_rays + skipped_stats.hits, skipped_stats.primary_rays);
            EXPECT_EQ(skipped_stats.rays, traced_stats.rays) << names[k] << ", " << variant.name;
            EXPECT_EQ(skipped_stats.primary_rays, traced_stats.primary_rays);
            EXPECT_EQ(skipped_stats.hits, traced_stats.hits);
            EXPECT_EQ(skipped_stats.shadow_rays, traced_stats.shadow_rays);
            EXPECT_EQ(skipped_stats.occlusion_rays, traced_stats.occlusion_rays);
        }
        // The normals image of a colour render is filled there too.
        FrameRequest all;
        all.depth = all.normals = true;
        RenderOptions traced;
        traced.skip_empty_windows = false;
        RenderOptions skipped;
        const FrameImages reference = render_frame_rgb8(scenes[k], traced, all);
        const FrameImages images = render_frame_rgb8(scenes[k], skipped, all);
        EXPECT_TRUE(images.color.rgb == reference.color.rgb) << names[k];
        EXPECT_TRUE(images.depth.rgb == reference.depth.rgb) << names[k];
        EXPECT_TRUE(images.normals.rgb == reference.normals.rgb) << names[k];
    }
    // Cost mode's colour counts each ray's nodes, and a thin lens's rays leave the lens from
    // different points: neither skips.
    for (bool lens : {false, true}) {
        Scene scene = scenes[0];
        RenderOptions options;
        if (lens) {
            scene.camera.lens_radius = 0.1f;
        } else {
            options.mode = RenderMode::Cost;
        }
        RenderStats stats;
        render_image(scene, options, &stats);
        EXPECT_EQ(stats.window_missed_rays, 0u) << (lens ? "lens" : "cost");
    }
}

// Shadow rays of camera hits pass over the back faces of closed meshes where both their ends
// are outside (RenderOptions::skip_back_faces, scene/back_faces.h). Whatever the path, samples,
// tiles or threads, the image and every count are those of testing every face, and explain, which
// names the nearest blocker, still gives every pixel the rendered colour.
TEST(RenderTest, ShadowRaysThatSkipBackFacesChangeNoPixelAndNoCount) {
    SceneDesc desc;
    desc.file = "closed.txt";
    desc.camera = camera({1, 2.5f, 8}, {-0.1f, -0.3f, -1}, 35, 48, 40);
    desc.materials = {material({0.8f, 0.6f, 0.4f}, {0.7f, 0.7f, 0.7f}, 20), material({0.3f, 0.7f, 0.3f}),
                      material({0.5f, 0.5f, 0.9f}, {0.3f, 0.3f, 0.3f}, 4)};
    // A sun, a lamp outside every box, and a lamp inside the slab's box, for which only the ball
    // may skip.
    desc.lights = {directional({-0.5f, -1, -0.6f}, {0.6f, 0.6f, 0.6f}), point_light({2, 4, 3}, {0.5f, 0.5f, 0.3f}),
                   point_light({-2.5f, -1.35f, 1}, {0.4f, 0.4f, 0.4f})};
    desc.has_lights_block = true;
    TriangleMesh ball = smooth_sphere_mesh(24, 32);  // closed, bumpy: it shadows itself
    for (Vec3f& p : ball.positions) p = p * (1 + 0.15f * std::sin(7 * p.x) * std::cos(5 * p.z));
    TriangleMesh slab = cube_mesh();  // closed, in world space: [−4, 4] × [−1.6, −1.2] × [−4, 4]
    for (Vec3f& p : slab.positions) p = {4 * p.x, -1.4f + 0.2f * p.y, 4 * p.z};
    desc.meshes.push_back({"ball.obj", ball});
    desc.meshes.push_back({"slab.obj", slab});
    desc.meshes.push_back({"cube.obj", cube_mesh()});
    desc.root = group({mesh_object(0, 0), mesh_object(1, 1),
                       transform(Mat4::translate({1.8f, -0.7f, 0.5f}) * Mat4::scale({0.4f, 0.4f, 0.4f}), mesh_object(2, 2)),
                       sphere({-1.7f, -0.6f, 1}, 0.5f, 2)});
    const Scene scene = build(std::move(desc));

    RenderOptions shadows;
    shadows.shadows = true;
    const Integrator integrator = make_integrator(scene, shadows);
    const std::vector<std::vector<uint8_t>> skippable{{1, 1, 0, 0}, {1, 1, 0, 0}, {1, 0, 0, 0}};
    ASSERT_EQ(integrator.back_faces_skippable.size(), 3u);
    for (size_t light = 0; light < 3; ++light) EXPECT_EQ(integrator.back_faces_skippable[light].instances, skippable[light]);

    // Cones that lie (every child of the ball faces away from every direction) let every skipping
    // shadow ray through the ball: each path must then lose the ball's shadows, so each path
    // really skips. Only the ball's own shadow rays may skip, so only it lies.
    Scene lying = scene;
    for (NodeCones& cones : lying.meshes[0].cones)
        for (int slot = 0; slot < kWideBvhWidth; ++slot) cones.reach[slot] = 0;
    for (NodeCones& cones : lying.meshes[0].cones)
        for (int slot = 0; slot < kWideBvhWidth; ++slot) {
            // The sun's shadow rays go up the light's reversed direction: point every axis there.
            cones.axis[0][slot] = static_cast<int8_t>(std::lround(127 * 0.5f / std::sqrt(1.61f)));
            cones.axis[1][slot] = static_cast<int8_t>(std::lround(127 * 1.0f / std::sqrt(1.61f)));
            cones.axis[2][slot] = static_cast<int8_t>(std::lround(127 * 0.6f / std::sqrt(1.61f)));
        }

    struct Variant {
        const char* name;
        void (*set)(RenderOptions&);
    };
    const Variant variants[] = {
        {"packets", [](RenderOptions&) {}},
        {"single rays", [](RenderOptions& o) { o.packet_isa = PacketIsa::None; }},
        {"4 samples, 3 threads", [](RenderOptions& o) { o.samples_per_pixel = 4; o.threads = 3; }},
        {"tiles of 16, 2 threads, 2 bounces", [](RenderOptions& o) { o.tile_size = 16; o.threads = 2; o.bounces = 2; }},
    };
    for (const Variant& variant : variants) {
        RenderOptions every_face = shadows;
        variant.set(every_face);
        every_face.skip_back_faces = false;
        RenderOptions skipping = every_face;
        skipping.skip_back_faces = true;
        RenderStats every_face_stats, skipping_stats;
        const Image reference = render_image(scene, every_face, &every_face_stats);
        const Image image = render_image(scene, skipping, &skipping_stats);
        EXPECT_TRUE(same_floats(image, reference)) << variant.name;
        EXPECT_EQ(skipping_stats.rays, every_face_stats.rays) << variant.name;
        EXPECT_EQ(skipping_stats.shadow_rays, every_face_stats.shadow_rays) << variant.name;
        EXPECT_EQ(skipping_stats.secondary_rays, every_face_stats.secondary_rays) << variant.name;
        const Image lied_to = render_image(lying, skipping);
        EXPECT_FALSE(same_floats(lied_to, reference)) << variant.name << ": the cones are not read";
    }
    // Not vacuous: the shadows darken many pixels, of the ball on itself among them.
    RenderOptions unshadowed;
    const ImageRgb8 lit = render_image_rgb8(scene, unshadowed);
    const ImageRgb8 shadowed = render_image_rgb8(scene, shadows);
    int darker = 0;
    for (size_t i = 0; i < lit.rgb.size(); ++i) darker += shadowed.rgb[i] < lit.rgb[i];
    EXPECT_GT(darker, static_cast<int>(lit.rgb.size()) / 10);
    for (int y = 0; y < shadowed.height; ++y)
        for (int x = 0; x < shadowed.width; ++x) {
            const PixelExplanation e = explain_pixel(scene, shadows, x, shadowed.height - 1 - y);
            const uint8_t* pixel = shadowed.at(x, y);
            ASSERT_TRUE(e.rgb8[0] == pixel[0] && e.rgb8[1] == pixel[1] && e.rgb8[2] == pixel[2]) << x << ", " << y;
        }
}

// A shadow ray ends its start's offset from the light, and the offset grows with the hit's
// coordinates. Here a hit 1e4 away has an offset of 0.078, and a point light lies 0.03 outside
// the box of a closed mesh turned inside out: the ray ends inside that mesh, which it enters
// through faces that face away from it. Such rays must test every face (ends_clear_of_boxes);
// the first version let them through, and every pixel lost its shadow.
TEST(RenderTest, ShadowRaysEndingWithinTheirOffsetOfAMeshDoNotSkipItsBackFaces) {
    SceneDesc desc;
    desc.file = "far.txt";
    const Vec3f hit_point{0, -1.03f, -1e4f}, normal{0, 0.6f, 0.8f}, eye{5, 0, 5};
    desc.camera = perspective(eye, normalize(hit_point - eye), {0, 1, 0}, 0.02f, 16, 16);
    desc.materials = {material({0.8f, 0.8f, 0.8f})};
    desc.lights = {point_light({0, -1.03f, 0}, {1, 1, 1})};
    desc.has_lights_block = true;
    TriangleMesh inverted = inside_out(smooth_sphere_mesh(40, 60));  // closed, of radius 1, faces turned inwards
    inverted.normals.clear();
    inverted.normal_indices.clear();
    desc.meshes.push_back({"inverted.obj", inverted});
    desc.root = group({mesh_object(0, 0), sphere(hit_point - normal * 100.0f, 100, 0)});
    const Scene scene = build(std::move(desc));
    RenderOptions shadows;
    shadows.shadows = true;
    ASSERT_EQ(make_integrator(scene, shadows).back_faces_skippable.at(0).instances, (std::vector<uint8_t>{1, 0}));
    for (PacketIsa isa : {best_packet_isa(), PacketIsa::None}) {
        RenderOptions skipping = shadows;
        skipping.packet_isa = isa;
        RenderOptions every_face = skipping;
        every_face.skip_back_faces = false;
        const Image reference = render_image(scene, every_face);
        EXPECT_TRUE(same_floats(render_image(scene, skipping), reference)) << packet_isa_name(isa);
        int shadowed = 0;  // not vacuous: the mesh shadows every pixel
        for (int y = 0; y < reference.height; ++y)
            for (int x = 0; x < reference.width; ++x) shadowed += reference.at(x, y) == Vec3f{0, 0, 0};
        EXPECT_EQ(shadowed, reference.width * reference.height);
    }
}

// Where skipping back faces can change the image, and only how: a shadow ray starts its offset
// (about 1e-5 of the coordinates) off its hit, so on a floor within that of a closed ball mesh
// resting on it (a ring of radius about the square root of 2·radius·offset around the contact),
// the ray starts inside the ball: testing every face, the ball's top blocks it; skipping, that top
// faces away from the ray and the light gets in (scene/back_faces.h). Seen in a close-up at floor
// level (the review that found it); `--test-every-face` turns skipping off. Skipping tests a
// subset of the faces, so it can only ever light a pixel more.
TEST(RenderTest, SkippingBackFacesCanOnlyLetLightInWhereObjectsTouch) {
    SceneDesc desc;
    desc.file = "contact.txt";
    desc.camera = perspective({-3, 2e-6f, 1e-4f}, normalize(Vec3f{1, -2e-6f / 3, 0}), {0, 1, 0}, 0.01f, 48, 48);
    desc.materials = {material({0.8f, 0.8f, 0.8f})};
    desc.lights = {directional({0, -1, 0}, {1, 1, 1})};
    desc.has_lights_block = true;
    TriangleMesh floor = cube_mesh();  // [−5, 5] × [−1, 0] × [−5, 5]
    for (Vec3f& p : floor.positions) p = {5 * p.x, 0.5f * p.y - 0.5f, 5 * p.z};
    TriangleMesh ball = smooth_sphere_mesh(64, 64);  // radius 1, its lowest point on the floor
    for (Vec3f& p : ball.positions) p = p + Vec3f{0, 1, 0};
    desc.meshes.push_back({"floor.obj", floor});
    desc.meshes.push_back({"ball.obj", ball});
    desc.root = group({mesh_object(0, 0), mesh_object(1, 0)});
    const Scene scene = build(std::move(desc));
    for (PacketIsa isa : {best_packet_isa(), PacketIsa::None}) {
        RenderOptions skipping;
        skipping.shadows = true;
        skipping.packet_isa = isa;
        RenderOptions every_face = skipping;
        every_face.skip_back_faces = false;
        const Image skipped = render_image(scene, skipping), tested = render_image(scene, every_face);
        int lighter = 0, darker = 0;
        for (int y = 0; y < tested.height; ++y)
            for (int x = 0; x < tested.width; ++x) {
                const Vec3f a = skipped.at(x, y), b = tested.at(x, y);
                lighter += a.x > b.x;
                darker += a.x < b.x;
            }
        std::printf("%s: skipping lit %d of %d pixels more\n", packet_isa_name(isa), lighter, tested.width * tested.height);
        EXPECT_GT(lighter, 0) << packet_isa_name(isa) << ": the leak this test shows is gone; update the docs";
        EXPECT_EQ(darker, 0) << packet_isa_name(isa);
    }
}

// Scenes at the edges of the window test's reasoning, found by a review (each rendered wrongly
// before its fix): a lone sphere under a matrix far from orthogonal, traced through the float
// inverse, reaches well outside the box made with the matrix, and a lone instance's box is not
// tested by the tracer; a plane whose dot products with the camera's centre underflow; a camera
// of nearly 180 degrees whose `up` nearly parallels its direction, so that make_camera's rounded
// `horizontal` is not at right angles to it and the image's edges look slightly backwards; and a
// lone surface of revolution, whose tests are counted.
TEST(RenderTest, WindowsThatSeeNothingHoldAtTheEdges) {
    const char* const common = R"(Background { color 0.1 0.2 0.3 ambientLight 1 1 1 }
Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }
)";
    const struct {
        const char* name;
        bool skips;  // whether some windows are still found to see nothing
        const char* camera;
        const char* objects;
    } cases[] = {
        {"ill-conditioned transform", false,
         "PerspectiveCamera { center -3.44064879 4.91521263 0 direction 3.44064879 -4.91521263 0 up 0 0 1 angle 40 "
         "width 128 height 128 }",
         "Transform { Matrix4f { 1 0.7 0 0  0.7 0.490001 0 0  0 0 1 0  0 0 0 1 } Sphere { center 0 0 0 radius 1 } }"},
        {"underflowing plane", false,
         "PerspectiveCamera { center 2.64697796e-23 2.64697796e-23 2.64697796e-23 direction 1.45 1.45 -2.8 up 0 0 1 "
         "angle 30 width 32 height 32 }",
         "Plane { normal 7.67623634e-23 7.67623634e-23 -1.48230763e-22 offset 0 }"},
        {"nearly 180 degrees", true,
         "PerspectiveCamera { center 0 0 0 direction -0.631836891 -0.632301569 0.541339397 "
         "up -0.604615092 -0.605060399 0.518017888 angle 179.998856 width 64 height 64 }",
         "Sphere { center -2.28915 4.07729 1.77073 radius 0.02 }"},
        {"lone surface of revolution", false,
         "PerspectiveCamera { center 0 1 8 direction 0 0 -1 up 0 1 0 angle 60 width 64 height 64 }",
         "RevSurface { profile BsplineCurve { controls [ 0 0 0 ] [ 0 0 0 ] [ 0 0 0 ] [ 0.9 0 0 ] [ 1.05 0.05 0 ] "
         "[ 0.3 0.22 0 ] [ 0.12 0.5 0 ] [ 0 1.62 0 ] [ 0 1.62 0 ] [ 0 1.62 0 ] } }"},
    };
    for (const auto& c : cases) {
        const std::string text = std::string(c.camera) + "\n" + common + "Group { numObjects 1 MaterialIndex 0 " +
                                 c.objects + " }\n";
        const Scene scene = build(load_scene_text(text, "edge.txt"));
        for (int variant = 0; variant < 2; ++variant) {
            RenderOptions traced;
            if (variant == 1) {
                traced.samples_per_pixel = 4;
                traced.threads = 2;
                traced.tile_size = 32;
            }
            traced.skip_empty_windows = false;
            RenderOptions skipped = traced;
            skipped.skip_empty_windows = true;
            RenderStats traced_stats, skipped_stats;
            const Image reference = render_image(scene, traced, &traced_stats);
            EXPECT_GT(traced_stats.hits, 0u) << c.name;  // something is in view
            EXPECT_TRUE(same_floats(render_image(scene, skipped, &skipped_stats), reference)) << c.name;
            EXPECT_EQ(skipped_stats.hits, traced_stats.hits) << c.name;
            EXPECT_EQ(skipped_stats.rev_surface.tests, traced_stats.rev_surface.tests) << c.name;
            EXPECT_EQ(skipped_stats.window_missed_rays > 0, c.skips) << c.name;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Supersampling.

// A flat-coloured unit sphere at the origin (kd 0.75 under ambient 1, no lights) on background
// 0.25, seen from (0, 0, 10) with angle 15 on 20×20. The silhouette on the image plane is a
// circle around (10, 10) of radius f·r/√(D² − r²) = (10/tan 7.5°)/√99 = 7.6343 pixels.
Scene flat_sphere_scene() {
    SceneDesc desc;
    desc.file = "flat.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 15, 20, 20);
    desc.background = {0.25f, 0.25f, 0.25f};
    desc.ambient = Vec3f{1, 1, 1};
    desc.materials = {material({0.75f, 0.75f, 0.75f})};
    desc.root = sphere({0, 0, 0}, 1);
    return build(std::move(desc));
}

TEST(RenderTest, SupersamplingIsDeterministicAndChangesOnlyEdgePixels) {
    const Scene scene = flat_sphere_scene();
    const double radius = (10 / std::tan(7.5 * 3.14159265358979 / 180)) / std::sqrt(99.0);
    RenderOptions one;
    const Image single = render_image(scene, one);
    RenderOptions four;
    four.samples_per_pixel = 4;
    const Image multi = render_image(scene, four);
    // Run to run, and with other threads and tiles, the jitter is the same.
    EXPECT_TRUE(same_floats(render_image(scene, four), multi));
    four.threads = 3;
    four.tile_size = 5;
    EXPECT_TRUE(same_floats(render_image(scene, four), multi));
    int mixed = 0;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x) {
            const double d = std::hypot(x - 10.0, y - 10.0);
            const float s = single.at(x, y).x, m = multi.at(x, y).x;
            // One sample at the pixel's point (x, y): inside the circle or not.
            if (d < radius - 0.01) {
                EXPECT_EQ(s, 0.75f) << x << "," << y;
            }
            if (d > radius + 0.01) {
                EXPECT_EQ(s, 0.25f) << x << "," << y;
            }
            // Four samples inside [x − ½, x + ½) × [y − ½, y + ½): far from the edge, the same value;
            // across it, an average of four values of 0.25 or 0.75 (exact in binary).
            if (d + 0.7072 < radius) {
                EXPECT_EQ(m, 0.75f) << x << "," << y;
            }
            if (d - 0.7072 > radius) {
                EXPECT_EQ(m, 0.25f) << x << "," << y;
            }
            const float quarters = (m - 0.25f) / 0.125f;  // number of hitting samples
            EXPECT_EQ(quarters, std::round(quarters)) << x << "," << y;
            if (m != 0.25f && m != 0.75f) {
                ++mixed;
                EXPECT_LE(std::fabs(d - radius), 0.7072) << "mixed pixel away from the edge: " << x << "," << y;
            }
        }
    // The circumference is about 48 pixels long: many edge pixels are partly covered.
    EXPECT_GT(mixed, 15);
    EXPECT_FALSE(same_floats(single, multi));
}

TEST(RenderTest, SupersamplingAveragesToTheFlatColourInsideAndOtherCountsWork) {
    // spp 2, 3 (rows of jittered cells) and 9 (a 3×3 grid) also keep the interior exact.
    const Scene scene = flat_sphere_scene();
    for (int spp : {2, 3, 9}) {
        RenderOptions options;
        options.samples_per_pixel = spp;
        const Image image = render_image(scene, options);
        EXPECT_NEAR(image.at(10, 10).x, 0.75f, 1e-6) << spp;
        EXPECT_NEAR(image.at(0, 0).x, 0.25f, 1e-6) << spp;
        EXPECT_TRUE(same_floats(render_image(scene, options), image)) << spp;
    }
}

// A supersampled render is brute_force's average of each sample's own camera ray: the renderer
// makes a block's sample rays together, in SIMD, and they must be these rays to the bit, on every
// path and with shadows.
TEST(RenderTest, SupersamplingIsTheAverageOfEachSamplesOwnCameraRay) {
    for (const Scene& scene : {mesh_scene(), spheres_scene(), transformed_scene()}) {
        for (int spp : {3, 4}) {
            for (bool shadows : {false, true}) {
                const Image expected = brute_force(scene, shadows, spp);
                RenderOptions options;
                options.samples_per_pixel = spp;
                options.shadows = shadows;
                EXPECT_TRUE(same_floats(render_image(scene, options), expected)) << spp << " " << shadows;
                options.packet_isa = PacketIsa::None;
                EXPECT_TRUE(same_floats(render_image(scene, options), expected)) << spp << " " << shadows;
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Shadows.

TEST(RenderTest, PointUnderASphereLitFromAboveIsBlackOnlyWithShadows) {
    // The floor y = 0 (kd 0.5) and a unit sphere at (0, 2, 0); a point light at (0, 10, 0). The camera
    // at (0, 3, 8) looks along (0, −3, −8): the centre pixel (10, 10) of 20×20 is that exact ray, and it
    // passes 1.87 from the sphere's centre, reaching the floor at the origin, right under the sphere.
    SceneDesc desc;
    desc.file = "shadow.txt";
    CameraDesc cam = camera({0, 3, 8}, {0, -3, -8}, 40, 20, 20);
    desc.camera = cam;
    desc.background = {0, 0, 0};
    desc.materials = {material({0.5f, 0.5f, 0.5f})};
    desc.lights = {point_light({0, 10, 0}, {1, 1, 1})};
    desc.has_lights_block = true;
    desc.root = group({plane({0, 1, 0}, 0), sphere({0, 2, 0}, 1)});
    const Scene scene = build(std::move(desc));
    RenderOptions lit;
    RenderOptions shadowed;
    shadowed.shadows = true;
    const Image a = render_image(scene, lit), b = render_image(scene, shadowed);
    // Without shadows: N·L = 1 at the origin, 0.5·1.
    EXPECT_NEAR(a.at(10, 10).x, 0.5f, 1e-6);
    EXPECT_EQ(b.at(10, 10), (Vec3f{0, 0, 0}));
    // Shadows only darken, and only some pixels.
    int darker = 0, same = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        EXPECT_LE(b.pixels[i].x, a.pixels[i].x);
        if (b.pixels[i] == a.pixels[i]) ++same; else ++darker;
    }
    EXPECT_GT(darker, 5);
    EXPECT_GT(same, 200);
    // Every packet width agrees with shadows too.
    for (PacketIsa isa : packet_isas()) {
        RenderOptions o = options_with(isa);
        o.shadows = true;
        EXPECT_TRUE(same_floats(render_image(scene, o), b)) << packet_isa_name(isa);
    }
}

// ---------------------------------------------------------------------------------------------
// Debug modes and background.

// A unit sphere at the origin from (0, 0, 10), angle 15, 20×20: pixel (10, 10) is the axis ray, which
// meets the sphere at (0, 0, 1) with t = 9 and normal +z.
Scene axis_sphere_scene() {
    SceneDesc desc;
    desc.file = "axis.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 15, 20, 20);
    desc.background = {0.1f, 0.7f, 0.2f};
    desc.materials = {material({1, 1, 1})};
    desc.lights = {directional({0, 0, -1}, {1, 1, 1})};
    desc.has_lights_block = true;
    desc.root = sphere({0, 0, 0}, 1);
    return build(std::move(desc));
}

// The hit of pixel (x, y) of axis_sphere_scene, solved by hand in double: t and the normal.
void solve_axis_sphere(int x, int y, double& t, double normal[3]) {
    const double f = 10 / std::tan(7.5 * 3.14159265358979 / 180);
    double d[3] = {(x - 10) / f, (y - 10) / f, -1};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + 1);
    for (double& c : d) c /= len;
    // |o + t·d|² = 1 with o = (0, 0, 10): t² + 20·d.z·t + 99 = 0.
    const double b = 10 * d[2];
    t = -b - std::sqrt(b * b - 99);
    normal[0] = t * d[0];
    normal[1] = t * d[1];
    normal[2] = 10 + t * d[2];
}

TEST(RenderTest, NormalsModeShowsTheAbsoluteUnitNormal) {
    const Scene scene = axis_sphere_scene();
    RenderOptions options;
    options.mode = RenderMode::Normals;
    const Image image = render_image(scene, options);
    EXPECT_NEAR(image.at(10, 10).x, 0, 1e-6);
    EXPECT_NEAR(image.at(10, 10).y, 0, 1e-6);
    EXPECT_NEAR(image.at(10, 10).z, 1, 1e-6);
    const int pixels[3][2] = {{13, 11}, {5, 14}, {15, 6}};  // all within 7.6 pixels of the centre
    for (const auto& p : pixels) {
        double t, n[3];
        solve_axis_sphere(p[0], p[1], t, n);
        const Vec3f pixel = image.at(p[0], p[1]);
        EXPECT_NEAR(pixel.x, std::fabs(n[0]), 1e-5) << p[0] << "," << p[1];
        EXPECT_NEAR(pixel.y, std::fabs(n[1]), 1e-5) << p[0] << "," << p[1];
        EXPECT_NEAR(pixel.z, std::fabs(n[2]), 1e-5) << p[0] << "," << p[1];
    }
    // Where nothing is hit: black, not the background.
    EXPECT_EQ(image.at(0, 0), (Vec3f{0, 0, 0}));
}

TEST(RenderTest, DepthModeMapsTheRangeToGreyNearWhiteFarBlack) {
    const Scene scene = axis_sphere_scene();
    RenderOptions options;
    options.mode = RenderMode::Depth;
    options.depth_near = 8;
    options.depth_far = 12;
    Image image = render_image(scene, options);
    // t = 9 at the centre: (12 − 9)/(12 − 8) = 0.75.
    EXPECT_NEAR(image.at(10, 10).x, 0.75f, 1e-6);
    EXPECT_EQ(image.at(10, 10).x, image.at(10, 10).y);
    EXPECT_EQ(image.at(10, 10).x, image.at(10, 10).z);
    double t, n[3];
    solve_axis_sphere(13, 11, t, n);
    EXPECT_NEAR(image.at(13, 11).x, (12 - t) / 4, 1e-5);
    EXPECT_EQ(image.at(0, 0), (Vec3f{0, 0, 0}));
    // Outside the range the grey clamps: hits beyond far are black, hits nearer than near white.
    options.depth_near = 1;
    options.depth_far = 5;
    image = render_image(scene, options);
    EXPECT_EQ(image.at(10, 10), (Vec3f{0, 0, 0}));
    options.depth_near = 20;
    options.depth_far = 30;
    image = render_image(scene, options);
    EXPECT_EQ(image.at(10, 10), (Vec3f{1, 1, 1}));
    // No range given: that of the visible hits; the nearest (the centre, t = 9) is white.
    options.depth_near = options.depth_far = 0;
    image = render_image(scene, options);
    EXPECT_EQ(image.at(10, 10), (Vec3f{1, 1, 1}));
    float darkest = 1;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x)
            if (std::hypot(x - 10.0, y - 10.0) < 7) darkest = std::min(darkest, image.at(x, y).x);
    EXPECT_LT(darkest, 0.9f);
    EXPECT_GE(darkest, 0.0f);
}

TEST(RenderTest, MaterialModeGivesOneFlatColourPerMaterial) {
    // Three spheres in a row; the outer two share material 0, the middle one has material 1.
    SceneDesc desc;
    desc.file = "materials.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 30, 30, 12);
    desc.background = {0.5f, 0.5f, 0.5f};
    desc.materials = {material({1, 0, 0}), material({1, 0, 0})};  // equal colours, different indices
    desc.lights = {directional({0, 0, -1}, {1, 1, 1})};
    desc.has_lights_block = true;
    desc.root = group({sphere({-2.5f, 0, 0}, 1, 0), sphere({0, 0, 0}, 1, 1), sphere({2.5f, 0, 0}, 1, 0)});
    SceneDesc unlit = desc;
    unlit.lights.clear();
    const Scene scene = build(std::move(desc));
    RenderOptions options;
    options.mode = RenderMode::Material;
    const Image image = render_image(scene, options);
    // Column of each sphere's centre: x = cx + fx·X/10 with cx = 15 and, as the course's handout
    // defines the camera (angle spans the width too), fx = 15/tan 15° = 55.98.
    const float f = 15 / std::tan(15 * 3.14159265f / 180);
    const int left = static_cast<int>(std::lround(15 - f * 0.25f)), right = static_cast<int>(std::lround(15 + f * 0.25f));
    const Vec3f m0 = image.at(left, 6), m1 = image.at(15, 6);
    EXPECT_NE(m0, m1);
    EXPECT_NE(m0, (Vec3f{0, 0, 0}));
    EXPECT_NE(m1, (Vec3f{0, 0, 0}));
    EXPECT_EQ(image.at(right, 6), m0);
    EXPECT_EQ(image.at(left + 1, 7), m0);  // flat: the same all over the sphere
    EXPECT_EQ(image.at(15, 4), m1);
    EXPECT_EQ(image.at(0, 11), (Vec3f{0, 0, 0}));  // nothing hit: black
    // Every pixel is black or one of the two colours.
    const Vec3f black{0, 0, 0};
    for (const Vec3f& p : image.pixels) EXPECT_TRUE(p == m0 || p == m1 || p == black);
    // Lights do not matter.
    EXPECT_TRUE(same_floats(render_image(build(std::move(unlit)), options), image));
}

TEST(RenderTest, CostModeIsAHeatMapOfTheNodesEachRayVisits) {
    const Scene scene = spheres_scene();
    RenderOptions options;
    options.mode = RenderMode::Cost;
    RenderStats stats;
    const Image image = render_image(scene, options, &stats);
    EXPECT_EQ(stats.traversal, "single-ray");  // packets do not count nodes per ray
    // Count the nodes of each pixel's ray independently.
    const Camera& cam = scene.camera;
    std::map<uint64_t, Vec3f> colour_of;
    uint64_t total = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            TraceCounters counters;
            Hit hit;
            intersect(scene, camera_ray(cam, static_cast<float>(x), static_cast<float>(y)), cam.t_min, hit, &counters);
            total += counters.nodes_visited;
            const auto found = colour_of.find(counters.nodes_visited);
            if (found == colour_of.end())
                colour_of[counters.nodes_visited] = image.at(x, y);
            else
                EXPECT_EQ(found->second, image.at(x, y)) << "equal costs, different colours at " << x << "," << y;
        }
    EXPECT_EQ(stats.nodes_visited, total);
    ASSERT_GE(colour_of.size(), 3u) << "the scene should give several different costs";
    // Hotter with more nodes: dark blue, then towards red, yellow, white: (R, G, B) ordered
    // lexicographically grows with the count; the cheapest rays are dark blue.
    const Vec3f* previous = nullptr;
    for (const auto& [nodes, colour] : colour_of) {
        if (previous) {
            const bool hotter = colour.x != previous->x ? colour.x > previous->x
                                : colour.y != previous->y ? colour.y > previous->y
                                                          : colour.z > previous->z;
            EXPECT_TRUE(hotter) << nodes << " nodes";
        }
        previous = &colour;
    }
    const Vec3f coolest = colour_of.begin()->second;
    EXPECT_EQ(coolest.x, 0);
    EXPECT_EQ(coolest.y, 0);
    EXPECT_GT(coolest.z, 0);
    EXPECT_LT(coolest.z, 0.6f);
}

TEST(RenderTest, BackgroundColourWhereNothingIsHit) {
    const Scene scene = axis_sphere_scene();
    const Image image = render_image(scene, RenderOptions{});
    EXPECT_EQ(image.at(0, 0), (Vec3f{0.1f, 0.7f, 0.2f}));
    EXPECT_EQ(image.at(19, 19), (Vec3f{0.1f, 0.7f, 0.2f}));
    // course-format.md §c: background 0.1 0.7 0.2 becomes (25, 178, 51) in the file.
    const ImageRgb8 bytes = quantize(image);
    EXPECT_EQ(bytes.at(0, 0)[0], 25);
    EXPECT_EQ(bytes.at(0, 0)[1], 178);
    EXPECT_EQ(bytes.at(0, 0)[2], 51);
    // The centre is the sphere lit head-on: kd 1 · N·L 1.
    EXPECT_EQ(image.at(10, 10), (Vec3f{1, 1, 1}));
    EXPECT_GT(count_hits(image, {0.1f, 0.7f, 0.2f}), 100);
    // An empty scene is all background.
    SceneDesc empty;
    empty.file = "empty.txt";
    empty.camera = camera({0, 0, 10}, {0, 0, -1}, 30, 5, 4);
    empty.background = {0.3f, 0.2f, 0.1f};
    empty.root = group({});
    const Image nothing = render_image(build(std::move(empty)), RenderOptions{});
    for (const Vec3f& p : nothing.pixels) EXPECT_EQ(p, (Vec3f{0.3f, 0.2f, 0.1f}));
}

TEST(RenderTest, MitConventionsSamplePixelCentres) {
    // A 2×2 image of a sphere centred on the axis: with pixel centres (+0.5) the four pixels look
    // symmetrically off the axis and are identical; with the course's corners, pixel (1, 1) is the
    // axis ray itself (cx = cy = 1) and differs from pixel (0, 0).
    SceneDesc desc;
    desc.file = "mit.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 10, 2, 2);
    desc.background = {0, 0, 0};
    desc.materials = {material({1, 1, 1})};
    desc.lights = {point_light({3, 4, 10}, {1, 1, 1})};
    desc.has_lights_block = true;
    desc.root = sphere({0, 0, 0}, 1);
    RenderOptions options;
    options.mode = RenderMode::Normals;
    const Image mit = render_image(build(desc, Conventions::mit6837()), options);
    EXPECT_EQ(mit.at(0, 0), mit.at(1, 0));
    EXPECT_EQ(mit.at(0, 0), mit.at(0, 1));
    EXPECT_EQ(mit.at(0, 0), mit.at(1, 1));
    EXPECT_GT(mit.at(0, 0).x, 0);
    const Image course = render_image(build(desc), options);
    EXPECT_NEAR(course.at(1, 1).z, 1, 1e-6);
    EXPECT_NE(course.at(0, 0), course.at(1, 1));
}

// ---------------------------------------------------------------------------------------------
// Degenerate input.

bool all_finite(const Image& image) {
    for (const Vec3f& p : image.pixels)
        if (!is_finite(p)) return false;
    return true;
}

TEST(RenderTest, NoNanOrInfinityWithDegenerateTriangles) {
    // Zero-area triangles of every kind, lying across the view (some on the axis ray), in a mesh
    // with cancelling and zero vertex normals, as Triangle objects, and under a transform; plus a
    // sphere of radius 0 on the axis and ordinary objects around them.
    TriangleMesh degenerate;
    degenerate.positions = {{-1, 0, 0}, {0, 0, 0}, {1, 0, 0},   // collinear through the axis
                            {0, 1, 0},  {0, 1, 0}, {0, 1, 0},   // one point three times
                            {0, -1, 0}, {0, -1, 0}, {1, -1, 0},  // two equal corners
                            {-2, 0, 0}, {-1, 1, 0}, {-1.5f, 0.5f, 0}};
    degenerate.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    degenerate.normals = {{0, 0, 1}, {0, 0, -1}, {0, 0, 0}};
    degenerate.normal_indices = {0, 1, 2, 0, 0, 1, 2, 2, 2, 0, 1, 2};
    SceneDesc desc;
    desc.file = "degenerate.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 20, 24, 24);
    desc.background = {0.2f, 0.2f, 0.2f};
    desc.materials = {material({0.8f, 0.8f, 0.8f}, {1, 1, 1}, 10)};
    desc.lights = {point_light({0, 0, 5}, {1, 1, 1}), directional({0, 0, -1}, {0.5f, 0.5f, 0.5f})};
    desc.has_lights_block = true;
    desc.meshes.push_back({"degenerate.obj", degenerate});
    desc.root = group({
        mesh_object(0),
        transform(Mat4::translate({0.5f, 0.5f, 1}) * Mat4::scale({2, 2, 2}), mesh_object(0)),
        triangle({-1, -1, 2}, {1, 1, 2}, {0, 0, 2}),
        triangle({0.5f, 0.5f, 3}, {0.5f, 0.5f, 3}, {0.5f, 0.5f, 3}),
        sphere({0, 0, 4}, 0),
        sphere({2, 2, -3}, 1),
        plane({0, 1, 0}, -3),
    });
    const Scene scene = build(std::move(desc));
    for (RenderMode mode : {RenderMode::Shaded, RenderMode::Normals, RenderMode::Depth, RenderMode::Material,
                            RenderMode::Cost})
        for (int spp : {1, 4})
            for (bool shadows : {false, true})
                for (PacketIsa isa : packet_isas()) {
                    RenderOptions options = options_with(isa);
                    options.mode = mode;
                    options.samples_per_pixel = spp;
                    options.shadows = shadows;
                    const Image image = render_image(scene, options);
                    EXPECT_TRUE(all_finite(image)) << "mode " << static_cast<int>(mode) << " spp " << spp
                                                   << " shadows " << shadows << " " << packet_isa_name(isa);
                }
    // The ordinary objects are still drawn around the degenerate ones.
    const Image image = render_image(scene, RenderOptions{});
    EXPECT_GT(count_hits(image, {0.2f, 0.2f, 0.2f}), 50);
}

TEST(RenderTest, DepthModeWithOneDistanceOrNoHitsStaysFinite) {
    // Every hit at the same t (a plane facing an orthographic-like narrow view) or no hit at all:
    // the automatic range is empty, which must not divide by zero.
    SceneDesc desc;
    desc.file = "flat.txt";
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 1, 3, 3);
    desc.materials = {material({1, 1, 1})};
    desc.root = group({});
    RenderOptions options;
    options.mode = RenderMode::Depth;
    const Image none = render_image(build(desc), options);
    EXPECT_TRUE(all_finite(none));
    for (const Vec3f& p : none.pixels) EXPECT_EQ(p, (Vec3f{0, 0, 0}));
    // A single pixel seeing a plane: one distance, drawn white (nearest and farthest at once).
    desc.camera = camera({0, 0, 10}, {0, 0, -1}, 1, 1, 1);
    desc.root = plane({0, 0, 1}, 0);
    const Image one = render_image(build(desc), options);
    EXPECT_TRUE(all_finite(one));
    EXPECT_EQ(one.at(0, 0), (Vec3f{1, 1, 1}));
}

}  // namespace
}  // namespace raycast
