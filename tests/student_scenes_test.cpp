// What scenes written by the course's students need (the issue "The scenes students actually
// write"), run as a user would: the handout's field of view for non-square images, with a note
// saying so; --allow-missing-meshes; a field given twice; quoted mesh paths with and without
// spaces. The sphere extents below are worked out by hand from the camera formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "test_support.h"

namespace raycast::test {
namespace {

// A sphere of radius 2 at distance 10 seen through a 90° camera in an 80×40 frame.
// The ray through pixel (x, y) is (a, b, −1) with a = (x − 40)/f_x and b = (y − 20)/f_y; it meets
// the sphere when its distance from the centre, 10·√(a² + b²)/√(1 + a² + b²), is below 2, that is
// when a² + b² < 4/96. Along the centre row (b = 0): |x − 40| < f_x·0.20412.
//  - the handout's reading (default): f_x = 40/tan 45° = 40 → |x − 40| < 8.165: columns 32..48, 17
//  - square pixels (--fov vertical): f_x = f_y = 20 → |x − 40| < 4.082: columns 36..44, 9
// Along the centre column (a = 0) both give f_y = 20 → rows 16..24, 9.
const char* const kWideScene = R"(PerspectiveCamera {
    center 0 0 10  direction 0 0 -1  up 0 1 0  angle 90  width 80  height 40
}
Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }
Background { color 0 0 0 }
Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }
Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 2 } }
)";

// Pixels lit in row `y` (y = 0 at the bottom, as ImageRgb8 stores it) and in column `x`.
int lit_in_row(const ImageRgb8& image, int y) {
    int count = 0;
    for (int x = 0; x < image.width; ++x) count += image.at(x, y)[0] > 0 ? 1 : 0;
    return count;
}
int lit_in_column(const ImageRgb8& image, int x) {
    int count = 0;
    for (int y = 0; y < image.height; ++y) count += image.at(x, y)[0] > 0 ? 1 : 0;
    return count;
}

std::string wide_dir(const std::string& name) {
    const std::string dir = temp_dir("students/" + name);
    write_file(dir + "/wide.txt", kWideScene);
    return dir;
}

const char* const kStretchNote =
    "raycast: note: the image is 80x40 and the camera's angle spans both its width and its height, so "
    "pixels are stretched as the course's handout defines them; --fov vertical gives square pixels";

TEST(StudentScenesTest, AngleSpansBothAxesByDefaultAndTheHeightWithFovVertical) {
    const std::string dir = wide_dir("fov");
    ASSERT_EQ(run_raycast("wide.txt default.ppm -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("wide.txt both.ppm -q --fov both", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("wide.txt vertical.ppm -q --fov vertical", dir).exit_code, 0);
    const ImageRgb8 stretched = read_image(dir + "/default.ppm");
    const ImageRgb8 square = read_image(dir + "/vertical.ppm");
    ASSERT_EQ(stretched.width, 80);
    ASSERT_EQ(stretched.height, 40);
    EXPECT_EQ(read_file(dir + "/default.ppm"), read_file(dir + "/both.ppm"));
    // Row 20 and column 40 go through the image centre.
    EXPECT_EQ(lit_in_row(stretched, 20), 17);
    EXPECT_EQ(lit_in_column(stretched, 40), 9);
    EXPECT_EQ(lit_in_row(square, 20), 9);
    EXPECT_EQ(lit_in_column(square, 40), 9);
}

TEST(StudentScenesTest, MitConventionsKeepSquarePixels) {
    const std::string dir = wide_dir("fov_mit");
    ASSERT_EQ(run_raycast("wide.txt mit.ppm -q --conventions mit6837", dir).exit_code, 0);
    // Square pixels, sampled at their centres: row y = 20 is at 20.5, so b = 0.025 and
    // |x + 0.5 − 40| < 20·√(4/96 − b²) = 4.05: columns 36..43, 8 of them.
    EXPECT_EQ(lit_in_row(read_image(dir + "/mit.ppm"), 20), 8);
}

TEST(StudentScenesTest, ANoteSaysWhenPixelsAreStretchedAndOnlyThen) {
    const std::string dir = wide_dir("note");
    RunResult run = run_raycast("wide.txt o.ppm", dir);
    ASSERT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output, std::string(kStretchNote) + "\n");
    // Not with -q, not when --fov is given, not for a square image, not with MIT's conventions.
    for (const char* options : {"-q", "--fov both", "--fov vertical", "--size 40x40", "--conventions mit6837"}) {
        run = run_raycast(std::string("wide.txt o.ppm ") + options, dir);
        EXPECT_EQ(run.exit_code, 0) << options;
        EXPECT_EQ(run.output, "") << options;
    }
    // --size decides: a square scene made wide gets the note, with the size it has.
    run = run_raycast("wide.txt o.ppm --size 64x32", dir);
    EXPECT_NE(run.output.find("the image is 64x32 and the camera's angle spans both"), std::string::npos) << run.output;
}

// Two spheres and a mesh that is not there.
std::string scene_with_mesh(const std::string& mesh_line, int objects) {
    return std::string(R"(PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 24 height 24 }
Lights { numLights 1 DirectionalLight { direction -1 -1 -1 color 1 1 1 } }
Background { color 0.1 0.2 0.3 }
Materials { numMaterials 2 Material { diffuseColor 1 0 0 } Material { diffuseColor 0 1 0 } }
Group {
    numObjects )") + std::to_string(objects) + R"(
    MaterialIndex 0
    Sphere { center -1 0 0 radius 1 }
    MaterialIndex 1
)" + mesh_line + R"(
    Sphere { center 1 0 0 radius 1 }
}
)";
}

TEST(StudentScenesTest, AMissingMeshIsAnErrorUnlessAllowedThenAWarningAndTheRestRenders) {
    const std::string dir = temp_dir("students/missing_mesh");
    write_file(dir + "/s.txt", scene_with_mesh("    TriangleMesh { obj_file mesh/big.obj }", 3));
    write_file(dir + "/without.txt", scene_with_mesh("", 2));
    const std::string message =
        "s.txt:10:29: %s: cannot open OBJ file 'mesh/big.obj': tried 'mesh/big.obj' (from the working "
        "directory) and '../mesh/big.obj' (from the scene file's parent folder)\n"
        "      TriangleMesh { obj_file mesh/big.obj }\n"
        "                              ^\n";
    auto with = [&](const char* severity) {
        std::string text = message;
        text.replace(text.find("%s"), 2, severity);
        return text;
    };

    RunResult run = run_raycast("s.txt refused.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output, with("error") + "s.txt:10: note: --allow-missing-meshes renders the rest of the scene without it\n");
    EXPECT_FALSE(file_exists(dir + "/refused.ppm"));

    run = run_raycast("s.txt allowed.ppm --allow-missing-meshes", dir);
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output,
              with("warning") + "s.txt:10: note: the scene is rendered without this mesh (--allow-missing-meshes)\n");
    ASSERT_EQ(run_raycast("without.txt expected.ppm", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/allowed.ppm"), read_file(dir + "/expected.ppm"));

    // -q silences the warning; a mesh that exists but is broken is still an error.
    run = run_raycast("s.txt quiet.ppm --allow-missing-meshes -q", dir);
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output, "");
    std::filesystem::create_directories(dir + "/mesh");
    write_file(dir + "/mesh/big.obj", "v 0 0 0\nf 1 2 3\n");
    run = run_raycast("s.txt broken.ppm --allow-missing-meshes", dir);
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_FALSE(file_exists(dir + "/broken.ppm"));
}

TEST(StudentScenesTest, QuotedMeshPathsWithAndWithoutSpacesRenderTheSameMesh) {
    const std::string dir = temp_dir("students/quoted");
    const std::string quad = "v -2 -1 -2\nv 2 -1 -2\nv 2 2 -2\nv -2 2 -2\nf 1 2 3 4\n";
    write_file(dir + "/quad.obj", quad);
    write_file(dir + "/my quad.obj", quad);
    write_file(dir + "/plain.txt", scene_with_mesh("    TriangleMesh { obj_file quad.obj }", 3));
    write_file(dir + "/quoted.txt", scene_with_mesh("    TriangleMesh { obj_file \"quad.obj\" }", 3));
    write_file(dir + "/spaces.txt", scene_with_mesh("    TriangleMesh { obj_file \"my quad.obj\"}", 3));
    write_file(dir + "/open.txt", scene_with_mesh("    TriangleMesh { obj_file \"my quad.obj }", 3));
    for (const char* name : {"plain", "quoted", "spaces"}) {
        const RunResult run = run_raycast(std::string(name) + ".txt " + name + ".ppm", dir);
        EXPECT_EQ(run.exit_code, 0) << name << ": " << run.output;
        EXPECT_EQ(run.output, "") << name;
    }
    EXPECT_EQ(read_file(dir + "/quoted.ppm"), read_file(dir + "/plain.ppm"));
    EXPECT_EQ(read_file(dir + "/spaces.ppm"), read_file(dir + "/plain.ppm"));
    // The mesh is in the image.
    write_file(dir + "/none.txt", scene_with_mesh("", 2));
    ASSERT_EQ(run_raycast("none.txt none.ppm", dir).exit_code, 0);
    EXPECT_NE(read_file(dir + "/plain.ppm"), read_file(dir + "/none.ppm"));

    const RunResult run = run_raycast("open.txt open.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(first_line(run.output),
              "open.txt:10:29: error: the file name's quote is not closed: add a '\"' before the end of the line");
    EXPECT_FALSE(file_exists(dir + "/open.ppm"));
}

TEST(StudentScenesTest, AFieldGivenTwiceRendersWithTheLastValueAndAWarning) {
    const std::string dir = temp_dir("students/twice");
    std::string scene = scene_with_mesh("", 2);
    const std::string red = "Material { diffuseColor 1 0 0 }";
    scene.replace(scene.find(red), red.size(), "Material { diffuseColor 1 0 0 diffuseColor 0 0 1 }");
    write_file(dir + "/twice.txt", scene);
    std::string blue_scene = scene_with_mesh("", 2);
    blue_scene.replace(blue_scene.find(red), red.size(), "Material { diffuseColor 0 0 1 }");
    write_file(dir + "/blue.txt", blue_scene);
    const RunResult run = run_raycast("twice.txt twice.ppm", dir);
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output,
              "twice.txt:4:58: warning: 'diffuseColor' is given twice in Material: the last value is used\n"
              "  Materials { numMaterials 2 Material { diffuseColor 1 0 0 diffuseColor 0 0 1 } Material { "
              "diffuseColor 0 1 0 } }\n"
              "                                                           ^\n"
              "twice.txt:4:39: note: the first value was given here\n"
              "  Materials { numMaterials 2 Material { diffuseColor 1 0 0 diffuseColor 0 0 1 } Material { "
              "diffuseColor 0 1 0 } }\n"
              "                                        ^\n");
    ASSERT_EQ(run_raycast("blue.txt blue.ppm", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/twice.ppm"), read_file(dir + "/blue.ppm"));
}

TEST(StudentScenesTest, MirrorsAndGlassWithoutBouncesSaySoOnce) {
    const std::string dir = temp_dir("students/no_bounces");
    std::string scene = scene_with_mesh("", 2);
    const std::string red = "Material { diffuseColor 1 0 0 }";
    scene.replace(scene.find(red), red.size(), "Material { diffuseColor 1 0 0 reflectiveColor 0.5 0.5 0.5 }");
    write_file(dir + "/mirror.txt", scene);
    const std::string note =
        "raycast: note: the scene has reflective or transparent materials, but no reflected or transmitted rays "
        "are traced: add --bounces N (e.g. --bounces 5) to see mirrors and glass\n";
    EXPECT_EQ(run_raycast("mirror.txt o.ppm", dir).output, note);
    // MIT's form names its own flag.
    EXPECT_EQ(run_raycast("-input mirror.txt -output o.ppm", dir).output,
              "raycast: note: the scene has reflective or transparent materials, but no reflected or transmitted rays "
              "are traced: add -bounces N (e.g. -bounces 5) to see mirrors and glass\n");
    for (const char* quiet : {"--bounces 1", "-q", "--mode normals"})
        EXPECT_EQ(run_raycast(std::string("mirror.txt o.ppm ") + quiet, dir).output, "") << quiet;
    // A reflective material that no object uses is not worth a note.
    std::string unused = scene;
    unused.replace(unused.find("MaterialIndex 0"), 15, "MaterialIndex 1");
    write_file(dir + "/unused.txt", unused);
    EXPECT_EQ(run_raycast("unused.txt o.ppm", dir).output, "");
}

}  // namespace
}  // namespace raycast::test
