// End-to-end tests of the raycast command line, run as a separate process: help and version, usage
// errors (exit 2 and a message), the course's and MIT 6.837's forms, the image format chosen by the
// output's extension or by --format, --stats, --quiet, thread-count independence, the `compare`
// tool, and the promise that a failed run never leaves or damages an output file. The expectations
// come from --help, README.md and docs/limits.md (exit 0 success, 1 input or output error, 2 usage
// error).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scene_builders.h"
#include "sceneio/write_obj.h"
#include "test_support.h"

namespace raycast::test {
namespace {

// A sphere in front of a floor plane, a quad mesh (two triangles) and a point light: every kind of
// primitive, so that thread and packet differences would show.
const char* const kScene = R"(PerspectiveCamera {
    center 0 0 10
    direction 0 0 -1
    up 0 1 0
    angle 30
    width 32
    height 24
}
Lights {
    numLights 1
    PointLight { position 2 5 5 color 0.9 0.9 0.9 }
}
Background { color 0.1 0.2 0.3 }
Materials {
    numMaterials 2
    Material { diffuseColor 1 0 0 specularColor 1 1 1 shininess 20 }
    Material { diffuseColor 0 1 0 }
}
Group {
    numObjects 3
    MaterialIndex 0
    Sphere { center 0 0 0 radius 1 }
    MaterialIndex 1
    Plane { normal 0 1 0 offset -1 }
    TriangleMesh { obj_file quad.obj }
}
)";

// One quadrilateral face: a polygon is cut into a fan, so the mesh has 2 triangles.
const char* const kQuadObj = "v -2 -1 -2\nv 2 -1 -2\nv 2 2 -2\nv -2 2 -2\nf 1 2 3 4\n";

// A scene with no lights and no ambient light: raycast warns that everything will be black.
const char* const kDarkScene =
    R"(PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 8 height 8 }
Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }
Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }
)";

// A temp folder holding kScene as s.txt and its mesh.
std::string scene_dir(const std::string& name) {
    const std::string dir = temp_dir("cli/" + name);
    write_file(dir + "/s.txt", kScene);
    write_file(dir + "/quad.obj", kQuadObj);
    return dir;
}

std::string make_ppm(int width, int height, const std::vector<uint8_t>& rgb) {
    std::string bytes = "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
    bytes.append(rgb.begin(), rgb.end());
    return bytes;
}

uint32_t le32(const std::string& bytes, size_t at) {
    uint32_t v = 0;
    for (size_t i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + i])) << (8 * i);
    return v;
}

uint32_t le16(const std::string& bytes, size_t at) {
    return static_cast<uint32_t>(static_cast<uint8_t>(bytes[at])) |
           static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + 1])) << 8;
}

// The fields of a --stats line ("raycast-stats key=value ..."), by key.
std::map<std::string, std::string> stats_fields(const std::string& line) {
    std::map<std::string, std::string> fields;
    std::istringstream in(line.substr(std::string("raycast-stats ").size()));
    for (std::string field; in >> field;) {
        const size_t eq = field.find('=');
        if (eq != std::string::npos) fields[field.substr(0, eq)] = field.substr(eq + 1);
    }
    return fields;
}

// ---- help, version, usage errors -------------------------------------------------------------

TEST(CliTest, HelpPrintsTheUsageAndExitsZero) {
    for (const char* flag : {"--help", "-h"}) {
        SCOPED_TRACE(flag);
        const RunResult run = run_raycast(flag);
        EXPECT_EQ(run.exit_code, 0);
        EXPECT_EQ(first_line(run.output), "usage: raycast [options] SCENE OUTPUT");
        EXPECT_NE(run.output.find("Exit status: 0 success, 1 input or output error, 2 usage error."),
                  std::string::npos);
        EXPECT_NE(run.output.find("--stats"), std::string::npos);
    }
}

TEST(CliTest, VersionPrintsOneLineAndExitsZero) {
    const RunResult run = run_raycast("--version");
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output.rfind("raycast ", 0), 0u) << run.output;
    EXPECT_EQ(lines_of(run.output).size(), 1u) << run.output;
}

TEST(CliTest, UsageErrorsExitTwoWithAMessageAndAHint) {
    const std::string dir = scene_dir("usage_errors");
    const std::pair<const char*, const char*> cases[] = {
        {"", "missing SCENE and OUTPUT"},
        {"s.txt", "missing OUTPUT (the image to write)"},
        {"s.txt o.ppm extra.ppm", "unexpected argument 'extra.ppm'"},
        {"--bogus s.txt o.ppm", "unknown option '--bogus'"},
        {"s.txt o.ppm --threads", "--threads needs a value"},
        {"s.txt o.ppm --size", "--size needs a value"},
        {"--threads 0 s.txt o.ppm", "--threads must be at least 1, got 0"},
        {"--threads abc s.txt o.ppm", "--threads needs a whole number, got 'abc'"},
        {"-j -2 s.txt o.ppm", "-j must be at least 1, got -2"},
        {"--size 0x0 s.txt o.ppm", "--size width must be at least 1, got 0"},
        {"--size 10 s.txt o.ppm", "--size needs WIDTHxHEIGHT, e.g. 640x480, got '10'"},
        {"--size 10x s.txt o.ppm", "--size height needs a whole number, got ''"},
        {"--size 16385x10 s.txt o.ppm", "--size width must be at most 16384, got 16385"},
        {"--mode fancy s.txt o.ppm", "--mode must be shaded, normals, depth, material, cost or ao, got 'fancy'"},
        {"--mode ao --ao-samples 0 s.txt o.ppm", "--ao-samples must be at least 1, got 0"},
        {"--mode ao --ao-distance -1 s.txt o.ppm", "--ao-distance must be a positive number, got -1"},
        {"--bounces -1 s.txt o.ppm", "--bounces must not be negative, got -1"},
        {"--bounces 1001 s.txt o.ppm", "--bounces must be at most 1000, got 1001"},
        {"--bounces two s.txt o.ppm", "--bounces needs a whole number, got 'two'"},
        {"-input s.txt -size 8 8 -output o.ppm -bounces -3", "-bounces must not be negative, got -3"},
        {"--weight 1.5 s.txt o.ppm", "--weight must be from 0 to 1, got 1.5"},
        {"--weight -0.1 s.txt o.ppm", "--weight must be from 0 to 1, got -0.1"},
        {"--weight nan s.txt o.ppm", "--weight needs a number, got 'nan'"},
        // An unset shell variable ("$OUT") gives an empty argument: the render wrote nothing.
        {"s.txt ''", "OUTPUT is an empty name: name the image to write"},
        {"'' o.ppm", "SCENE is an empty name"},
        {"s.txt o.ppm --depth ''", "--depth needs a file name, got an empty one"},
        {"-input s.txt -size 8 8 -output ''", "-output needs a file name, got an empty one"},
        // One file for two outputs: the last written won, in silence.
        {"s.txt o.ppm --depth ./o.ppm", "the image and --depth are both './o.ppm': give each its own name"},
        {"s.txt o.ppm --depth d.ppm --normals d.ppm", "--depth and --normals are both 'd.ppm': give each its own name"},
        {"-input s.txt -size 8 8 -output o.ppm -depth 1 2 d.ppm -normals o.ppm",
         "the image and -normals are both 'o.ppm': give each its own name"},
        {"-input s.txt -size 8 8 -output o.ppm -depth 9 9 d.ppm", "-depth needs NEAR < FAR, got 9 9"},
        {"s.txt o.ppm --aperture 1e30", "--aperture must be at most 1e+18, raycast's coordinate limit, got 1e+30"},
        {"s.txt o.ppm --aperture 1 --focus-distance 1e20",
         "--focus-distance must be at most 1e+18, raycast's coordinate limit, got 1e+20"},
        {"-jx s.txt o.ppm", "-j needs a whole number, got 'x'"},
        {"--threads= s.txt o.ppm", "--threads needs a whole number, got ''"},
        {"--stats=1 s.txt o.ppm", "--stats takes no value, got '1'"},
        {"s.txt o.ppm --quiet=yes", "--quiet takes no value, got 'yes'"},
        {"--bogus=3 s.txt o.ppm", "unknown option '--bogus'"},
        {"-input s.txt -size 8 8 -output o.ppm -weight 2", "-weight must be from 0 to 1, got 2"},
        {"s.txt o --format jpg", "--format must be bmp, ppm, tga or png, got 'jpg'"},
        {"s.txt o --format=.ppm", "--format must be bmp, ppm, tga or png, got '.ppm'"},
        {"s.txt o --format ''", "--format must be bmp, ppm, tga or png, got ''"},
        {"s.txt o --format", "--format needs a value"},
        // MIT's form has no --format: -output's name gives the format, as MIT's program reads it.
        {"-input s.txt -size 8 8 -output o --format ppm",
         "--format is for raycast SCENE OUTPUT: with -input, -output FILE takes its format from its name (.bmp, "
         ".ppm, .tga or .png)"},
        // explain and view write no image.
        {"explain s.txt 1 1 --format ppm", "unknown option '--format'"},
    };
    for (const auto& [arguments, message] : cases) {
        SCOPED_TRACE(arguments);
        const RunResult run = run_raycast(arguments, dir);
        EXPECT_EQ(run.exit_code, 2);
        const std::vector<std::string> lines = lines_of(run.output);
        ASSERT_EQ(lines.size(), 2u) << run.output;
        EXPECT_EQ(lines[0], std::string("raycast: usage error: ") + message);
        EXPECT_EQ(lines[1], "Try 'raycast --help' for more information.");
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj"}));
    }
}

// ---- MIT 6.837's form ------------------------------------------------------------------------

// A name the folder cannot hold is refused before the render, not after it by the final rename.
TEST(CliTest, AnOutputNameTooLongForItsFolderIsRefusedBeforeTheRender) {
    const std::string dir = scene_dir("long_name");
    const std::string name = std::string(300, 'a') + ".ppm";
    const RunResult run = run_raycast("s.txt " + name, dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(first_line(run.output),
              name + ": error: cannot write image: its name is 304 bytes long, and the folder takes at most 255");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj"}));
}

// An output that is a symbolic link is written through: the image lands where the link leads,
// and the link stays. A link into a folder that does not exist is refused before the render,
// naming that folder.
TEST(CliTest, AnOutputLinkIsWrittenThroughAndItsFolderCheckedFirst) {
    const std::string dir = scene_dir("output_link");
    ASSERT_EQ(run_command("mkdir '" + dir + "/images' && ln -s images/latest.ppm '" + dir + "/o.ppm' && ln -s "
                          "missing/x.ppm '" + dir + "/broken.ppm'").exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt o.ppm -q", dir).exit_code, 0);
    EXPECT_TRUE(parse_ppm(read_file(dir + "/images/latest.ppm")).ok);
    EXPECT_EQ(run_command("test -L '" + dir + "/o.ppm'").exit_code, 0) << "the link was replaced by a file";
    const RunResult broken = run_raycast("s.txt broken.ppm", dir);
    EXPECT_EQ(broken.exit_code, 1);
    EXPECT_EQ(first_line(broken.output), "broken.ppm: error: cannot write image: the folder 'missing' does not exist");
    // Two names of one file, one of them through a link, the file there or not yet: the last
    // image written had replaced the first in silence.
    ASSERT_EQ(run_command("cd '" + dir + "' && ln -s d.ppm later.ppm").exit_code, 0);
    for (const char* arguments : {"s.txt images/latest.ppm --depth o.ppm", "s.txt d.ppm --normals later.ppm"}) {
        const RunResult twice = run_raycast(arguments, dir);
        EXPECT_EQ(twice.exit_code, 2) << arguments;
        EXPECT_NE(twice.output.find("give each its own name"), std::string::npos) << twice.output;
    }
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj", "images", "o.ppm", "broken.ppm", "later.ppm"}));
}

// Another user's link in a sticky folder such as /tmp is not followed, as the kernel's
// fs.protected_symlinks follows none: anyone could have pointed it at the user's own files.
TEST(CliTest, AnotherUsersLinkInAStickyFolderIsRefusedBeforeTheRender) {
    if (::geteuid() != 0) GTEST_SKIP() << "needs root to make a link that belongs to another user";
    const std::string dir = scene_dir("sticky_link");
    write_file(dir + "/notes.txt", "precious\n");
    ASSERT_EQ(run_command("chmod 1777 '" + dir + "' && ln -s notes.txt '" + dir + "/out.ppm' && chown -h 65534 '" +
                          dir + "/out.ppm'").exit_code, 0);
    const RunResult run = run_raycast("s.txt out.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(first_line(run.output),
              "out.ppm: error: cannot write image: it is another user's link in a sticky folder (as /tmp is), which is "
              "not followed, as the system follows none: choose another name");
    EXPECT_EQ(read_file(dir + "/notes.txt"), "precious\n");
}

// A system that starts no more threads (ulimit -u reached) gets the render done on the threads
// there are, with the same image: the helpers' pool and the deep-scene stack thread both fall back
// (base/parallel.cpp). The limit binds only a user other than root, so the test runs raycast as
// `nobody` with at most one task, itself, and is skipped where it cannot (not root, no setpriv).
TEST(CliTest, ARenderWhoseThreadsCannotStartRunsOnTheOnesThereAre) {
    if (::geteuid() != 0 || run_command("command -v setpriv && command -v prlimit").exit_code != 0)
        GTEST_SKIP() << "needs root, setpriv and prlimit to run raycast as another user under a process limit";
    const std::string dir = scene_dir("no_threads");
    // Nested past the 64 levels that run on the caller's stack: the parser and builder ask for a
    // thread with a big stack, and do without it.
    std::string deep = "PerspectiveCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 angle 30 width 32 height 24 }\n"
                       "Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }\n"
                       "Materials { numMaterials 1 Material { diffuseColor 1 0 0 } }\n";
    for (int level = 0; level < 80; ++level) deep += "Group { numObjects 1 MaterialIndex 0\n";
    deep += "Sphere { center 0 0 0 radius 1 }\n";
    for (int level = 0; level < 80; ++level) deep += "}\n";
    write_file(dir + "/deep.txt", deep);
    ASSERT_EQ(run_command("chmod 777 '" + dir + "' && cp '" RAYCAST_EXECUTABLE "' '" + dir + "/raycast' && chmod 755 '" +
                          dir + "/raycast'").exit_code, 0);
    // In a sanitizer build, LeakSanitizer's check at exit needs a thread of its own: off here.
    const std::string as_nobody = "cd '" + dir + "' && ASAN_OPTIONS=\"${ASAN_OPTIONS}:detect_leaks=0\" prlimit " +
                                  "--nproc=1:1 setpriv --reuid=65534 --regid=65534 --clear-groups ";
    // The limit holds: nobody's shell cannot start a second process.
    EXPECT_NE(run_command(as_nobody + "sh -c 'true & wait' 2>&1").exit_code, 0);
    for (const char* scene : {"s.txt", "deep.txt"}) {
        SCOPED_TRACE(scene);
        const RunResult limited = run_command(as_nobody + "./raycast " + scene + " limited.ppm -j 4 -q 2>&1");
        ASSERT_EQ(limited.exit_code, 0) << limited.output;
        ASSERT_EQ(run_raycast(std::string(scene) + " free.ppm -j 4 -q", dir).exit_code, 0);
        EXPECT_EQ(read_file(dir + "/limited.ppm"), read_file(dir + "/free.ppm"));
    }
}

// The thin lens focuses by default on what the image's centre sees; a plane seen at a grazing
// angle, farther than the coordinate limit, made every lens ray's direction zero (its distance,
// squared, overflowed) and the image all background, with exit 0.
TEST(CliTest, AThinLensFocusedFarBeyondTheCoordinateLimitStillSeesTheScene) {
    const std::string dir = temp_dir("cli/far_focus");
    write_file(dir + "/far.txt",
               "PerspectiveCamera { center 0 0 0 direction 0 -0.02 -1 up 0 1 0 angle 40 width 64 height 48 }\n"
               "Lights { numLights 1 DirectionalLight { direction -0.3 -1 -0.5 color 0.8 0.8 0.8 } }\n"
               "Materials { numMaterials 1 Material { diffuseColor 0.7 0.6 0.5 } }\n"
               "Group { numObjects 2 MaterialIndex 0 Plane { normal 0 1 0 offset -5e17 }\n"
               "  Sphere { center 0 -3 -10 radius 2 } }\n");
    const RunResult pinhole = run_raycast("far.txt pinhole.ppm --stats -q", dir);
    const RunResult lens = run_raycast("far.txt lens.ppm --aperture 0.1 --stats -q", dir);
    ASSERT_EQ(lens.exit_code, 0) << lens.output;
    const double pinhole_hits = std::stod(stats_fields(pinhole.output).at("hit_fraction"));
    EXPECT_GT(pinhole_hits, 0.4);
    EXPECT_NEAR(std::stod(stats_fields(lens.output).at("hit_fraction")), pinhole_hits, 0.02) << lens.output;
    // An orthographic camera has no lens: --aperture changes nothing, and says so.
    write_file(dir + "/ortho.txt",
               "OrthographicCamera { center 0 0 10 direction 0 0 -1 up 0 1 0 size 5 }\n"
               "Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }\n"
               "Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }\n"
               "Group { numObjects 1 MaterialIndex 0 Sphere { center 0 0 0 radius 1 } }\n");
    const RunResult ortho = run_raycast("ortho.txt lens.ppm --size 16x16 --aperture 0.5", dir);
    ASSERT_EQ(ortho.exit_code, 0) << ortho.output;
    EXPECT_EQ(ortho.output,
              "raycast: note: --aperture makes a thin lens of a perspective camera; the scene's orthographic camera "
              "has none, and the image is as sharp as without it\n");
    ASSERT_EQ(run_raycast("ortho.txt sharp.ppm --size 16x16 -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/lens.ppm"), read_file(dir + "/sharp.ppm"));
}

// A nearly singular transform makes every ray go alone (render_test's
// ANearlySingularTransformGivesTheSameImageOnEveryPath), and the command line says so, unless
// the user asked for no packets anyway.
TEST(CliTest, ANearlySingularTransformSaysItsRaysGoAlone) {
    const std::string dir = temp_dir("cli/near_singular");
    write_file(dir + "/n.txt",
               "PerspectiveCamera { center 0 2 6 direction 0 -0.4 -1 up 0 1 0 angle 50 width 16 height 16 }\n"
               "Lights { numLights 1 DirectionalLight { direction -0.3 -1 -0.5 color 0.8 0.8 0.8 } }\n"
               "Materials { numMaterials 1 Material { diffuseColor 0.7 0.6 0.5 } }\n"
               "Group { numObjects 1 MaterialIndex 0 Transform { Matrix { 0.5 0.6 0.9 0  0.5 0.6 0.9000001 0  "
               "0.3 0.8 -0.8 0  0 0 0 1 } Sphere { center 0 0 0 radius 1 } } }\n");
    const RunResult run = run_raycast("n.txt o.ppm", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output,
              "raycast: note: a transform in the scene is nearly singular (its condition is 4.12e+07): every ray is "
              "traced alone, without SIMD packets, so that the image is the same on every path\n");
    EXPECT_EQ(run_raycast("n.txt o.ppm --no-packets", dir).output, "");
}

// Mirrors and glass deep in --bounces can take hours: the first camera sample that reaches its ray
// limit makes a note at once (once), and the count comes at the end; -q says neither.
TEST(CliTest, ARenderReachingTheRayLimitSaysSoAtOnce) {
    const std::string dir = temp_dir("cli/ray_limit");
    write_file(dir + "/m.txt", mirrors_and_glass_scene(4));
    const RunResult run = run_raycast("m.txt o.ppm --bounces 40 --weight 0", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::vector<std::string> lines = lines_of(run.output);
    ASSERT_EQ(lines.size(), 2u) << run.output;
    EXPECT_EQ(lines[0],
              "raycast: note: camera samples are reaching their limit of 65536 rays (mirror and glass rays 40 bounces "
              "deep), so this render may take long: lower --bounces, or raise --weight");
    EXPECT_EQ(lines[1].rfind("raycast: warning: ", 0), 0u) << lines[1];
    EXPECT_NE(lines[1].find("camera samples reached the limit of 65536 rays each"), std::string::npos) << lines[1];
    EXPECT_EQ(run_raycast("m.txt q.ppm --bounces 40 --weight 0 -q", dir).output, "");
}

TEST(CliTest, MitFormRendersAtTheSizeGiven) {
    const std::string dir = scene_dir("mit_form");
    const RunResult run = run_raycast("-input s.txt -size 64 48 -output o.ppm", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const Ppm image = parse_ppm(read_file(dir + "/o.ppm"));
    ASSERT_TRUE(image.ok);
    EXPECT_EQ(image.width, 64);
    EXPECT_EQ(image.height, 48);
}

TEST(CliTest, BadMitCommandLinesExitTwo) {
    const std::string dir = scene_dir("mit_errors");
    const std::pair<const char*, const char*> cases[] = {
        {"-size 64 64 -output o.ppm", "-input SCENE is missing"},
        {"-input s.txt -size 0 0 -output o.ppm", "-size width must be at least 1, got 0"},
        {"-input s.txt -size 64 -output o.ppm", "-size height needs a whole number, got '-output'"},
        {"-input s.txt -size 64 64 -depth 1 2", "-depth NEAR FAR FILE needs a value"},
        {"-input s.txt -size 64 64 -depth near 2 d.ppm", "-depth NEAR needs a number, got 'near'"},
        {"-input s.txt -size 64 64", "nothing to write: give -output FILE (or -depth NEAR FAR FILE, or -normals FILE)"},
        {"-input s.txt -size 64 64 -output", "-output needs a value"},
        {"-input s.txt -output o.ppm extra.ppm",
         "unexpected argument 'extra.ppm' (with -input, name files with -output)"},
    };
    for (const auto& [arguments, message] : cases) {
        SCOPED_TRACE(arguments);
        const RunResult run = run_raycast(arguments, dir);
        EXPECT_EQ(run.exit_code, 2);
        EXPECT_EQ(first_line(run.output), std::string("raycast: usage error: ") + message);
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj"}));
    }
}

// ---- output formats --------------------------------------------------------------------------

TEST(CliTest, OutputFormatFollowsTheExtension) {
    const std::string dir = scene_dir("formats");
    // 30 pixels wide, so that BMP rows (90 bytes) need 2 bytes of padding to reach 92.
    for (const char* name : {"o.bmp", "o.ppm", "o.tga", "upper.BMP"}) {
        const RunResult run = run_raycast(std::string("s.txt ") + name + " --size 30x24 -q", dir);
        ASSERT_EQ(run.exit_code, 0) << name << ": " << run.output;
        EXPECT_EQ(run.output, "");
    }
    const std::string bmp = read_file(dir + "/o.bmp");
    ASSERT_GE(bmp.size(), 54u);
    EXPECT_EQ(bmp.substr(0, 2), "BM");
    EXPECT_EQ(bmp.size(), 54u + 92u * 24u);  // 14 + 40 header bytes, 24 rows of 92 bytes
    EXPECT_EQ(le32(bmp, 2), bmp.size());
    EXPECT_EQ(le32(bmp, 18), 30u);
    EXPECT_EQ(static_cast<int32_t>(le32(bmp, 22)) < 0 ? -static_cast<int32_t>(le32(bmp, 22))
                                                      : static_cast<int32_t>(le32(bmp, 22)),
              24);
    EXPECT_EQ(le16(bmp, 28), 24u);  // bits per pixel
    EXPECT_EQ(read_file(dir + "/upper.BMP"), bmp);

    const Ppm ppm = parse_ppm(read_file(dir + "/o.ppm"));
    ASSERT_TRUE(ppm.ok);
    EXPECT_EQ(ppm.width, 30);
    EXPECT_EQ(ppm.height, 24);

    const std::string tga = read_file(dir + "/o.tga");
    ASSERT_GE(tga.size(), 18u + 3u * 30u * 24u);
    EXPECT_EQ(static_cast<uint8_t>(tga[2]), 2u);  // uncompressed true colour
    EXPECT_EQ(le16(tga, 12), 30u);
    EXPECT_EQ(le16(tga, 14), 24u);
    EXPECT_EQ(static_cast<uint8_t>(tga[16]), 24u);

    // The three files hold the same pixels.
    for (const char* other : {"o.bmp", "o.tga"}) {
        const RunResult run = run_raycast(std::string("compare o.ppm ") + other, dir);
        EXPECT_EQ(run.exit_code, 0) << run.output;
        EXPECT_NE(run.output.find("differing pixels: 0 of 720 (0.0000%)"), std::string::npos) << run.output;
    }
}

#ifdef RAYCAST_HAVE_PNG
TEST(CliTest, PngOutputHoldsTheSamePixelsAsPpm) {
    const std::string dir = scene_dir("png");
    ASSERT_EQ(run_raycast("s.txt o.png -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt o.ppm -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/o.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    const RunResult run = run_raycast("compare o.ppm o.png", dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find("differing pixels: 0 of 768"), std::string::npos) << run.output;
    // --format png writes the same file under any name.
    ASSERT_EQ(run_raycast("s.txt image --format png -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/image"), read_file(dir + "/o.png"));
}
#else
TEST(CliTest, PngOutputWithoutLibpngIsAnOutputError) {
    // Asked for by the name or by --format png: the same error, and nothing written.
    const std::string dir = scene_dir("png");
    for (const auto& [arguments, output] :
         {std::pair<std::string, std::string>{"s.txt o.png", "o.png"}, {"s.txt image --format png", "image"}}) {
        const RunResult run = run_raycast(arguments, dir);
        EXPECT_EQ(run.exit_code, 1) << arguments;
        EXPECT_EQ(first_line(run.output), output + ": error: PNG images need libpng: rebuild raycast with libpng-dev "
                                                   "installed, or use .bmp, .ppm or .tga");
    }
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj"}));
    // The format given, not the name's: a .png name written as PPM needs no libpng.
    ASSERT_EQ(run_raycast("s.txt o.png --format ppm -q", dir).exit_code, 0);
    EXPECT_TRUE(parse_ppm(read_file(dir + "/o.png")).ok);
}
#endif

TEST(CliTest, UnknownOrMissingExtensionIsAUsageErrorAndWritesNothing) {
    const std::string dir = scene_dir("bad_extension");
    const std::pair<const char*, const char*> cases[] = {
        {"s.txt o.jpg", "unknown image format '.jpg' for 'o.jpg': use .bmp, .ppm, .tga or .png, or give --format"},
        {"s.txt image", "cannot tell the image format of 'image': name it .bmp, .ppm, .tga or .png, or give --format"},
        {"s.txt out.d/image",
         "cannot tell the image format of 'out.d/image': name it .bmp, .ppm, .tga or .png, or give --format"},
        {"s.txt /dev/stdout",
         "cannot tell the image format of '/dev/stdout': name it .bmp, .ppm, .tga or .png, or give --format"},
        // --format names the image's format only: the other outputs, and MIT's -output, have none.
        {"s.txt o --format ppm --depth d", "cannot tell the image format of 'd': name it .bmp, .ppm, .tga or .png"},
        {"s.txt o.ppm --normals n.jpg", "unknown image format '.jpg' for 'n.jpg': use .bmp, .ppm, .tga or .png"},
        {"-input s.txt -size 8 8 -output image",
         "cannot tell the image format of 'image': name it .bmp, .ppm, .tga or .png"},
    };
    for (const auto& [arguments, message] : cases) {
        SCOPED_TRACE(arguments);
        const RunResult run = run_raycast(arguments, dir);
        EXPECT_EQ(run.exit_code, 2);
        EXPECT_EQ(first_line(run.output), std::string("raycast: usage error: ") + message);
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj"}));
    }
}

// --format names OUTPUT's format whatever its name says: none, or another image extension.
TEST(CliTest, FormatWritesTheImageInTheFormatGivenWhateverItsName) {
    const std::string dir = scene_dir("format");
    for (const char* arguments :
         {"s.txt o.ppm", "s.txt o.tga", "s.txt image --format ppm", "s.txt attached --format=ppm",
          "s.txt upper --format PPM", "s.txt ppm.bmp --format ppm", "s.txt tga.ppm --format tga"}) {
        const RunResult run = run_raycast(std::string(arguments) + " -q", dir);
        ASSERT_EQ(run.exit_code, 0) << arguments << ": " << run.output;
        EXPECT_EQ(run.output, "") << arguments;
    }
    const std::string ppm = read_file(dir + "/o.ppm");
    ASSERT_TRUE(parse_ppm(ppm).ok);
    EXPECT_EQ(read_file(dir + "/image").substr(0, 2), "P6");
    for (const char* name : {"image", "attached", "upper", "ppm.bmp"}) EXPECT_EQ(read_file(dir + "/" + name), ppm) << name;
    EXPECT_EQ(read_file(dir + "/tga.ppm"), read_file(dir + "/o.tga"));
    // Only OUTPUT: --depth and --normals still follow their own names.
    ASSERT_EQ(run_raycast("s.txt both --format ppm --normals n.bmp -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/both"), ppm);
    EXPECT_EQ(read_file(dir + "/n.bmp").substr(0, 2), "BM");
}

// A pipe is written into, in place, and its name has no extension: --format gives the format.
// Here /dev/stdout is the pipe the test reads; stderr is left out of it.
TEST(CliTest, FormatPpmWritesAnImageThroughAPipe) {
    const std::string dir = scene_dir("format_pipe");
    ASSERT_EQ(run_raycast("s.txt o.ppm -q", dir).exit_code, 0);
    const RunResult run =
        run_command("cd '" + dir + "' && '" + RAYCAST_EXECUTABLE + "' s.txt /dev/stdout --format ppm -q");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output.substr(0, 2), "P6");
    EXPECT_EQ(run.output, read_file(dir + "/o.ppm"));
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj", "o.ppm"}));
}

// "-" is standard output, as for most tools; with the image there, --stats goes to standard
// error, so that the pipe holds the image alone.
TEST(CliTest, ADashIsStandardOutputAndStatsThenGoToStandardError) {
    const std::string dir = scene_dir("format_dash");
    ASSERT_EQ(run_raycast("s.txt o.ppm -q", dir).exit_code, 0);
    const std::string command = "cd '" + dir + "' && '" + RAYCAST_EXECUTABLE + "' s.txt - --format ppm --stats -q";
    const RunResult image = run_command(command + " 2>/dev/null");
    ASSERT_EQ(image.exit_code, 0) << image.output;
    EXPECT_EQ(image.output, read_file(dir + "/o.ppm"));
    const RunResult stats = run_command(command + " 2>&1 >/dev/null");
    ASSERT_EQ(stats.exit_code, 0) << stats.output;
    EXPECT_EQ(stats.output.rfind("raycast-stats ", 0), 0u) << stats.output;
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj", "o.ppm"}));  // no file named "-"
    const RunResult no_format = run_raycast("s.txt -", dir);
    EXPECT_EQ(no_format.exit_code, 2);
    EXPECT_NE(no_format.output.find("cannot tell the image format of '/dev/stdout'"), std::string::npos)
        << no_format.output;
}

// --format ppm writes a --crop piece as a .ppm name does: with its window, for merge.
TEST(CliTest, FormatPpmWritesACropPieceThatMerges) {
    const std::string dir = scene_dir("format_crop");
    ASSERT_EQ(run_raycast("s.txt whole.ppm -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt top --crop 0,0,32,10 --format ppm -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt bottom.bmp --crop 0,10,32,24 --format ppm -q", dir).exit_code, 0);
    EXPECT_EQ(read_file(dir + "/top").rfind("P6\n# raycast-crop 0,0,32,10 of 32x24\n", 0), 0u);
    const RunResult merge = run_raycast("merge -o merged.ppm top bottom.bmp -q", dir);
    ASSERT_EQ(merge.exit_code, 0) << merge.output;
    EXPECT_EQ(read_file(dir + "/merged.ppm"), read_file(dir + "/whole.ppm"));
}

// ---- --stats, --quiet, threads ---------------------------------------------------------------

TEST(CliTest, StatsPrintsOneLineWithTheDocumentedKeys) {
    const std::string dir = scene_dir("stats");
    // --fov both (the default, given explicitly) keeps the note about stretched pixels away.
    const RunResult run = run_raycast("s.txt o.ppm --stats --threads 2 --fov both", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::vector<std::string> lines = lines_of(run.output);
    ASSERT_EQ(lines.size(), 1u) << run.output;
    ASSERT_EQ(lines[0].rfind("raycast-stats ", 0), 0u) << lines[0];
    const std::map<std::string, std::string> fields = stats_fields(lines[0]);
    for (const char* key : {"load_ms", "build_ms", "render_ms", "rays", "mrays_per_s", "triangles", "threads"}) {
        SCOPED_TRACE(key);
        ASSERT_EQ(fields.count(key), 1u) << lines[0];
        EXPECT_GE(std::stod(fields.at(key)), 0.0);
    }
    EXPECT_EQ(fields.at("rays"), "768");     // one primary ray per pixel: 32 × 24, no shadow rays
    EXPECT_EQ(fields.at("triangles"), "2");  // the quad, cut into two triangles
    EXPECT_EQ(fields.at("threads"), "2");
}

TEST(CliTest, StatsStillPrintsWithQuiet) {
    const std::string dir = scene_dir("stats_quiet");
    write_file(dir + "/dark.txt", kDarkScene);
    const RunResult run = run_raycast("dark.txt o.ppm --stats -q --threads 1", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::vector<std::string> lines = lines_of(run.output);
    ASSERT_EQ(lines.size(), 1u) << run.output;
    EXPECT_EQ(lines[0].rfind("raycast-stats ", 0), 0u);
    EXPECT_EQ(stats_fields(lines[0]).at("rays"), "64");
    EXPECT_EQ(stats_fields(lines[0]).at("threads"), "1");
}

TEST(CliTest, QuietPrintsNothingOnSuccess) {
    const std::string dir = scene_dir("quiet");
    write_file(dir + "/dark.txt", kDarkScene);
    // Without -q the missing lights are worth a warning (course form; MIT's conventions light such
    // a scene with a white ambient instead), and MIT's -gui a note ...
    const RunResult warned = run_raycast("dark.txt loud.ppm", dir);
    ASSERT_EQ(warned.exit_code, 0) << warned.output;
    EXPECT_EQ(warned.output,
              "dark.txt: warning: the scene has no lights and no ambient light: every object will be black\n");
    const RunResult noted = run_raycast("-input dark.txt -output loud_mit.ppm -gui", dir);
    ASSERT_EQ(noted.exit_code, 0) << noted.output;
    EXPECT_EQ(noted.output, "raycast: note: -gui is ignored: raycast has no OpenGL preview\n");
    // ... and with it nothing is printed at all, while the images are the same.
    for (const char* quiet : {"-q", "--quiet"}) {
        SCOPED_TRACE(quiet);
        RunResult run = run_raycast(std::string("dark.txt quiet.ppm ") + quiet, dir);
        EXPECT_EQ(run.exit_code, 0);
        EXPECT_EQ(run.output, "");
        EXPECT_EQ(read_file(dir + "/quiet.ppm"), read_file(dir + "/loud.ppm"));
        run = run_raycast(std::string("-input dark.txt -output quiet_mit.ppm -gui ") + quiet, dir);
        EXPECT_EQ(run.exit_code, 0);
        EXPECT_EQ(run.output, "");
        EXPECT_EQ(read_file(dir + "/quiet_mit.ppm"), read_file(dir + "/loud_mit.ppm"));
    }
}

// --test-every-face turns back-face skipping off (scene/back_faces.h). The scene where skipping
// shows: a close-up, at floor level, of where a closed ball mesh rests on a closed floor mesh
// (RenderTest.SkippingBackFacesCanOnlyLetLightInWhereObjectsTouch). By default some pixels there
// are lit that testing every face leaves in the ball's shadow, and none the other way.
TEST(CliTest, TestEveryFaceTurnsBackFaceSkippingOff) {
    const std::string dir = temp_dir("every_face");
    TriangleMesh floor = test::cube_mesh();  // [−5, 5] × [−1, 0] × [−5, 5]
    for (Vec3f& p : floor.positions) p = {5 * p.x, 0.5f * p.y - 0.5f, 5 * p.z};
    write_file(dir + "/floor.obj", obj_text(floor));
    write_file(dir + "/ball.obj", obj_text(test::sphere_mesh({0, 1, 0}, 1, 64, 64)));  // resting on the floor
    write_file(dir + "/contact.txt", R"(PerspectiveCamera {
    center -3 2e-6 1e-4
    direction 1 -6.6666667e-7 0
    up 0 1 0
    angle 0.01
    width 48
    height 48
}
Lights { numLights 1 DirectionalLight { direction 0 -1 0 color 1 1 1 } }
Background { color 0 0 1 }
Materials { numMaterials 1 Material { diffuseColor 0.8 0.8 0.8 } }
Group {
    numObjects 2
    MaterialIndex 0
    TriangleMesh { obj_file floor.obj }
    TriangleMesh { obj_file ball.obj }
}
)");
    ASSERT_EQ(run_raycast("contact.txt skipping.ppm --shadows -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("contact.txt every_face.ppm --shadows -q --test-every-face", dir).exit_code, 0);
    const Ppm skipping = parse_ppm(read_file(dir + "/skipping.ppm"));
    const Ppm every_face = parse_ppm(read_file(dir + "/every_face.ppm"));
    ASSERT_TRUE(skipping.ok && every_face.ok);
    ASSERT_EQ(skipping.rgb.size(), every_face.rgb.size());
    int lighter = 0, darker = 0;
    for (size_t i = 0; i < skipping.rgb.size(); ++i) {
        lighter += skipping.rgb[i] > every_face.rgb[i];
        darker += skipping.rgb[i] < every_face.rgb[i];
    }
    EXPECT_GT(lighter, 0);
    EXPECT_EQ(darker, 0);
}

TEST(CliTest, OneThreadAndTwoThreadsWriteTheSameImage) {
    const std::string dir = scene_dir("threads");
    ASSERT_EQ(run_raycast("s.txt one.ppm --threads 1 --shadows -q", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt two.ppm --threads 2 --shadows -q --tile 5", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt scalar.ppm -j 2 --shadows -q --no-packets", dir).exit_code, 0);
    ASSERT_EQ(run_raycast("s.txt every_face.ppm -j 2 --shadows -q --test-every-face", dir).exit_code, 0);
    const std::string one = read_file(dir + "/one.ppm");
    ASSERT_TRUE(parse_ppm(one).ok);
    EXPECT_EQ(read_file(dir + "/two.ppm"), one);
    EXPECT_EQ(read_file(dir + "/scalar.ppm"), one);
    EXPECT_EQ(read_file(dir + "/every_face.ppm"), one);
    // The image is not trivially uniform: the sphere, floor, quad and background all show.
    std::set<std::vector<uint8_t>> colours;
    const Ppm image = parse_ppm(one);
    for (size_t i = 0; i + 2 < image.rgb.size(); i += 3)
        colours.insert({image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]});
    EXPECT_GT(colours.size(), 4u);
}

// GNU tools take "-j4" and "--threads=4" as "-j 4" and "--threads 4"; so does raycast, for every
// option with a value, including the compare tool's.
TEST(CliTest, AttachedValuesReadAsSeparateOnes) {
    const std::string dir = scene_dir("attached");
    ASSERT_EQ(run_raycast("s.txt apart.ppm -j 1 --size 16x12 --mode normals -q", dir).exit_code, 0);
    const RunResult attached = run_raycast("s.txt attached.ppm -j1 --size=16x12 --mode=normals -q", dir);
    ASSERT_EQ(attached.exit_code, 0) << attached.output;
    ASSERT_EQ(run_raycast("s.txt shaded.ppm --threads=2 --size=16x12 -q", dir).exit_code, 0);
    const Ppm apart = parse_ppm(read_file(dir + "/apart.ppm"));
    ASSERT_TRUE(apart.ok);
    EXPECT_EQ(apart.width, 16);
    EXPECT_EQ(apart.height, 12);
    EXPECT_EQ(read_file(dir + "/attached.ppm"), read_file(dir + "/apart.ppm"));
    // The normals image differs from the shaded one, so --mode=normals was not dropped.
    EXPECT_NE(read_file(dir + "/shaded.ppm"), read_file(dir + "/apart.ppm"));
    const RunResult compare = run_raycast("compare apart.ppm shaded.ppm --max-diff=255 --diff=d.ppm", dir);
    EXPECT_EQ(compare.exit_code, 0) << compare.output;
    EXPECT_EQ(lines_of(compare.output).back(),
              "within tolerance: 0 of 192 pixels (0%) differ by more than 255 levels; none may");
    EXPECT_TRUE(parse_ppm(read_file(dir + "/d.ppm")).ok);
}

// ---- compare ---------------------------------------------------------------------------------

// A: four pixels of (10, 20, 30). B: pixel 1 is (13, 20, 40), off by 3 and 10; pixel 2 is (11, 20, 30),
// off by 1. By hand: 2 of 4 pixels differ (50%), 1 by more than 1 level, max error 10, mean error
// (3 + 10 + 1) / 12 channels = 1.166667, MSE 110 / 12, PSNR 10·log10(255² / (110/12)) = 38.5087 dB.
const std::vector<uint8_t> kA = {10, 20, 30, 10, 20, 30, 10, 20, 30, 10, 20, 30};
const std::vector<uint8_t> kB = {10, 20, 30, 13, 20, 40, 11, 20, 30, 10, 20, 30};

TEST(CliTest, CompareReportsIdenticalImages) {
    const std::string dir = temp_dir("cli/compare_same");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/a2.ppm", make_ppm(2, 2, kA));
    const RunResult run = run_raycast("compare a.ppm a2.ppm", dir);
    EXPECT_EQ(run.exit_code, 0);
    EXPECT_EQ(run.output,
              "compared a.ppm and a2.ppm (2x2)\n"
              "differing pixels: 0 of 4 (0.0000%)\n"
              "pixels off by more than 1 level: 0\n"
              "max error: 0 levels\n"
              "mean error: 0.000000 levels\n"
              "PSNR: inf (identical)\n");
}

TEST(CliTest, CompareCountsDifferingPixelsAndStillExitsZero) {
    const std::string dir = temp_dir("cli/compare_differ");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/b.ppm", make_ppm(2, 2, kB));
    const RunResult run = run_raycast("compare a.ppm b.ppm", dir);
    EXPECT_EQ(run.exit_code, 0);  // documented: 0 is success; a difference is a result, not an error
    EXPECT_EQ(run.output,
              "compared a.ppm and b.ppm (2x2)\n"
              "differing pixels: 2 of 4 (50.0000%)\n"
              "pixels off by more than 1 level: 1\n"
              "max error: 10 levels\n"
              "mean error: 1.166667 levels\n"
              "PSNR: 38.51 dB\n");
}

TEST(CliTest, CompareDiffWritesAHeatMap) {
    const std::string dir = temp_dir("cli/compare_diff");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/b.ppm", make_ppm(2, 2, kB));
    const RunResult run = run_raycast("compare a.ppm b.ppm --diff d.ppm", dir);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const Ppm diff = parse_ppm(read_file(dir + "/d.ppm"));
    ASSERT_TRUE(diff.ok);
    ASSERT_EQ(diff.width, 2);
    ASSERT_EQ(diff.height, 2);
    auto pixel = [&](size_t i) { return std::vector<uint8_t>(diff.rgb.begin() + 3 * i, diff.rgb.begin() + 3 * i + 3); };
    EXPECT_EQ(pixel(0), (std::vector<uint8_t>{0, 0, 0}));  // equal: black
    EXPECT_EQ(pixel(3), (std::vector<uint8_t>{0, 0, 0}));
    EXPECT_EQ(pixel(1), (std::vector<uint8_t>{255, 255, 255}));  // the largest difference: white
    const std::vector<uint8_t> small = pixel(2);                 // 1 level: dark blue, never black
    EXPECT_GT(small[2], 0);
    EXPECT_GE(small[2], small[0]);
    EXPECT_GE(small[2], small[1]);
    EXPECT_NE(small, (std::vector<uint8_t>{255, 255, 255}));
}

TEST(CliTest, CompareErrorsAreReported) {
    const std::string dir = temp_dir("cli/compare_errors");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/wide.ppm", make_ppm(3, 2, std::vector<uint8_t>(18, 7)));

    RunResult run = run_raycast("compare a.ppm wide.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(first_line(run.output), "wide.ppm: error: cannot compare: it is 3x2 but 'a.ppm' is 2x2");

    run = run_raycast("compare a.ppm missing.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(first_line(run.output).rfind("missing.ppm: error: ", 0), 0u) << run.output;

    run = run_raycast("compare a.ppm", dir);
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(first_line(run.output), "raycast: usage error: compare needs two images: raycast compare A B");

    run = run_raycast("compare a.ppm a.ppm --diff a.ppm", dir);
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_EQ(first_line(run.output),
              "raycast: usage error: the output 'a.ppm' is an image being compared itself: choose another name");
    EXPECT_EQ(read_file(dir + "/a.ppm"), make_ppm(2, 2, kA));
}

// Grading (--max-diff, --max-fraction, --mask) on kA and kB: pixel 1 is off by 10 levels, pixel 2
// by 1, so 1 of the 4 pixels differs by more than 1 level and 2 by more than 0.
TEST(CliTest, CompareGradesWithinTheTolerance) {
    const std::string dir = temp_dir("cli/compare_grade_pass");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/b.ppm", make_ppm(2, 2, kB));
    // 25% of 4 pixels: 1 may differ by more than 1 level, and 1 does.
    RunResult run = run_raycast("compare a.ppm b.ppm --max-diff 1 --max-fraction 0.25", dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(lines_of(run.output).back(),
              "within tolerance: 1 of 4 pixels (25%) differ by more than 1 level; at most 25% (1 pixel) may");
    // --max-diff alone allows no pixel beyond it.
    run = run_raycast("compare a.ppm b.ppm --max-diff 10", dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(lines_of(run.output).back(), "within tolerance: 0 of 4 pixels (0%) differ by more than 10 levels; none may");
}

TEST(CliTest, CompareExitsOneWithALineSayingWhyBeyondTheTolerance) {
    const std::string dir = temp_dir("cli/compare_grade_fail");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/b.ppm", make_ppm(2, 2, kB));
    // The course's tolerance: 0.1% of 4 pixels is 0.
    RunResult run = run_raycast("compare a.ppm b.ppm --max-diff 1 --max-fraction 0.001", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(lines_of(run.output).back(),
              "raycast: images differ: 1 of 4 pixels (25%) differ by more than 1 level; at most 0.1% (0 pixels) may");
    run = run_raycast("compare a.ppm b.ppm --max-diff 9", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(lines_of(run.output).back(),
              "raycast: images differ: 1 of 4 pixels (25%) differ by more than 9 levels; none may");
    // --max-fraction alone counts every difference (--max-diff 0).
    run = run_raycast("compare a.ppm b.ppm --max-fraction 0.25", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(lines_of(run.output).back(),
              "raycast: images differ: 2 of 4 pixels (50%) differ by more than 0 levels; at most 25% (1 pixel) may");
}

TEST(CliTest, CompareIgnoresThePixelsThatAreBlackInTheMask) {
    const std::string dir = temp_dir("cli/compare_mask");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/b.ppm", make_ppm(2, 2, kB));
    // Pixel 1, the one off by 10, is black in the mask; pixel 2 (off by 1) is grey, so it counts.
    write_file(dir + "/mask.ppm", make_ppm(2, 2, {255, 255, 255, 0, 0, 0, 1, 1, 1, 255, 255, 255}));
    const RunResult run = run_raycast("compare a.ppm b.ppm --mask mask.ppm --max-diff 0 --max-fraction 0.34", dir);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output,
              "compared a.ppm and b.ppm (2x2)\n"
              "ignored pixels (black in mask.ppm): 1\n"
              "differing pixels: 1 of 3 (33.3333%)\n"
              "pixels off by more than 1 level: 0\n"
              "max error: 1 levels\n"
              "mean error: 0.111111 levels\n"
              "PSNR: 57.67 dB\n"
              "within tolerance: 1 of 3 pixels (33.3%) differ by more than 0 levels; at most 34% (1 pixel) may\n");
}

TEST(CliTest, CompareToleranceMistakesAreUsageErrors) {
    const std::string dir = temp_dir("cli/compare_grade_usage");
    write_file(dir + "/a.ppm", make_ppm(2, 2, kA));
    write_file(dir + "/wide.ppm", make_ppm(3, 2, std::vector<uint8_t>(18, 7)));
    const std::pair<const char*, const char*> cases[] = {
        {"--max-diff 256", "--max-diff must be at most 255, got 256"},
        {"--max-diff -1", "--max-diff must not be negative, got -1"},
        {"--max-diff 1.5", "--max-diff needs a whole number, got '1.5'"},
        {"--max-diff", "--max-diff needs a number of levels, 0 to 255"},
        {"--max-fraction 1.5", "--max-fraction must be from 0 to 1, got 1.5"},
        {"--max-fraction -0.1", "--max-fraction must be from 0 to 1, got -0.1"},
        {"--max-fraction 0.1%", "--max-fraction needs a number from 0 to 1, got '0.1%'"},
        {"--max-fraction nan", "--max-fraction needs a number from 0 to 1, got 'nan'"},
        {"--mask", "--mask needs a file name"},
    };
    for (const auto& [options, message] : cases) {
        SCOPED_TRACE(options);
        const RunResult run = run_raycast(std::string("compare a.ppm a.ppm ") + options, dir);
        EXPECT_EQ(run.exit_code, 2);
        EXPECT_EQ(first_line(run.output), std::string("raycast: usage error: ") + message);
    }
    const RunResult run = run_raycast("compare a.ppm a.ppm --mask wide.ppm", dir);
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output, "wide.ppm: error: cannot use it as a mask: it is 3x2 but the images are 2x2\n");
}

// ---- failed runs and existing outputs ---------------------------------------------------------

TEST(CliTest, AFailedRunNeverDamagesAnExistingOutput) {
    const std::string dir = scene_dir("failed_run");
    write_file(dir + "/bad.txt", "PerspectiveCamera { center 0 0 10 direction 0 0\n");
    const std::string precious = "precious bytes, not an image\n";
    write_file(dir + "/o.ppm", precious);
    const std::pair<const char*, int> cases[] = {
        {"bad.txt o.ppm", 1},                               // the scene does not parse
        {"missing.txt o.ppm", 1},                           // no scene at all
        {"s.txt o.ppm --depth /nonexistent/dir/d.ppm", 1},  // a second output cannot be written
        {"s.txt o.ppm --crop 0,0,100,100", 2},              // found only after the scene is loaded
        {"-input bad.txt -size 8 8 -output o.ppm", 1},
        {"s.txt o.ppm --threads 0", 2},
    };
    for (const auto& [arguments, exit_code] : cases) {
        SCOPED_TRACE(arguments);
        const RunResult run = run_raycast(arguments, dir);
        EXPECT_EQ(run.exit_code, exit_code) << run.output;
        EXPECT_EQ(read_file(dir + "/o.ppm"), precious);
        // No temporary file is left behind either.
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj", "bad.txt", "o.ppm"}));
    }
    // A successful run replaces it.
    ASSERT_EQ(run_raycast("s.txt o.ppm -q", dir).exit_code, 0);
    EXPECT_TRUE(parse_ppm(read_file(dir + "/o.ppm")).ok);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt", "quad.obj", "bad.txt", "o.ppm"}));
}

// `raycast view` runs the raycast-view program beside raycast (so that a render never loads the
// HTTP library); a raycast copied alone says what is missing, and the renderer itself does not
// link cpp-httplib.
TEST(CliTest, ViewRunsTheViewerProgramBesideRaycastAndSaysWhenItIsMissing) {
    const std::string dir = temp_dir("view_program");
    ASSERT_EQ(run_command("cp '" RAYCAST_EXECUTABLE "' '" + dir + "/raycast'").exit_code, 0);
    const RunResult alone = run_command("'" + dir + "/raycast' view s.txt 2>&1");
    EXPECT_EQ(alone.exit_code, 1);
    EXPECT_EQ(alone.output, "raycast view: error: the viewer is the program " + dir +
                                "/raycast-view, which is not there: it is built with raycast (cmake --build)\n");
    const RunResult libraries = run_command("ldd '" RAYCAST_EXECUTABLE "' 2>&1");
    if (libraries.exit_code == 0) {
        EXPECT_EQ(libraries.output.find("httplib"), std::string::npos) << libraries.output;
    }
}

}  // namespace
}  // namespace raycast::test
