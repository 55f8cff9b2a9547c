// A catalogue of malformed and hostile inputs run through the raycast program. The rule under test
// (the issue, and docs/limits.md): every one ends with a located error and a non-zero exit, or with
// a correct image, within a few seconds; a failed run never leaves an output file; no NaN or
// infinity reaches an image. Each case asserts the exact first line of the message
// (`file:line:col: error: ...`, worked out by hand from the files in tests/bad_inputs/, where
// every file is valid.txt with one line changed or cut), the exit code, and that the output folder
// is still empty. Files that need bytes or sizes a text file cannot hold well (binary garbage,
// 100,000 nested groups) are written by the tests. Runs are guarded by `timeout` so that a hang
// fails the test instead of stalling the suite.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "test_support.h"

namespace raycast::test {
namespace {

const char* const kDir = "tests/bad_inputs/";

// Runs raycast from `working_dir` (the repository root by default) under `timeout`: exit 124 means
// it did not finish within a minute, far beyond the few seconds any of these inputs may take.
// `shell_setup` runs first in the same shell (e.g. a ulimit).
RunResult run_guarded(const std::string& arguments, const std::string& working_dir = source_dir(),
                      const std::string& shell_setup = "") {
    return run_command("cd '" + working_dir + "' && " + shell_setup + "timeout -k 5 60 '" +
                       std::string(RAYCAST_EXECUTABLE) + "' " + arguments + " 2>&1");
}

struct Rendered {
    RunResult run;
    std::string out_dir;  ///< an empty folder before the run; the image goes to out_dir/out.ppm
    std::string image() const { return out_dir + "/out.ppm"; }
};

// A new empty folder for one run, unique to the test and the call, so that tests run in parallel
// (ctest -j) never share one.
std::string fresh_dir(const std::string& label) {
    static int counter = 0;
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    return temp_dir(std::string("bad_inputs/") + test->name() + "/" + std::to_string(++counter) + "_" + label);
}

// Renders tests/bad_inputs/<name> (or any path given with a '/') into a fresh folder.
Rendered render(const std::string& name, const std::string& extra = "") {
    Rendered r;
    const std::string scene = name.find('/') == std::string::npos ? kDir + name : name;
    r.out_dir = fresh_dir(name.substr(name.find_last_of('/') + 1));
    r.run = run_guarded("'" + scene + "' '" + r.image() + "' " + extra);
    return r;
}

// The common assertion: exit 1, this exact first line, and nothing written (no image, no temporary).
void expect_input_error(const std::string& name, const std::string& expected_first_line) {
    SCOPED_TRACE(name);
    const Rendered r = render(name);
    EXPECT_NE(r.run.exit_code, 124) << "timed out";
    EXPECT_EQ(r.run.exit_code, 1) << r.run.output;
    EXPECT_EQ(first_line(r.run.output), expected_first_line) << r.run.output;
    EXPECT_TRUE(files_in(r.out_dir).empty()) << "a failed run left files in " << r.out_dir;
}

struct Case {
    const char* file;
    const char* message;  ///< the first line after "tests/bad_inputs/<file>"
};

void expect_input_errors(const std::vector<Case>& cases) {
    for (const Case& c : cases) expect_input_error(c.file, std::string(kDir) + c.file + c.message);
}

// Counts pixels that are not exactly (r, g, b).
int pixels_other_than(const Ppm& image, uint8_t r, uint8_t g, uint8_t b) {
    int count = 0;
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3)
        count += image.rgb[i] != r || image.rgb[i + 1] != g || image.rgb[i + 2] != b;
    return count;
}

// For inputs whose numbers are legal but extreme: either a located error with a non-zero exit and
// nothing written, or exit 0 and an image that passes `check_image`.
// Whether `line` is "<file>:<line>:<column>: error: ..." for the given file (digits for line and
// column). Written by hand: std::regex trips a false -Wmaybe-uninitialized in GCC 12 under ASan.
bool is_located_error(const std::string& line, const std::string& file) {
    if (line.compare(0, file.size(), file) != 0) return false;
    size_t pos = file.size();
    for (int part = 0; part < 2; ++part) {
        if (pos >= line.size() || line[pos] != ':') return false;
        const size_t digits_start = ++pos;
        while (pos < line.size() && line[pos] >= '0' && line[pos] <= '9') ++pos;
        if (pos == digits_start) return false;
    }
    return line.compare(pos, 9, ": error: ") == 0;
}

template <typename Check>
void expect_located_error_or_correct_image(const std::string& name, Check check_image,
                                           const char* false_claim = nullptr) {
    SCOPED_TRACE(name);
    const Rendered r = render(name, "-q");
    ASSERT_NE(r.run.exit_code, 124) << "timed out";
    if (r.run.exit_code == 0) {
        const Ppm image = parse_ppm(read_file(r.image()));
        ASSERT_TRUE(image.ok);
        check_image(image);
        return;
    }
    EXPECT_EQ(r.run.exit_code, 1) << r.run.output;
    EXPECT_TRUE(is_located_error(first_line(r.run.output), std::string(kDir) + name)) << r.run.output;
    if (false_claim) {
        EXPECT_EQ(r.run.output.find(false_claim), std::string::npos) << r.run.output;
    }
    EXPECT_TRUE(files_in(r.out_dir).empty());
}

// ---- the baseline --------------------------------------------------------------------------------

TEST(BadInputTest, TheValidBaselineSceneRendersSilently) {
    const Rendered r = render("valid.txt");
    EXPECT_EQ(r.run.exit_code, 0);
    EXPECT_EQ(r.run.output, "");
    const Ppm image = parse_ppm(read_file(r.image()));
    ASSERT_TRUE(image.ok);
    EXPECT_EQ(image.width, 8);
    EXPECT_EQ(image.height, 8);
    // The red sphere covers some pixels, the grey background (0.5 -> 127) the rest.
    EXPECT_GT(pixels_other_than(image, 127, 127, 127), 0);
    EXPECT_LT(pixels_other_than(image, 127, 127, 127), 64);
}

// ---- files that are not scenes ---------------------------------------------------------------------

TEST(BadInputTest, AnEmptyFileLacksACameraAndAGroup) {
    const Rendered r = render("empty.txt");
    EXPECT_EQ(r.run.exit_code, 1);
    EXPECT_EQ(r.run.output,
              "tests/bad_inputs/empty.txt: error: the scene has no camera: add a PerspectiveCamera block\n"
              "tests/bad_inputs/empty.txt: error: the scene has no Group: there is nothing to render\n");
    EXPECT_TRUE(files_in(r.out_dir).empty());
}

TEST(BadInputTest, BinaryGarbageIsRefusedAsNotTextAtItsFirstByte) {
    // Bytes 0, 1, ..., 255 sixteen times: the first, a NUL, shows that this is no text file
    // (sceneio/text_check.h). One error and nothing else; no source line, since it holds the NUL.
    const std::string dir = fresh_dir("garbage");
    std::string bytes;
    for (int round = 0; round < 16; ++round)
        for (int b = 0; b < 256; ++b) bytes += static_cast<char>(b);
    write_file(dir + "/garbage.txt", bytes);
    const RunResult run = run_guarded("garbage.txt out.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output, "garbage.txt:1:1: error: this is not a text file: byte 0x00 (NUL) never appears in text\n");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"garbage.txt"}));
}

// valid.txt with its sphere replaced by a TriangleMesh: the keyword at 24:5, the path at 25:18.
std::string scene_with_mesh(const std::string& obj_file) {
    const std::vector<std::string> lines = lines_of(read_file(source_dir() + "/" + kDir + "valid.txt"));
    std::string text;
    for (size_t i = 0; i < 23; ++i) text += lines[i] + "\n";
    return text + "    TriangleMesh {\n        obj_file " + obj_file + "\n    }\n}\n";
}

// Renders scene_with_mesh(obj_name) into dir/out.ppm, the OBJ file holding `obj_text`.
RunResult render_with_mesh(const std::string& dir, const std::string& obj_name, const std::string& obj_text) {
    write_file(dir + "/" + obj_name, obj_text);
    write_file(dir + "/scene.txt", scene_with_mesh(obj_name));
    return run_guarded("scene.txt out.ppm", dir);
}

TEST(BadInputTest, AMeshFileThatIsNotTextIsRefusedAtItsFirstBadByte) {
    using namespace std::string_literals;  // keeps the NUL bytes
    struct BinaryMesh {
        const char* name;
        std::string bytes;
        const char* error;
    };
    const BinaryMesh meshes[] = {
        // A zip archive renamed .obj: its local header's version field holds the first NUL.
        {"zip.obj", "PK\x03\x04\x14\0\0\0\x08\0"s, "zip.obj:1:6: error: this is not a text file: byte 0x00 (NUL) never appears in text"},
        // A binary FBX: "Kaydara FBX Binary" and two spaces, then a NUL.
        {"model.obj", "Kaydara FBX Binary  \0\x1a\0\xe8\x1c\0\0"s,
         "model.obj:1:21: error: this is not a text file: byte 0x00 (NUL) never appears in text"},
        // A PLY whose header is text and whose body is binary floats: 1.0f is 00 00 80 3f.
        {"bunny.obj", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n\0\0\x80\x3f"s,
         "bunny.obj:6:1: error: this is not a text file: byte 0x00 (NUL) never appears in text"},
        // No NUL, but a line that starts with a byte no UTF-8 character starts with.
        {"latin1.obj", "v 0 0 0\n\xe9t\xe9\n"s,
         "latin1.obj:2:1: error: this is not a text file: byte 0xe9 at the start of a line does not begin a UTF-8 "
         "character"},
    };
    for (const BinaryMesh& mesh : meshes) {
        SCOPED_TRACE(mesh.name);
        const std::string dir = fresh_dir(mesh.name);
        const RunResult run = render_with_mesh(dir, mesh.name, mesh.bytes);
        EXPECT_EQ(run.exit_code, 1);
        EXPECT_EQ(run.output, std::string(mesh.error) + "\nscene.txt:25:18: note: the mesh was named here\n" +
                                  "          obj_file " + mesh.name + "\n                   ^\n");
        EXPECT_EQ(files_in(dir), (std::set<std::string>{mesh.name, "scene.txt"}));
    }
}

// A typo in an OBJ file (a face written 'f1') drops the line: the user is told where, in the OBJ
// file, and the rest renders (LoadObj.UnknownStatementsAreSkippedWithAWarning has the rules).
TEST(BadInputTest, AnUnknownObjStatementIsWarnedAboutInTheObjFile) {
    const std::string dir = fresh_dir("unknown_statement");
    const RunResult run =
        render_with_mesh(dir, "typo.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf1 3 4\n");
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output,
              "typo.obj:6:1: warning: unknown statement 'f1': the line is skipped (raycast reads v, vn, vt and f, "
              "and passes over the other OBJ statements: o, g, s, usemtl, ...)\n"
              "  f1 3 4\n"
              "  ^\n");
    EXPECT_TRUE(file_exists(dir + "/out.ppm"));
}

// A broken OBJ file named by two TriangleMeshes is reported once, where it is first named, and
// the second naming gets a note (the file's errors were printed twice).
TEST(BadInputTest, ABrokenMeshNamedTwiceIsReportedOnce) {
    const std::string dir = fresh_dir("named_twice");
    write_file(dir + "/bad.obj", "v 0 0 0\nv 1 x 0\n");
    std::string scene = scene_with_mesh("bad.obj");
    const std::string mesh = "    TriangleMesh {\n        obj_file bad.obj\n    }\n";
    scene.insert(scene.rfind('}'), mesh);                                              // a second one
    scene.replace(scene.find("numObjects 1"), std::string("numObjects 1").size(), "numObjects 2");
    write_file(dir + "/scene.txt", scene);
    const RunResult run = run_guarded("scene.txt out.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output,
              "bad.obj:2:5: error: 'x' is not a number\n"
              "  v 1 x 0\n"
              "      ^\n"
              "scene.txt:25:18: note: the mesh was named here\n"
              "          obj_file bad.obj\n"
              "                   ^\n"
              "scene.txt:28:18: note: the same mesh is named here too\n"
              "          obj_file bad.obj\n"
              "                   ^\n");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"bad.obj", "scene.txt"}));
}

TEST(BadInputTest, AMeshWithNoFacesIsWarnedAboutAtTheTriangleMesh) {
    // Points only, or comments only: the mesh draws nothing, and the image is the background's.
    for (const char* obj : {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "# nothing here\n"}) {
        SCOPED_TRACE(obj);
        const std::string dir = fresh_dir("no_faces");
        const RunResult run = render_with_mesh(dir, "points.obj", obj);
        EXPECT_EQ(run.exit_code, 0);
        EXPECT_EQ(run.output,
                  "scene.txt:24:5: warning: the OBJ file 'points.obj' has no faces ('f' lines): this mesh draws nothing\n"
                  "      TriangleMesh {\n"
                  "      ^\n");
        const Ppm image = parse_ppm(read_file(dir + "/out.ppm"));
        ASSERT_TRUE(image.ok);
        EXPECT_EQ(pixels_other_than(image, 127, 127, 127), 0);  // background 0.5 -> 127
    }
}

TEST(BadInputTest, PseudoRandomBytesEndInALocatedErrorWithBoundedOutput) {
    const std::string dir = fresh_dir("random");
    std::string bytes;
    uint32_t state = 12345;
    for (int i = 0; i < 65536; ++i) {
        state = state * 1664525u + 1013904223u;  // Numerical Recipes' LCG
        bytes += static_cast<char>(state >> 24);
    }
    write_file(dir + "/random.txt", bytes);
    const RunResult run = run_guarded("random.txt out.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_TRUE(is_located_error(first_line(run.output), "random.txt")) << first_line(run.output);
    EXPECT_LT(run.output.size(), 20000u);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"random.txt"}));
}

TEST(BadInputTest, ADirectoryAsTheSceneIsAnInputError) {
    expect_input_error("tests/bad_inputs", "tests/bad_inputs: error: cannot open scene file: it is a directory");
}

TEST(BadInputTest, AMissingSceneFileIsAnInputError) {
    expect_input_error("no_such_scene.txt",
                       "tests/bad_inputs/no_such_scene.txt: error: cannot open scene file: No such file or directory");
}

// ---- truncated files --------------------------------------------------------------------------------

TEST(BadInputTest, ATruncatedFileIsReportedAtTheEndOfFileInEveryKindOfBlock) {
    // Every file ends with a line break, so the end of the file is at column 1 of the line after the last.
    expect_input_errors({
        {"truncated_camera_keyword.txt",
         ":2:1: error: expected '{' after 'PerspectiveCamera', got the end of the file"},
        {"truncated_camera.txt", ":4:1: error: expected a number for 'direction', got the end of the file"},
        {"truncated_lights.txt",
         ":13:1: error: unexpected end of file: 'DirectionalLight' opened at line 11 is not closed"},
        {"truncated_light_value.txt", ":14:1: error: expected a number for 'color', got the end of the file"},
        {"truncated_background.txt", ":11:1: error: expected a number for 'color', got the end of the file"},
        {"truncated_materials_list.txt",
         ":20:1: error: unexpected end of file: 'Materials' opened at line 17 is not closed"},
        {"truncated_materials.txt", ":20:1: error: unexpected end of file: 'Material' opened at line 19 is not closed"},
        {"truncated_group.txt", ":24:1: error: unexpected end of file: 'Group' opened at line 21 is not closed"},
        {"truncated_sphere.txt", ":27:1: error: expected a number for 'radius', got the end of the file"},
        {"truncated_plane.txt", ":26:1: error: unexpected end of file: 'Plane' opened at line 24 is not closed"},
        {"truncated_triangle.txt", ":28:1: error: expected a number for 'vertex2', got the end of the file"},
        {"truncated_triangle_mesh.txt", ":26:1: error: expected a file name for 'obj_file', got the end of the file"},
        {"truncated_transform.txt",
         ":27:1: error: unexpected end of file: 'Transform' opened at line 24 is not closed"},
        {"truncated_transform_item.txt", ":26:1: error: expected a number for 'Translate', got the end of the file"},
        {"truncated_rotate.txt", ":26:1: error: expected a number for 'Rotate', got the end of the file"},
        {"truncated_matrix.txt", ":26:1: error: expected a number for 'Matrix4f', got the end of the file"},
    });
}

// ---- numbers ----------------------------------------------------------------------------------------

TEST(BadInputTest, NumbersBeyondTheFloatRangeAreRejectedAtTheToken) {
    expect_input_errors({
        {"huge_number.txt", ":25:16: error: number '1e39' for 'center' is out of range (floats reach about 3.4e38)"},
    });
}

TEST(BadInputTest, NanAndInfinityAreNotNumbers) {
    expect_input_errors({
        {"nan_number.txt", ":26:16: error: expected a number for 'radius', got 'nan'"},
        {"inf_number.txt", ":25:16: error: expected a number for 'center', got 'inf'"},
        {"negative_inf_number.txt", ":13:17: error: expected a number for 'color', got '-inf'"},
    });
}

TEST(BadInputTest, ASphereRadiusMustBePositive) {
    expect_input_errors({
        {"sphere_negative_radius.txt", ":26:16: error: radius must be positive, got -1"},
        {"sphere_zero_radius.txt", ":26:16: error: radius must be positive, got 0"},
        // 1e-50 rounds to 0 as a float (strtof's rule), so it is a zero radius.
        {"sphere_radius_underflows.txt", ":26:16: error: radius must be positive, got 0"},
    });
}

TEST(BadInputTest, APlaneNormalMustNotBeZero) {
    expect_input_errors({{"plane_zero_normal.txt", ":25:9: error: the plane's 'normal' must not be the zero vector"}});
}

// A plane's points lie as far from the origin as the plane, and from past the coordinate limit
// their distance to a point light overflowed when squared (a floor at 1e19 came out black). A
// scaled plane n·p = d lies |d|/|n| away: Scale 1 1e10 1 takes offset -1e9 to 1e19.
TEST(BadInputTest, PlanesBeyondTheCoordinateLimitAreRejected) {
    expect_input_errors({
        {"plane_far.txt",
         ":24:5: error: this plane lies 2e+19 from the origin, beyond raycast's limit of 1e+18 (float arithmetic "
         "would overflow): scale the scene down"},
        {"plane_scaled_far.txt",
         ":26:9: error: this plane lies 1e+19 from the origin, beyond raycast's limit of 1e+18 (float arithmetic "
         "would overflow): scale the scene down"},
    });
}

TEST(BadInputTest, TheCameraNeedsADirectionAndAnUpThatIsNotParallelToIt) {
    expect_input_errors({
        {"camera_up_parallel.txt",
         ":4:5: error: the camera 'up' is parallel to 'direction': the image would have no up; "
         "choose an up vector that is not"},
        {"camera_zero_direction.txt", ":3:5: error: the camera 'direction' must not be the zero vector"},
    });
}

TEST(BadInputTest, TheCameraAngleMustBeBetween0And180Degrees) {
    expect_input_errors({
        {"camera_angle_0.txt", ":5:11: error: angle must be more than 0 and less than 180 degrees, got 0"},
        {"camera_angle_180.txt", ":5:11: error: angle must be more than 0 and less than 180 degrees, got 180"},
        {"camera_angle_200.txt", ":5:11: error: angle must be more than 0 and less than 180 degrees, got 200"},
        {"camera_angle_negative.txt", ":5:11: error: angle must be more than 0 and less than 180 degrees, got -30"},
    });
}

TEST(BadInputTest, TheImageSizeMustBePositiveAndWithinTheLimits) {
    // Limits from src/base/limits.h: 16384 a side, 2^26 = 67108864 pixels in all.
    expect_input_errors({
        {"camera_width_0.txt", ":6:11: error: width must be at least 1, got 0"},
        {"camera_height_negative.txt", ":7:12: error: height must be at least 1, got -3"},
        {"camera_width_past_limit.txt", ":6:11: error: width 16385 is more than raycast's limit of 16384"},
        {"camera_pixels_past_limit.txt",
         ":6:11: error: a 16384 x 16384 image has more pixels than raycast's limit of 67108864 (8192 x 8192)"},
        {"camera_width_absurd.txt", ":6:11: error: number '99999999999' for 'width' is out of range"},
        {"camera_width_no_height.txt", ":7:1: error: the camera has a width but no height"},
    });
}

// Regression (fixed): read_int accepts values up to 2^31 inclusive and the camera stores the result in an int, so
// 2147483648 wraps to -2147483648 and the message blames a number the file does not contain.
TEST(BadInputTest, AWidthOf2147483648IsReportedAsWritten) {
    const Rendered r = render("camera_width_2147483648.txt");
    EXPECT_EQ(r.run.exit_code, 1);
    const std::string line = first_line(r.run.output);
    EXPECT_EQ(line.rfind("tests/bad_inputs/camera_width_2147483648.txt:6:11: error: ", 0), 0u) << line;
    EXPECT_NE(line.find("2147483648"), std::string::npos) << line;
    EXPECT_EQ(line.find("-2147483648"), std::string::npos) << line;
    EXPECT_TRUE(files_in(r.out_dir).empty());
}

TEST(BadInputTest, ACommandLineSizePastThePixelLimitIsAUsageError) {
    const std::pair<const char*, const char*> cases[] = {
        {"--size 16384x16384",
         "raycast: usage error: --size 16384x16384 has 268435456 pixels, more than raycast's limit of 67108864 "
         "(8192x8192)"},
        {"--size 8193x8192",
         "raycast: usage error: --size 8193x8192 has 67117056 pixels, more than raycast's limit of 67108864 "
         "(8192x8192)"},
    };
    for (const auto& [size, message] : cases) {
        SCOPED_TRACE(size);
        const Rendered r = render("valid.txt", size);
        EXPECT_EQ(r.run.exit_code, 2);
        EXPECT_EQ(first_line(r.run.output), message);
        EXPECT_TRUE(files_in(r.out_dir).empty());
    }
    const std::string dir = fresh_dir("mit_size");
    const RunResult run =
        run_guarded(std::string("-input ") + kDir + "valid.txt -size 16384 16384 -output '" + dir + "/out.ppm'");
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(first_line(run.output),
              "raycast: usage error: -size 16384x16384 has 268435456 pixels, more than raycast's limit of 67108864 "
              "(8192x8192)");
    EXPECT_TRUE(files_in(dir).empty());
}

// ---- counts and indices -----------------------------------------------------------------------------

TEST(BadInputTest, CountsThatDoNotMatchAreReported) {
    expect_input_errors({
        {"count_objects_too_many.txt", ":28:1: error: numObjects is 2 but the group has 1 object"},
        {"count_objects_too_few.txt", ":24:5: error: numObjects is 0 but more objects follow"},
        {"count_objects_negative.txt", ":22:16: error: numObjects must not be negative, got -1"},
        {"count_materials.txt", ":20:1: error: numMaterials is 2 but 1 material is given"},
        {"count_lights.txt", ":15:1: error: numLights is 3 but 1 light is given"},
    });
}

TEST(BadInputTest, AMaterialIndexOutOfRangeIsReportedAtTheIndex) {
    expect_input_errors({
        {"material_index_out_of_range.txt",
         ":23:19: error: material index 1 is out of range: the scene has 1 material (index 0)"},
        {"material_index_negative.txt",
         ":23:19: error: material index -1 is out of range: the scene has 1 material (index 0)"},
        {"material_index_without_materials.txt",
         ":19:19: error: material index 0 is out of range: no materials are defined before this point (Materials must "
         "come before the Group)"},
    });
}

// ---- nesting ----------------------------------------------------------------------------------------

// Writes a scene whose Group (or Transform) nesting is `levels` deep, opening one level per line
// from line 3 on.
std::string nested_scene(int levels, bool transforms) {
    std::string text =
        "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 8 height 8 }\n"
        "Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }\n";
    if (transforms) {
        text += "Group { numObjects 1 MaterialIndex 0\n";
        for (int i = 1; i < levels; ++i) text += "Transform { Translate 0 0 0\n";
        text += "Sphere { center 0 0 0 radius 1 }\n";
    } else {
        for (int i = 0; i < levels; ++i) text += "Group { numObjects 1\n";
        text += "MaterialIndex 0 Sphere { center 0 0 0 radius 1 }\n";
    }
    for (int i = 0; i < levels; ++i) text += "}\n";
    return text;
}

TEST(BadInputTest, AHundredThousandNestedGroupsStopAtTheNestingLimit) {
    // Level 1001 (the first too deep) opens on line 2 + 1001 = 1003.
    for (const bool transforms : {false, true}) {
        SCOPED_TRACE(transforms ? "transforms" : "groups");
        const std::string dir = fresh_dir(transforms ? "transforms" : "groups");
        write_file(dir + "/nested.txt", nested_scene(100000, transforms));
        const RunResult run = run_guarded("nested.txt out.ppm", dir);
        EXPECT_EQ(run.exit_code, 1);
        EXPECT_EQ(run.output, std::string("nested.txt:1003:1: error: groups and transforms are nested more than 1000 "
                                          "levels deep\n  ") +
                                  (transforms ? "Transform { Translate 0 0 0" : "Group { numObjects 1") + "\n  ^\n");
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"nested.txt"}));
    }
}

TEST(BadInputTest, NestingExactlyAtTheLimitRendersTheSameAsNoNesting) {
    const std::string dir = fresh_dir("nested_1000");
    write_file(dir + "/deep.txt", nested_scene(1000, false));
    write_file(dir + "/flat.txt", nested_scene(1, false));
    const RunResult deep = run_guarded("deep.txt deep.ppm -q", dir);
    ASSERT_EQ(deep.exit_code, 0) << deep.output;
    ASSERT_EQ(run_guarded("flat.txt flat.ppm -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/deep.ppm"), read_file(dir + "/flat.ppm"));
}

// The parser recurses once per level, and a sanitizer build needs about 10 KiB of stack per level
// (a Release build about 1.7 KiB): the 1000-level limit does not fit in a default 8 MiB stack, and
// 800 nested groups used to die with "AddressSanitizer: stack-overflow". The parser and the scene
// builder now run on a thread with a large stack of their own. To check that without a sanitizer
// build, the Release binary gets 1 MiB, an eighth of the default stack.
TEST(BadInputTest, TheNestingLimitFitsInTheStackOfASanitizerBuild) {
    const std::string dir = fresh_dir("small_stack");
    write_file(dir + "/deep.txt", nested_scene(1000, false));
    write_file(dir + "/too_deep.txt", nested_scene(100000, false));
    const RunResult deep = run_guarded("deep.txt deep.ppm -q", dir, "ulimit -s 1024 && ");
    EXPECT_EQ(deep.exit_code, 0) << deep.output;
    const RunResult too_deep = run_guarded("too_deep.txt too_deep.ppm -q", dir, "ulimit -s 1024 && ");
    EXPECT_EQ(too_deep.exit_code, 1);
    EXPECT_EQ(first_line(too_deep.output),
              "too_deep.txt:1003:1: error: groups and transforms are nested more than 1000 levels deep");
    EXPECT_FALSE(file_exists(dir + "/too_deep.ppm"));
}

// ---- transforms -------------------------------------------------------------------------------------

TEST(BadInputTest, SingularTransformsAreRejected) {
    expect_input_errors({
        {"transform_scale_zero.txt",
         ":25:15: error: a Scale factor of 0 squashes the object flat: the transform could not be inverted"},
        {"transform_singular_matrix.txt",
         ":25:20: error: 'Matrix4f' is singular (its determinant is 0): it cannot be inverted"},
        // A zero x scale behind a projective last row (column by column: the last row is 1 0 0 0),
        // which had rendered: the row was dropped one way and used the other.
        {"transform_projective_matrix.txt",
         ":25:20: error: the last row of 'Matrix4f' is 1 0 0 0, not 0 0 0 1: raycast's transforms are affine (a "
         "projective matrix would bend rays into curves)"},
    });
}

// Each Scale 1e-10 is within the limit of 1e-18 to 1e18; their product is not: the error names the
// inner Transform, where the product is formed. (Two Scale 1e-20, whose product's inverse is past
// float, had been refused as singular there; each is past the limit now.)
TEST(BadInputTest, TransformsScalingPastTheLimitTogetherAreRejected) {
    expect_input_errors({
        {"transform_tiny_scale_product.txt",
         ":26:9: error: this transform (with those around it) scales by 1e-20, below raycast's limit of 1e-18 (float "
         "arithmetic would overflow): give the objects in it smaller coordinates and it a larger scale"},
    });
}

TEST(BadInputTest, ErrorsFoundWhileBuildingTheSceneShowTheLineAndCaret) {
    // Found after parsing, by build_scene, and shown as the parser shows its own errors: a product
    // of transforms that scales past the limit, and the extent limit (1e18, base/limits.h) for a
    // triangle with corners at 1e20, the camera and a point light.
    const std::pair<const char*, const char*> cases[] = {
        {"transform_tiny_scale_product.txt",
         "tests/bad_inputs/transform_tiny_scale_product.txt:26:9: error: this transform (with those around it) "
         "scales by 1e-20, below raycast's limit of 1e-18 (float arithmetic would overflow): give the objects in it "
         "smaller coordinates and it a larger scale\n"
         "          Transform {\n"
         "          ^\n"},
        // The camera too: rays from 1e30 overflow the same products.
        {"camera_center_huge.txt",
         "tests/bad_inputs/camera_center_huge.txt:1:1: error: the camera is at coordinates of 1e+30, beyond raycast's "
         "limit of 1e+18 (float arithmetic would overflow): scale the scene down\n"
         "  PerspectiveCamera {\n"
         "  ^\n"},
        {"huge_triangle.txt",
         "tests/bad_inputs/huge_triangle.txt:17:5: error: this object reaches coordinates of 1e+20, beyond raycast's "
         "limit of 1e+18 (float arithmetic would overflow): scale the scene down\n"
         "      Triangle {\n"
         "      ^\n"},
        // An object under a Transform is tested in its own space: past the limit there it vanished,
        // though the Transform brought it to a radius of 1 in the world.
        {"sphere_scaled_down_from_huge.txt",
         "tests/bad_inputs/sphere_scaled_down_from_huge.txt:19:9: error: this object reaches coordinates of 1e+20 in "
         "its own space (before its Transform), beyond raycast's limit of 1e+18 (float arithmetic would overflow): "
         "give it smaller coordinates and its Transform a larger scale\n"
         "          Sphere {\n"
         "          ^\n"},
        // And a point light: its distance to a hit, squared, overflowed, and it lit nothing.
        {"point_light_huge.txt",
         "tests/bad_inputs/point_light_huge.txt:11:5: error: this point light is at coordinates of 2e+19, beyond "
         "raycast's limit of 1e+18 (float arithmetic would overflow): scale the scene down\n"
         "      PointLight {\n"
         "      ^\n"},
    };
    for (const auto& [name, output] : cases) {
        SCOPED_TRACE(name);
        const Rendered r = render(name);
        EXPECT_EQ(r.run.exit_code, 1);
        EXPECT_EQ(r.run.output, output);
        EXPECT_TRUE(files_in(r.out_dir).empty());
    }
}

// ---- degenerate geometry ----------------------------------------------------------------------------

TEST(BadInputTest, DegenerateTrianglesAreWarnedAboutAndNeverSeen) {
    // A point-like and a segment-like triangle in front of the sphere of valid.txt: a warning at each,
    // and the image of valid.txt exactly (no pixel covered, no NaN turned into black).
    const Rendered base = render("valid.txt");
    ASSERT_EQ(base.run.exit_code, 0);
    const Rendered r = render("degenerate_triangles.txt");
    EXPECT_EQ(r.run.exit_code, 0);
    const std::vector<std::string> lines = lines_of(r.run.output);
    ASSERT_EQ(lines.size(), 6u) << r.run.output;
    EXPECT_EQ(lines[0],
              "tests/bad_inputs/degenerate_triangles.txt:28:5: warning: degenerate triangle: its vertices are on one "
              "line, so it is never seen");
    EXPECT_EQ(lines[3],
              "tests/bad_inputs/degenerate_triangles.txt:29:5: warning: degenerate triangle: its vertices are on one "
              "line, so it is never seen");
    EXPECT_EQ(read_file(r.image()), read_file(base.image()));

    // Nor do they cast shadows.
    const Rendered base_shadows = render("valid.txt", "--shadows");
    const Rendered shadows = render("degenerate_triangles.txt", "--shadows -q");
    ASSERT_EQ(shadows.run.exit_code, 0);
    EXPECT_EQ(read_file(shadows.image()), read_file(base_shadows.image()));
}

TEST(BadInputTest, DegenerateTrianglesAloneLeaveTheBackground) {
    // Background 0.5 -> to_byte truncates 127.5 to 127 in every channel of every pixel.
    for (const char* name : {"degenerate_triangles_alone.txt", "obj_degenerate.txt"}) {
        SCOPED_TRACE(name);
        const Rendered r = render(name, "-q");
        ASSERT_EQ(r.run.exit_code, 0) << r.run.output;
        const Ppm image = parse_ppm(read_file(r.image()));
        ASSERT_TRUE(image.ok);
        EXPECT_EQ(pixels_other_than(image, 127, 127, 127), 0);
    }
}

// ---- OBJ files --------------------------------------------------------------------------------------

TEST(BadInputTest, ObjIndicesOutOfRangeAreLocatedInTheObjFile) {
    const Case cases[] = {
        {"obj_index_out_of_range", ".obj:4:7: error: vertex index 4 is out of range: the file has 3 vertices"},
        {"obj_index_zero", ".obj:4:5: error: index 0 is invalid: OBJ indices start at 1"},
        {"obj_index_negative_out_of_range",
         ".obj:4:9: error: vertex index -4 is out of range: 3 vertices are defined before this line"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        const Rendered r = render(std::string(c.file) + ".txt");
        EXPECT_EQ(r.run.exit_code, 1);
        const std::vector<std::string> lines = lines_of(r.run.output);
        ASSERT_EQ(lines.size(), 6u) << r.run.output;
        EXPECT_EQ(lines[0], std::string(kDir) + c.file + c.message);
        // Then the face line with a caret, and a note at the scene's obj_file token.
        EXPECT_EQ(lines[3], std::string(kDir) + c.file + ".txt:25:18: note: the mesh was named here");
        EXPECT_TRUE(files_in(r.out_dir).empty());
    }
}

TEST(BadInputTest, AMissingObjFileIsLocatedAtItsNameInTheScene) {
    expect_input_errors({
        {"obj_missing.txt",
         ":25:18: error: cannot open OBJ file 'no_such_mesh.obj': tried 'no_such_mesh.obj' (from the working "
         "directory), 'tests/bad_inputs/no_such_mesh.obj' (next to the scene file) and "
         "'tests/bad_inputs/../no_such_mesh.obj' (from the scene file's parent folder)"},
    });
}

// ---- output paths -----------------------------------------------------------------------------------

TEST(BadInputTest, AnUnwritableOutputPathIsAnOutputError) {
    const RunResult run = run_guarded(std::string(kDir) + "valid.txt /nonexistent/dir/x.bmp");
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output,
              "/nonexistent/dir/x.bmp: error: cannot write image: the folder '/nonexistent/dir' does not exist\n");
    EXPECT_FALSE(file_exists("/nonexistent/dir/x.bmp"));

    const std::string dir = fresh_dir("output_is_dir");
    ASSERT_EQ(std::system(("mkdir '" + dir + "/x.bmp'").c_str()), 0);
    const RunResult into_dir = run_guarded(std::string(kDir) + "valid.txt '" + dir + "/x.bmp'");
    EXPECT_EQ(into_dir.exit_code, 1);
    EXPECT_EQ(into_dir.output, dir + "/x.bmp: error: cannot write image: it is a directory\n");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"x.bmp"}));
    EXPECT_TRUE(files_in(dir + "/x.bmp").empty());
}

TEST(BadInputTest, AnOutputPathEqualToTheSceneIsRefusedAndTheSceneIsUntouched) {
    // The scene is named like an image, so the extension check passes and only the identity check is left.
    const std::string dir = fresh_dir("output_is_scene");
    const std::string scene = read_file(source_dir() + "/" + kDir + "valid.txt");
    ASSERT_FALSE(scene.empty());
    write_file(dir + "/scene.ppm", scene);
    const std::pair<const char*, const char*> cases[] = {
        {"scene.ppm scene.ppm", "scene.ppm"},
        {"scene.ppm ./scene.ppm", "./scene.ppm"},  // the same file by another name
        {"-input scene.ppm -size 8 8 -output scene.ppm", "scene.ppm"},
    };
    for (const auto& [arguments, shown] : cases) {
        SCOPED_TRACE(arguments);
        const RunResult run = run_guarded(arguments, dir);
        EXPECT_EQ(run.exit_code, 2);
        EXPECT_EQ(first_line(run.output), std::string("raycast: usage error: the output '") + shown +
                                              "' is the scene file itself: choose another name");
        EXPECT_EQ(read_file(dir + "/scene.ppm"), scene);
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"scene.ppm"}));
    }
}

TEST(BadInputTest, AnUnknownOutputExtensionIsAUsageError) {
    const std::string dir = fresh_dir("unknown_extension");
    const RunResult run = run_guarded(std::string(kDir) + "valid.txt '" + dir + "/x.gif'");
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(first_line(run.output), "raycast: usage error: unknown image format '.gif' for '" + dir +
                                          "/x.gif': use .bmp, .ppm, .tga or .png, or give --format");
    EXPECT_TRUE(files_in(dir).empty());
}

// ---- legal but extreme numbers: a located error or a correct image --------------------------------

// The *_huge/_tiny scenes light with ambient 1 and no lights, so a hit pixel is exactly the diffuse
// colour (0.4, 0.6, 0.8) -> (102, 153, 204) after truncation.

// Regression (fixed): a sphere 2e20 away with radius 1e20 fills a 60-degree cone, wider than the whole image (the
// corner rays are 21 degrees off axis), but the float quadratic overflows (2e20 squared > 3.4e38)
// and only the centre ray hits: a wrong image with exit 0. Sizes up to 2e19 render correctly.
TEST(BadInputTest, AHugeFarSphereRendersCorrectlyOrIsRejected) {
    expect_located_error_or_correct_image(
        "huge_far_sphere.txt", [](const Ppm& image) { EXPECT_EQ(pixels_other_than(image, 102, 153, 204), 0); });
}

// Regression (fixed): a triangle with vertices at +-1e20 that contains the whole view renders as background only:
// the intersection overflows (1e20 squared) and every ray misses. Vertices at +-3e18 work.
TEST(BadInputTest, AHugeTriangleRendersCorrectlyOrIsRejected) {
    expect_located_error_or_correct_image(
        "huge_triangle.txt", [](const Ppm& image) { EXPECT_EQ(pixels_other_than(image, 102, 153, 204), 0); });
}

std::string valid_image() {
    const Rendered base = render("valid.txt");
    return read_file(base.image());
}

// Regression (fixed): direction 0 0 -1e38 is perpendicular to up 0 1 0, but normalising it overflows and the
// parser reports "the camera 'up' is parallel to 'direction'", which is false.
TEST(BadInputTest, AHugeCameraDirectionIsNotCalledParallelToUp) {
    const std::string expected = valid_image();
    expect_located_error_or_correct_image(
        "camera_direction_huge.txt", [&](const Ppm& image) { EXPECT_EQ(image.rgb, parse_ppm(expected).rgb); },
        "parallel");
}

// Regression (fixed): direction 0 0 -1e-30 is not the zero vector, but its squared length underflows and the parser
// reports "the camera 'direction' must not be the zero vector", which is false.
TEST(BadInputTest, ATinyCameraDirectionIsNotCalledZero) {
    const std::string expected = valid_image();
    expect_located_error_or_correct_image(
        "camera_direction_tiny.txt", [&](const Ppm& image) { EXPECT_EQ(image.rgb, parse_ppm(expected).rgb); },
        "zero vector");
}

// Regression (fixed): a directional light with direction 0 0 -1e38 is the light of valid.txt (direction 0 0 -1),
// but normalising it overflows, N.L is NaN, and the lit sphere comes out black with exit 0.
TEST(BadInputTest, AHugeLightDirectionStillLightsTheScene) {
    const std::string expected = valid_image();
    expect_located_error_or_correct_image("light_direction_huge.txt",
                                          [&](const Ppm& image) { EXPECT_EQ(image.rgb, parse_ppm(expected).rgb); });
}

}  // namespace
}  // namespace raycast::test
