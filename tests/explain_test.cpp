// `raycast explain SCENE X Y`: the tree of rays behind one pixel, as JSON (docs/explain.md). Its
// colour and bytes must be exactly the rendered pixel's, for every pixel of a scene with mirrors,
// glass, a mesh and shadows, in every mode and with several samples; the JSON must be valid, hold
// the documented fields, and show the rays a user expects (a reflected ray on a mirror, a
// transmitted one through glass, one shadow ray per light); mistakes on the command line are usage
// errors (exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "json_value.h"
#include "render/render.h"
#include "scene/build_scene.h"
#include "sceneio/load_scene.h"
#include "test_support.h"

namespace raycast::test {
namespace {

// A mirror ball (left), a glass ball (right, both colours), a floor, a quad mesh behind and a
// triangle, under a point and a directional light. 20×20, angle 30: f = 10/tan 15° = 37.32, so the
// mirror ball's centre (−1.5, 0, 0) is pixel x = 10 − 37.32·0.15 = 4.4, row 10 from the bottom.
const char* const kScene = R"(PerspectiveCamera {
    center 0 0 10  direction 0 0 -1  up 0 1 0  angle 30  width 20  height 20
}
Lights {
    numLights 2
    PointLight { position 3 5 5 color 0.8 0.8 0.8 }
    DirectionalLight { direction -0.3 -1 -0.5 color 0.4 0.4 0.4 }
}
Background { color 0.2 0.3 0.5 }
Materials {
    numMaterials 4
    Material { diffuseColor 0.05 0.05 0.05 specularColor 0.5 0.5 0.5 shininess 40 reflectiveColor 0.9 0.9 0.9 }
    Material { diffuseColor 0 0 0 specularColor 0.6 0.6 0.6 shininess 60
               reflectiveColor 0.1 0.1 0.1 transparentColor 0.85 0.9 0.85 indexOfRefraction 1.5 }
    Material { diffuseColor 0.7 0.6 0.5 }
    Material { diffuseColor 0.2 0.6 0.3 specularColor 0.3 0.3 0.3 shininess 10 }
}
Group {
    numObjects 5
    MaterialIndex 0
    Sphere { center -1.5 0 0 radius 1 }
    MaterialIndex 1
    Sphere { center 1.4 -0.2 0.5 radius 0.9 }
    MaterialIndex 2
    Plane { normal 0 1 0 offset -1 }
    MaterialIndex 3
    TriangleMesh { obj_file quad.obj }
    Triangle { vertex0 -3 2 -3 vertex1 -1 3 -3 vertex2 -3 3.5 -3 }
}
)";

const char* const kQuadObj = "v -4 -1 -4\nv 4 -1 -4\nv 4 3 -4\nv -4 3 -4\nf 1 2 3 4\n";

std::string scene_dir(const std::string& name) {
    const std::string dir = temp_dir("explain/" + name);
    write_file(dir + "/s.txt", kScene);
    write_file(dir + "/quad.obj", kQuadObj);
    return dir;
}

JsonValue parse_json(const std::string& text) {
    JsonValue value;
    JsonReader reader(text);
    EXPECT_TRUE(reader.parse(value)) << reader.error() << "\n" << text;
    return value;
}

// Every ray of a JSON ray tree, depth first.
void collect_rays(const JsonValue& ray, std::vector<const JsonValue*>& out) {
    out.push_back(&ray);
    for (const JsonValue& child : ray["children"].array) collect_rays(child, out);
}

TEST(ExplainTest, EveryPixelsExplanationHasTheRenderedColourAndBytes) {
    const std::string dir = scene_dir("every_pixel");
    SceneLoadOptions load;
    SceneDesc desc = load_scene_file(dir + "/s.txt", load);
    const Scene scene = build_scene(std::move(desc), SceneBuildOptions{});
    struct Setting {
        const char* name;
        RenderOptions options;
    };
    std::vector<Setting> settings;
    // The render loop shades hits that need local shading only in a loop of its own
    // (shade_camera_hits_locally); explain always takes the radiance function's general path.
    settings.push_back({"the course's ray caster", RenderOptions{}});
    RenderOptions bounced;
    bounced.bounces = 4;
    settings.push_back({"4 bounces, no shadows", bounced});
    RenderOptions traced;
    traced.shadows = true;
    traced.bounces = 4;
    settings.push_back({"shadows, 4 bounces", traced});
    RenderOptions sampled = traced;
    sampled.samples_per_pixel = 4;
    sampled.transparent_shadows = true;
    sampled.bounces = 3;
    settings.push_back({"4 samples, transparent shadows", sampled});
    RenderOptions cut = traced;
    cut.weight_cutoff = 0.5f;
    settings.push_back({"weight cutoff 0.5", cut});
    for (const RenderMode mode : {RenderMode::Normals, RenderMode::Depth, RenderMode::Material, RenderMode::Cost,
                                  RenderMode::AmbientOcclusion}) {
        RenderOptions debug;
        debug.mode = mode;
        settings.push_back({render_mode_name(mode), debug});
    }
    for (Setting& setting : settings) {
        SCOPED_TRACE(setting.name);
        setting.options.threads = 2;
        const ImageRgb8 image = render_image_rgb8(scene, setting.options);
        int mismatches = 0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                // explain counts rows from the top; the image stores row 0 at the bottom.
                const PixelExplanation e = explain_pixel(scene, setting.options, x, image.height - 1 - y);
                const uint8_t* pixel = image.at(x, y);
                if (e.rgb8[0] != pixel[0] || e.rgb8[1] != pixel[1] || e.rgb8[2] != pixel[2]) ++mismatches;
                ASSERT_EQ(e.samples.size(), static_cast<size_t>(setting.options.samples_per_pixel));
                if (setting.options.samples_per_pixel == 1 && setting.options.mode != RenderMode::Depth) {
                    EXPECT_EQ(e.samples[0].rays[0].color, e.color);
                }
            }
        EXPECT_EQ(mismatches, 0);
    }
}

// The same bits, not only the same bytes: the render loop shades a packet's hits that need local
// shading only an operation at a time over all of them (SIMD), which must give each pixel's colour
// exactly as the radiance function's scalar code does, for every specular model, with back faces
// turned towards the viewer, with and without shadow rays (the same ones), under an attenuated
// point light.
TEST(ExplainTest, ThePacketsLocalShadingIsTheRadianceFunctionsBitForBit) {
    const std::string dir = scene_dir("local_bits");
    // The scene above with ambient light, a triangle wound clockwise, seen from behind, and a ball.
    std::string text = kScene;
    const auto replace = [&](const std::string& from, const std::string& to) {
        ASSERT_NE(text.find(from), std::string::npos) << from;
        text.replace(text.find(from), from.size(), to);
    };
    replace("Background { color 0.2 0.3 0.5 }", "Background { color 0.2 0.3 0.5 ambientLight 0.1 0.15 0.2 }");
    replace("numObjects 5", "numObjects 7");
    replace("    Triangle {", "    Triangle { vertex0 2 1 -2 vertex1 3 3 -2 vertex2 3.5 1 -2 }\n    Triangle {");
    // A dull ball (neither a mirror nor glass) whose lower half faces away from both lights.
    replace("    MaterialIndex 2\n", "    MaterialIndex 3\n    Sphere { center 0 -0.5 2 radius 0.5 }\n    MaterialIndex 2\n");
    write_file(dir + "/s.txt", text);
    for (const SpecularModel model :
         {SpecularModel::Phong, SpecularModel::BlinnClampedByNdotL, SpecularModel::BlinnTimesNdotL}) {
        for (const bool shade_back : {false, true}) {
            SceneLoadOptions load;
            SceneBuildOptions build;
            build.conventions.specular = model;
            build.conventions.shade_back_faces = shade_back;
            build.width = build.height = 24;
            Scene scene = build_scene(load_scene_file(dir + "/s.txt", load), build);
            ASSERT_EQ(scene.lights[0].kind, Light::Kind::Point);
            scene.lights[0].attenuation = Vec3f{1, 0.05f, 0.01f};
            for (const bool shadows : {false, true}) {
                SCOPED_TRACE(testing::Message() << "model " << static_cast<int>(model) << " shade_back "
                                                << shade_back << " shadows " << shadows);
                RenderOptions options;
                options.shadows = shadows;
                options.threads = 2;
                RenderStats stats;
                const Image image = render_image(scene, options, &stats);
                int mismatches = 0, lit = 0, back = 0;
                uint64_t explained_shadow_rays = 0;
                for (int y = 0; y < image.height; ++y)
                    for (int x = 0; x < image.width; ++x) {
                        const PixelExplanation explanation = explain_pixel(scene, options, x, image.height - 1 - y);
                        for (const RayRecord& ray : explanation.samples[0].rays)
                            explained_shadow_rays += ray.kind == RayKind::Shadow ? 1 : 0;
                        const Vec3f expected = explanation.color;
                        const Vec3f got = image.at(x, y);
                        if (std::memcmp(&expected, &got, sizeof got) != 0) ++mismatches;
                        if (got != scene.background) ++lit;
                        const Ray ray = camera_ray(scene.camera, static_cast<float>(x), static_cast<float>(y));
                        Hit hit;
                        intersect(scene, ray, scene.camera.t_min, hit);
                        if (hit.is_hit() && dot(surface_at(scene, ray, hit).normal, ray.direction) > 0) ++back;
                    }
                EXPECT_EQ(mismatches, 0);
                // The same shadow rays: the render decides which to trace for the whole packet.
                EXPECT_EQ(stats.shadow_rays, explained_shadow_rays);
                if (shadows) {
                    EXPECT_GT(explained_shadow_rays, 0u);
                }
                EXPECT_GT(back, 4);  // the clockwise triangle is seen from behind
                EXPECT_GT(lit, image.width * image.height / 2);  // mostly surfaces, not background
            }
        }
    }
}

TEST(ExplainTest, TheJsonShowsTheRayTreeAUserExpects) {
    const std::string dir = scene_dir("json");
    const RunResult render = run_raycast("s.txt image.ppm --shadows --bounces 3 -q", dir);
    ASSERT_EQ(render.exit_code, 0) << render.output;
    const ImageRgb8 image = read_image(dir + "/image.ppm");

    // The mirror ball's centre: pixel (4, 9) counted from the top.
    const RunResult run = run_raycast("explain s.txt 4 9 --shadows --bounces 3", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const JsonValue json = parse_json(run.output);
    ASSERT_EQ(json.type, JsonValue::Type::Object);
    EXPECT_EQ(json["scene"].string, "s.txt");
    EXPECT_EQ(json["x"].number, 4);
    EXPECT_EQ(json["y"].number, 9);
    EXPECT_EQ(json["image_size"][0].number, 20);
    EXPECT_EQ(json["mode"].string, "shaded");
    EXPECT_EQ(json["bounces"].number, 3);
    EXPECT_EQ(json["shadows"].boolean, true);
    const uint8_t* pixel = image.at(4, 20 - 1 - 9);
    for (size_t c = 0; c < 3; ++c) EXPECT_EQ(json["rgb8"][c].number, pixel[c]) << c;
    ASSERT_EQ(json["samples"].array.size(), 1u);
    const JsonValue& camera = json["samples"][0]["ray"];
    EXPECT_EQ(camera["kind"].string, "camera");
    EXPECT_EQ(camera["depth"].number, 0);
    ASSERT_EQ(camera["hit"].type, JsonValue::Type::Object);
    EXPECT_EQ(camera["hit"]["object"].number, 0);  // the mirror ball
    EXPECT_EQ(camera["hit"]["side"].string, "front");
    // Two lights: two shadow rays and two light terms; one reflected ray, no transmitted one.
    int shadows = 0, reflected = 0, transmitted = 0;
    for (const JsonValue& child : camera["children"].array) {
        shadows += child["kind"].string == "shadow";
        reflected += child["kind"].string == "reflected";
        transmitted += child["kind"].string == "transmitted";
    }
    EXPECT_EQ(shadows, 2);
    EXPECT_EQ(reflected, 1);
    EXPECT_EQ(transmitted, 0);
    EXPECT_EQ(camera["shading"]["lights"].array.size(), 2u);
    // The root's colour is the sum of its parts: local + reflected + transmitted.
    for (size_t c = 0; c < 3; ++c)
        EXPECT_NEAR(camera["color"][c].number,
                    camera["shading"]["local"][c].number + camera["shading"]["reflected"][c].number +
                        camera["shading"]["transmitted"][c].number,
                    1e-6);

    // The glass ball's centre (1.4, −0.2, 0.5): x = 10 + 37.32·1.4/9.5 = 15.5, y = 10 − 37.32·0.2/9.5
    // = 9.2 from the bottom, so row 10 from the top. The tree holds transmitted rays.
    const JsonValue glass = parse_json(run_raycast("explain s.txt 15 10 --bounces 3 -q", dir).output);
    std::vector<const JsonValue*> rays;
    collect_rays(glass["samples"][0]["ray"], rays);
    int through = 0;
    for (const JsonValue* ray : rays) through += (*ray)["kind"].string == "transmitted";
    EXPECT_GE(through, 2);  // in and out
    EXPECT_EQ(glass["samples"][0]["ray"]["hit"]["object"].number, 1);
}

TEST(ExplainTest, TheMitFormAndSamplesWork) {
    const std::string dir = scene_dir("mit");
    ASSERT_EQ(run_raycast("-input s.txt -size 20 20 -output m.ppm -bounces 2 -shadows -shade_back -q", dir).exit_code, 0);
    const RunResult run = run_raycast("explain -input s.txt -size 20 20 -bounces 2 -shadows -shade_back 15 10 -q", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const JsonValue json = parse_json(run.output);
    const ImageRgb8 image = read_image(dir + "/m.ppm");
    for (size_t c = 0; c < 3; ++c) EXPECT_EQ(json["rgb8"][c].number, image.at(15, 9)[c]);
    // Four samples: four trees, each from its own point in the pixel.
    const JsonValue sampled = parse_json(run_raycast("explain s.txt 3 3 --spp 4 -q", dir).output);
    ASSERT_EQ(sampled["samples"].array.size(), 4u);
    for (const JsonValue& sample : sampled["samples"].array) {
        EXPECT_GE(sample["offset"][0].number, 0);
        EXPECT_LT(sample["offset"][0].number, 1);
        EXPECT_EQ(sample["ray"]["kind"].string, "camera");
    }
}

// A glass goblet (a closed surface of revolution: its profile climbs the outside of the cup and
// comes down the inside to the axis) in front of a red ball.
const char* const kGobletScene = R"(PerspectiveCamera {
    center 0 2.5 9  direction 0 -0.15 -1  up 0 1 0  angle 30  width 24  height 24
}
Lights { numLights 1 PointLight { position -4 7 6 color 0.9 0.9 0.9 } }
Background { color 0.4 0.5 0.7 }
Materials {
    numMaterials 3
    Material { diffuseColor 0 0 0 specularColor 0.8 0.8 0.8 shininess 60
               reflectiveColor 0.1 0.1 0.1 transparentColor 0.9 0.9 0.9 indexOfRefraction 1.5 }
    Material { diffuseColor 0.8 0.2 0.1 }
    Material { diffuseColor 0.5 0.5 0.5 }
}
Group {
    numObjects 3
    MaterialIndex 0
    RevSurface { profile BsplineCurve { controls
        [ 0 0 0 ] [ 0 0 0 ] [ 0 0 0 ] [ 0.9 0 0 ] [ 1.05 0.05 0 ] [ 0.95 0.14 0 ] [ 0.3 0.22 0 ]
        [ 0.12 0.5 0 ] [ 0.11 1.1 0 ] [ 0.18 1.4 0 ] [ 0.95 1.55 0 ] [ 1.25 2.3 0 ] [ 1.1 3.0 0 ]
        [ 1.06 3.2 0 ] [ 1.0 3.2 0 ] [ 1.03 2.4 0 ] [ 0.8 1.75 0 ] [ 0 1.62 0 ] [ 0 1.62 0 ] [ 0 1.62 0 ] } }
    MaterialIndex 1
    Sphere { center 0.5 1.5 -3 radius 1 }
    MaterialIndex 2
    Plane { normal 0 1 0 offset -0.01 }
}
)";

TEST(ExplainTest, GlassSurfacesOfRevolutionAreRayTracedAndExplained) {
    const std::string dir = temp_dir("explain/goblet");
    write_file(dir + "/g.txt", kGobletScene);
    SceneDesc desc = load_scene_file(dir + "/g.txt");
    const Scene scene = build_scene(std::move(desc), SceneBuildOptions{});
    RenderOptions options;
    options.shadows = true;
    options.transparent_shadows = true;
    options.bounces = 6;
    options.threads = 2;
    const ImageRgb8 image = render_image_rgb8(scene, options);
    int through_glass = 0, mismatches = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const PixelExplanation e = explain_pixel(scene, options, x, image.height - 1 - y);
            const uint8_t* pixel = image.at(x, y);
            if (e.rgb8[0] != pixel[0] || e.rgb8[1] != pixel[1] || e.rgb8[2] != pixel[2]) ++mismatches;
            // A ray into the glass comes out again: a transmitted ray that starts inside (it met
            // the surface's back, leaving) follows one that entered (met its front).
            const RayTree& tree = e.samples[0];
            bool entered = false, left = false;
            for (const RayRecord& r : tree.rays) {
                if (r.kind != RayKind::Transmitted) continue;
                // The profile's normal points out of the solid (the starter's T × z): from its
                // front a refracted ray goes into glass (index 1.5), from its back out to vacuum.
                const RayRecord& parent = tree.rays[static_cast<size_t>(r.parent)];
                if (parent.object == 0) {
                    EXPECT_EQ(r.index_of_refraction, parent.back_face ? 1.0f : 1.5f);
                }
                if (!r.hit || r.object != 0) continue;
                entered |= !parent.back_face;
                left |= r.back_face;
            }
            through_glass += entered && left ? 1 : 0;
        }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(through_glass, 20) << "rays should enter the goblet's glass and leave it";
}

// Trees that double with every bounce: at 80 bounces one pixel's JSON was 421 MB. The trees of a
// pixel keep at most kMaxExplainedRays rays (shared out among its samples) and count the rest;
// the colour is still that of every ray traced, and the JSON's indentation stops growing past 16
// levels.
TEST(ExplainTest, DeepTreesAreCutAtTheLimitAndCountWhatTheyLeaveOut) {
    const std::string dir = temp_dir("explain/deep");
    write_file(dir + "/s.txt", mirrors_and_glass_scene(8));
    const Scene scene = build_scene(load_scene_file(dir + "/s.txt"), SceneBuildOptions{});
    RenderOptions options;
    options.shadows = true;
    options.transparent_shadows = true;
    options.bounces = 40;
    options.weight_cutoff = 0;
    options.threads = 2;
    for (const int spp : {1, 4}) {
        SCOPED_TRACE(spp);
        options.samples_per_pixel = spp;
        const ImageRgb8 image = render_image_rgb8(scene, options);
        const size_t capacity = kMaxExplainedRays / static_cast<size_t>(spp);
        int full = 0, mismatches = 0;
        const int row = 4;  // through the ball
        for (int x = 0; x < image.width; ++x) {
            const PixelExplanation e = explain_pixel(scene, options, x, row);
            const uint8_t* pixel = image.at(x, image.height - 1 - row);
            if (e.rgb8[0] != pixel[0] || e.rgb8[1] != pixel[1] || e.rgb8[2] != pixel[2]) ++mismatches;
            for (const RayTree& tree : e.samples) {
                ASSERT_LE(tree.rays.size(), capacity);
                if (tree.unrecorded == 0) continue;
                EXPECT_EQ(tree.rays.size(), capacity);
                ++full;
            }
            const std::string text = explanation_json(e);
            const JsonValue json = parse_json(text);
            EXPECT_EQ(json["samples"][0]["unrecorded_rays"].number, double(e.samples[0].unrecorded));
            size_t widest_indent = 0;
            for (size_t start = 0; start < text.size();) {
                const size_t end = std::min(text.find('\n', start), text.size());
                widest_indent = std::max(widest_indent, text.find_first_not_of(' ', start) - start);
                start = end + 1;
            }
            EXPECT_LE(widest_indent, 32u);
        }
        EXPECT_EQ(mismatches, 0);
        EXPECT_GT(full, 0) << "no tree reached the limit";
    }
}

TEST(ExplainTest, MistakesOnTheCommandLineAreUsageErrors) {
    const std::string dir = scene_dir("usage");
    struct Case {
        const char* arguments;
        const char* message;
    };
    for (const Case& c : {
             Case{"explain s.txt 20 3 -q", "raycast: usage error: pixel 20 3 is outside the 20x20 image (columns 0 to 19, "
                                        "rows 0 to 19)"},
             Case{"explain s.txt 3", "raycast: usage error: explain needs a scene and a pixel: raycast explain SCENE X Y"},
             Case{"explain s.txt -1 3", "raycast: usage error: explain X must not be negative, got -1"},
             Case{"explain s.txt 1 2 3", "raycast: usage error: explain needs a scene and a pixel: raycast explain SCENE X Y"},
             Case{"explain s.txt x 3", "raycast: usage error: explain X needs a whole number, got 'x'"},
             Case{"explain s.txt 1 1 --bounces -2", "raycast: usage error: --bounces must not be negative, got -2"},
             Case{"explain -input s.txt -size 4 4 -output o.ppm 1 1",
                  "raycast: usage error: explain prints the ray tree of one pixel and writes no image: drop -output, "
                  "-depth and -normals"},
             Case{"explain s.txt 15 15 --crop 0,0,10,10",
                  "raycast: usage error: explain takes X and Y in the whole image: drop --crop"},
         }) {
        const RunResult run = run_raycast(c.arguments, dir);
        EXPECT_EQ(run.exit_code, 2) << c.arguments << "\n" << run.output;
        EXPECT_EQ(first_line(run.output), c.message) << c.arguments;
    }
    // A scene error is an input error, as for a render.
    write_file(dir + "/bad.txt", "PerspectiveCamera { center 0 0 10 }\n");
    EXPECT_EQ(run_raycast("explain bad.txt 0 0", dir).exit_code, 1);
}

}  // namespace
}  // namespace raycast::test
