// Surfaces of revolution rendered by the program, end to end.
//  - Exact against tessellated: three surfaces (a cubic Bezier profile under rotations, a B-spline
//    goblet under a non-uniform scale, a degree-6 Bezier under a shear) rendered as RevSurface and
//    as dense triangle meshes with the surfaces' normals at the vertices, written as OBJ files by
//    raycast_revolve (tessellate_rev_surface evaluates the curves with eval_curve and shares
//    nothing with the intersection): the two images must agree within 2 levels on at least 99%
//    of the pixels, and the handout's coarse 30 × 40 tessellation must not.
//  - Every way of rendering works on them and agrees where it must: SIMD packets or single rays,
//    any thread count, crop pieces merged, each --mode, --spp, --shadows (the surfaces shadow the
//    floor), and --stats counts the surfaces and the Newton steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "geometry/curve.h"
#include "image/compare_images.h"
#include "image/image_io.h"
#include "test_support.h"

namespace raycast {
namespace {

struct Surface {
    Curve profile;
    int material = 0;
    std::string transform;  ///< transform items, the last applied first
};

std::vector<Surface> surfaces() {
    std::vector<Surface> all(3);
    // A vase: one cubic Bezier, listed upwards so that the starter's normal points out; tipped
    // towards the camera and turned.
    all[0].profile.type = CurveType::Bezier;
    all[0].profile.controls = {{0.9f, -1, 0}, {0.1f, -0.25f, 0}, {1.75f, 0.25f, 0}, {0.75f, 1, 0}};
    all[0].material = 0;
    all[0].transform = "Translate -2.7 0.1 0 YRotate 30 XRotate 25";
    // A goblet: a B-spline from the axis (three equal points), up the cup's outside, down its
    // inside, a stem and a foot back to the axis; squashed unevenly.
    all[1].profile.type = CurveType::Bspline;
    all[1].profile.controls = {{0, -1.6f, 0},  {0, -1.6f, 0},     {0, -1.6f, 0},   {1.1f, -1.6f, 0}, {1.2f, -1.45f, 0},
                               {0.25f, -1.3f, 0}, {0.12f, -0.6f, 0}, {0.2f, -0.1f, 0}, {1.2f, 0.2f, 0},  {1.3f, 1.3f, 0},
                               {1.1f, 1.9f, 0}, {1.15f, 1.95f, 0}, {1.0f, 1.7f, 0},  {0.9f, 0.6f, 0},  {0, 0.3f, 0},
                               {0, 0.3f, 0},    {0, 0.3f, 0}};
    all[1].material = 1;
    all[1].transform = "Translate 0 0.1 0 XRotate 15 Scale 0.8 0.9 0.55";
    // Degree 6, crossing the axis; sheared (x += 0.4 y) by a column-major Matrix4f.
    all[2].profile.type = CurveType::Bezier;
    all[2].profile.controls = {{-0.5f, -1, 0}, {1, -0.75f, 0}, {-0.25f, 0.5f, 0}, {0.75f, -0.25f, 0},
                               {0.25f, 0.4f, 0}, {1, 0.75f, 0}, {0.25f, 1, 0}};
    all[2].material = 2;
    all[2].transform = "Translate 2.5 -0.3 0 Matrix4f { 1 0 0 0  0.4 1 0 0  0 0 1 0  0 0 0 1 } XRotate -10";
    return all;
}

std::string profile_text(const Curve& curve) {
    std::string text = curve.type == CurveType::Bezier ? "BezierCurve { controls" : "BsplineCurve { controls";
    char point[96];
    for (const Vec3f& p : curve.controls) {
        std::snprintf(point, sizeof point, " [ %.9g %.9g %.9g ]", double(p.x), double(p.y), double(p.z));
        text += point;
    }
    return text + " }";
}

// The scene with each surface written by `object(i)`, over a floor that catches their shadows.
template <typename ObjectFn>
std::string scene_text(ObjectFn object) {
    std::string text =
        "PerspectiveCamera { center 0 0.8 10 direction 0 -0.1 -1 up 0 1 0 angle 40 width 200 height 120 }\n"
        "Lights { numLights 2\n"
        "  DirectionalLight { direction -0.4 -0.6 -1 color 0.7 0.7 0.7 }\n"
        "  PointLight { position 3 5 6 color 0.5 0.5 0.5 } }\n"
        "Background { color 0.1 0.1 0.15 }\n"
        "Materials { numMaterials 4\n"
        "  Material { diffuseColor 0.8 0.35 0.2 specularColor 0.3 0.3 0.3 shininess 8 }\n"
        "  Material { diffuseColor 0.3 0.6 0.9 specularColor 0.3 0.3 0.3 shininess 12 }\n"
        "  Material { diffuseColor 0.9 0.8 0.3 specularColor 0.2 0.2 0.2 shininess 6 }\n"
        "  Material { diffuseColor 0.5 0.5 0.5 } }\n"
        "Group { numObjects 4\n"
        "  MaterialIndex 3 Plane { normal 0 1 0 offset -1.8 }\n";
    const std::vector<Surface> all = surfaces();
    for (size_t i = 0; i < all.size(); ++i)
        text += "  MaterialIndex " + std::to_string(all[i].material) + " Transform { " + all[i].transform + " " +
                object(i) + " }\n";
    return text + "}\n";
}

std::string exact_scene() {
    const std::vector<Surface> all = surfaces();
    return scene_text([&](size_t i) { return "RevSurface { profile " + profile_text(all[i].profile) + " }"; });
}

// Writes the exact scene (exact.txt) into `dir`; returns the folder.
std::string exact_dir(const std::string& name) {
    const std::string dir = test::temp_dir("rev-surface/" + name);
    test::write_file(dir + "/exact.txt", exact_scene());
    return dir;
}

ImageRgb8 render(const std::string& dir, const std::string& scene, const std::string& output,
                 const std::string& options = "") {
    const test::RunResult run = test::run_raycast(scene + " " + output + " -q " + options, dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_image(dir + "/" + output);
}

bool identical(const ImageRgb8& a, const ImageRgb8& b) {
    return a.width == b.width && a.height == b.height && std::equal(a.rgb.begin(), a.rgb.end(), b.rgb.begin());
}

// The surfaces as meshes of along × around steps, made by raycast_revolve (the scene with each
// RevSurface replaced by an OBJ file with the surface's normals), against the exact image.
ImageComparison against_tessellation(const std::string& dir, const ImageRgb8& exact, int along, int around) {
    const std::string name = std::to_string(along) + "x" + std::to_string(around);
    const test::RunResult made = test::run_command("cd '" + dir + "' && '" + std::string(RAYCAST_BINARY_DIR) +
                                                   "/raycast_revolve' exact.txt " + name + ".txt --along " +
                                                   std::to_string(along) + " --around " + std::to_string(around) + " 2>&1");
    EXPECT_EQ(made.exit_code, 0) << made.output;
    EXPECT_EQ(made.output, "raycast_revolve: 3 surfaces, " + std::to_string(3 * 2 * along * around) + " triangles (" +
                               std::to_string(along) + " x " + std::to_string(around) + " each)\n");
    const ImageComparison c = compare_images(exact, render(dir, name + ".txt", name + ".ppm"));
    std::printf("exact against a %s tessellation: %zu of %zu pixels differ, %zu by more than 2 levels (max %d)\n",
                name.c_str(), c.differing_pixels, c.pixel_count, c.pixels_beyond(2), c.max_error);
    return c;
}

TEST(RevSurfaceRenderTest, ExactSurfacesMatchADenseTessellation) {
    const std::string dir = exact_dir("tessellated");
    const ImageRgb8 exact = render(dir, "exact.txt", "exact.ppm");
    // The surfaces fill a good part of the frame, so the comparison is about them.
    size_t background = 0;
    for (size_t i = 0; i + 2 < exact.rgb.size(); i += 3)
        background += exact.rgb[i] == 25 && exact.rgb[i + 1] == 25 && exact.rgb[i + 2] == 38;
    EXPECT_LT(background, exact.rgb.size() / 3 / 2);
    const ImageComparison dense = against_tessellation(dir, exact, 200, 160);
    EXPECT_LE(dense.pixels_beyond(2), dense.pixel_count / 100);
    // The comparison sees the geometry: the handout's coarse 30 × 40 tessellation fails it.
    const ImageComparison coarse = against_tessellation(dir, exact, 30, 40);
    EXPECT_GT(coarse.pixels_beyond(2), coarse.pixel_count / 100);
}

// Each of --along and --around may be 100000, but not both at once: raycast_revolve once tried to
// make 10^10 vertices and died of an uncaught std::bad_alloc. Now a usage error, before the scene
// is read, from just past the limit.
TEST(RevSurfaceRenderTest, RevolveRefusesMoreVerticesThanItsLimit) {
    const std::string dir = exact_dir("revolve_limit");
    const std::string tool = "'" + std::string(RAYCAST_BINARY_DIR) + "/raycast_revolve' ";
    const test::RunResult refused =
        test::run_command("cd '" + dir + "' && " + tool + "exact.txt big.txt --along 100000 --around 100000 2>&1");
    EXPECT_EQ(refused.exit_code, 2);
    EXPECT_EQ(refused.output,
              "raycast_revolve: --along 100000 by --around 100000 makes 10000100000 vertices a surface, more than the "
              "limit of 16777216\n");
    EXPECT_FALSE(test::file_exists(dir + "/big.txt"));
    const test::RunResult just_over =
        test::run_command("cd '" + dir + "' && " + tool + "exact.txt big.txt --along 4096 --around 4096 2>&1");
    EXPECT_EQ(just_over.exit_code, 2) << just_over.output;  // 4097 × 4096 vertices, 2^24 + 4096
}

TEST(RevSurfaceRenderTest, PacketsThreadsAndCropPiecesGiveTheSameImage) {
    const std::string dir = exact_dir("paths");
    const ImageRgb8 packets = render(dir, "exact.txt", "packets.ppm", "--threads 2");
    EXPECT_TRUE(identical(packets, render(dir, "exact.txt", "single.ppm", "--simd none --threads 1")));
    EXPECT_TRUE(identical(packets, render(dir, "exact.txt", "portable.ppm", "--simd portable --tile 8 --threads 3")));
    ASSERT_EQ(test::run_raycast("exact.txt top.ppm -q --crop 0,0,200,50", dir).exit_code, 0);
    ASSERT_EQ(test::run_raycast("exact.txt bottom.ppm -q --crop 0,50,200,120", dir).exit_code, 0);
    ASSERT_EQ(test::run_raycast("merge -o merged.ppm top.ppm bottom.ppm -q", dir).exit_code, 0);
    EXPECT_TRUE(identical(packets, read_image(dir + "/merged.ppm")));
}

// Pixels that differ between two images.
size_t differing(const ImageRgb8& a, const ImageRgb8& b) { return compare_images(a, b).differing_pixels; }

TEST(RevSurfaceRenderTest, EveryModeSamplesAndShadowsWork) {
    const std::string dir = exact_dir("modes");
    const ImageRgb8 plain = render(dir, "exact.txt", "plain.ppm");
    const ImageRgb8 shadows = render(dir, "exact.txt", "shadows.ppm", "--shadows");
    // The surfaces shadow the floor (and themselves): some pixels, and only darker ones.
    size_t darker = 0, lighter = 0;
    for (size_t i = 0; i < plain.rgb.size(); ++i) {
        darker += shadows.rgb[i] < plain.rgb[i];
        lighter += shadows.rgb[i] > plain.rgb[i];
    }
    EXPECT_GT(darker, 500u);
    EXPECT_EQ(lighter, 0u);
    // Antialiasing changes the edges only.
    const size_t changed = differing(plain, render(dir, "exact.txt", "spp.ppm", "--spp 4"));
    EXPECT_GT(changed, 100u);
    EXPECT_LT(changed, plain.rgb.size() / 3 / 3);
    // Each mode draws the surfaces: the material view has one flat colour per material, the normals
    // view |n|, the depth view grey levels, and all differ from the shaded image.
    for (const char* mode : {"normals", "depth", "material", "cost"}) {
        SCOPED_TRACE(mode);
        const ImageRgb8 image = render(dir, "exact.txt", std::string(mode) + ".ppm", std::string("--mode ") + mode);
        EXPECT_GT(differing(plain, image), plain.rgb.size() / 3 / 2);
    }
    // Shading normals: at the image's centre column the goblet faces the camera, |n_z| large.
    const ImageRgb8 normals = render(dir, "exact.txt", "normals2.ppm", "--mode normals");
    EXPECT_GT(normals.at(100, 60)[2], 150);
}

TEST(RevSurfaceRenderTest, StatsCountTheSurfacesAndNewtonSteps) {
    const std::string dir = exact_dir("stats");
    const test::RunResult run = test::run_raycast("exact.txt o.ppm --stats --shadows -q", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    std::map<std::string, std::string> fields;
    std::istringstream in(run.output);
    for (std::string field; in >> field;)
        if (field.find('=') != std::string::npos) fields[field.substr(0, field.find('='))] = field.substr(field.find('=') + 1);
    ASSERT_EQ(fields.count("rev_surfaces"), 1u) << run.output;
    EXPECT_EQ(fields.at("rev_surfaces"), "3");
    EXPECT_EQ(fields.at("triangles"), "0");
    // Every primary ray that reaches a surface's box is a test, and shadow rays add more.
    EXPECT_GT(std::stoull(fields.at("rev_surface_tests")), 5000u);
    EXPECT_GT(std::stoull(fields.at("newton_iterations")), std::stoull(fields.at("rev_surface_tests")) / 10);
    EXPECT_EQ(fields.at("newton_failures"), "0");
}

}  // namespace
}  // namespace raycast
