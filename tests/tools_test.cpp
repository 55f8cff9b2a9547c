// The helper programs beside raycast, run as a user runs them: raycast_meshgen (seeded OBJ meshes)
// and raycast_revolve (a scene's surfaces of revolution as meshes). Their mistakes are usage errors
// (exit 2) or write errors (exit 1) that leave no file behind and no input changed.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <string>

#include "test_support.h"

namespace raycast::test {
namespace {

RunResult run_tool(const std::string& tool, const std::string& arguments, const std::string& dir) {
    return run_command("cd '" + dir + "' && '" + std::string(RAYCAST_BINARY_DIR) + "/" + tool + "' " + arguments +
                       " 2>&1");
}

// Numbers are read whole: atof had taken "1e3junk" as 1000, "0x100" as 0 (then the minimum), and
// --bumps nan had written a mesh of NaN vertices that raycast refuses.
TEST(ToolsTest, MeshgenRefusesMalformedNumbers) {
    const std::string dir = temp_dir("tools/meshgen_numbers");
    const std::pair<const char*, const char*> cases[] = {
        {"torus 1e3junk a.obj", "raycast_meshgen: TRIANGLES must be a number from 8 to 200000000, got '1e3junk'"},
        {"torus 0x100 a.obj", "raycast_meshgen: TRIANGLES must be a number from 8 to 200000000, got '0x100'"},
        {"torus 7 a.obj", "raycast_meshgen: TRIANGLES must be a number from 8 to 200000000, got '7'"},
        {"bumpy-sphere 1000 a.obj --bumps nan", "raycast_meshgen: --bumps needs a number from 0 to 1, got 'nan'"},
        {"terrain 1000 a.obj --bumps inf", "raycast_meshgen: --bumps needs a number from 0 to 1, got 'inf'"},
        {"terrain 1000 a.obj --bumps 1e300", "raycast_meshgen: --bumps needs a number from 0 to 1, got '1e300'"},
        {"torus 1000 a.obj --bumps 0.1", "raycast_meshgen: --bumps is for bumpy-sphere and terrain; a torus has none"},
        {"torus 1000 a.obj --seed -1", "raycast_meshgen: --seed needs a whole number from 0 to 2^64 - 1, got '-1'"},
    };
    for (const auto& [arguments, message] : cases) {
        const RunResult run = run_tool("raycast_meshgen", arguments, dir);
        EXPECT_EQ(run.exit_code, 2) << arguments;
        EXPECT_EQ(run.output, std::string(message) + "\n") << arguments;
    }
    EXPECT_TRUE(files_in(dir).empty());
}

// As raycast and GNU tools read their command lines: --help prints the usage on standard output
// and exits 0 (it had been a usage error on standard error), and "--name=value" reads as
// "--name value".
TEST(ToolsTest, ToolsTakeHelpAndAttachedValuesAsRaycastDoes) {
    const std::string dir = temp_dir("tools/help");
    for (const char* tool : {"raycast_meshgen", "raycast_revolve"})
        for (const char* help : {"--help", "-h"}) {
            const RunResult run = run_command("cd '" + dir + "' && '" + std::string(RAYCAST_BINARY_DIR) + "/" + tool +
                                              "' " + help + " 2>/dev/null");
            EXPECT_EQ(run.exit_code, 0) << tool << " " << help;
            EXPECT_EQ(run.output.rfind(std::string("usage: ") + tool + " ", 0), 0u) << run.output;
        }
    const RunResult spaced = run_tool("raycast_meshgen", "bumpy-sphere 1000 a.obj --seed 7 --bumps 0.1", dir);
    const RunResult attached = run_tool("raycast_meshgen", "bumpy-sphere 1000 b.obj --seed=7 --bumps=0.1", dir);
    ASSERT_EQ(spaced.exit_code, 0) << spaced.output;
    ASSERT_EQ(attached.exit_code, 0) << attached.output;
    EXPECT_EQ(read_file(dir + "/a.obj"), read_file(dir + "/b.obj"));
    const RunResult bad = run_tool("raycast_meshgen", "bumpy-sphere 1000 c.obj --seed=x", dir);
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_EQ(bad.output, "raycast_meshgen: --seed needs a whole number from 0 to 2^64 - 1, got 'x'\n");

    write_file(dir + "/s.txt", read_file(std::string(RAYCAST_SOURCE_DIR) + "/scenes/revolution.txt"));
    const RunResult revolved = run_tool("raycast_revolve", "s.txt o.txt --along=8 --around=9", dir);
    ASSERT_EQ(revolved.exit_code, 0) << revolved.output;
    EXPECT_NE(revolved.output.find("(8 x 9 each)"), std::string::npos) << revolved.output;
    const RunResult small = run_tool("raycast_revolve", "s.txt p.txt --along=2", dir);
    EXPECT_EQ(small.exit_code, 2);
    EXPECT_EQ(small.output, "raycast_revolve: --along needs a whole number from 3 to 100000, got '2'\n");
}

// The mesh is written to a temporary file and renamed: a failed write leaves nothing at the path
// (it had left a mesh cut mid-line). What it writes loads in raycast with the count it prints.
TEST(ToolsTest, MeshgenWritesWholeMeshesOrNone) {
    const std::string dir = temp_dir("tools/meshgen_write");
    const RunResult missing = run_tool("raycast_meshgen", "terrain 1000 no_such_folder/a.obj", dir);
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_EQ(missing.output, "no_such_folder/a.obj: error: cannot write OBJ file: No such file or directory\n");
    EXPECT_TRUE(files_in(dir).empty());
    const RunResult made = run_tool("raycast_meshgen", "bumpy-sphere 1000 m.obj --bumps 0.1 --seed 7", dir);
    ASSERT_EQ(made.exit_code, 0) << made.output;
    EXPECT_EQ(made.output, "m.obj: 498 vertices, 992 triangles\n");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"m.obj"}));
    // Into a pipe it writes through (a rename would have put a plain file in the pipe's place).
    const RunResult piped = run_command("cd '" + dir + "' && mkfifo p && (cat p > copy.obj &) && '" +
                                        std::string(RAYCAST_BINARY_DIR) +
                                        "/raycast_meshgen' bumpy-sphere 1000 p --bumps 0.1 --seed 7 2>&1 && "
                                        "sleep 0.2 && test -p p && rm p");
    EXPECT_EQ(piped.exit_code, 0) << piped.output;
    EXPECT_EQ(read_file(dir + "/copy.obj"), read_file(dir + "/m.obj"));
    std::remove((dir + "/copy.obj").c_str());
    // Through a symbolic link, into the file it leads to; the link stays a link.
    const RunResult linked = run_command("cd '" + dir + "' && ln -s m.obj link.obj && '" +
                                         std::string(RAYCAST_BINARY_DIR) +
                                         "/raycast_meshgen' bumpy-sphere 1000 link.obj --seed 8 2>&1 && test -L link.obj");
    EXPECT_EQ(linked.exit_code, 0) << linked.output;
    EXPECT_NE(read_file(dir + "/m.obj").find("seed 8"), std::string::npos);
    std::remove((dir + "/link.obj").c_str());
    ASSERT_EQ(run_tool("raycast_meshgen", "bumpy-sphere 1000 m.obj --bumps 0.1 --seed 7", dir).exit_code, 0);
    write_file(dir + "/s.txt",
               "PerspectiveCamera { center 0 0 5 direction 0 0 -1 up 0 1 0 angle 30 width 8 height 8 }\n"
               "Lights { numLights 1 DirectionalLight { direction 0 0 -1 color 1 1 1 } }\n"
               "Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }\n"
               "Group { numObjects 1 MaterialIndex 0 TriangleMesh { obj_file m.obj } }\n");
    const RunResult rendered = run_raycast("s.txt o.ppm --stats -q", dir);
    ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
    EXPECT_NE(rendered.output.find(" triangles=992 "), std::string::npos) << rendered.output;
}

// raycast_revolve checks its output before it writes anything: the scene itself as OUTPUT had
// been overwritten with the copy (every curve lost), a quote in the name made a scene raycast
// could not read, and a missing folder was found only after gigabytes of OBJ files were written.
TEST(ToolsTest, RevolveChecksItsOutputBeforeWritingAnything) {
    const std::string dir = temp_dir("tools/revolve");
    const std::string scene = read_file(std::string(RAYCAST_SOURCE_DIR) + "/scenes/revolution.txt");
    ASSERT_NE(scene.find("RevSurface"), std::string::npos);
    write_file(dir + "/s.txt", scene);
    const std::pair<const char*, const char*> cases[] = {
        {"s.txt s.txt", "raycast_revolve: OUTPUT 's.txt' is the scene itself: choose another name"},
        {"s.txt ./s.txt", "raycast_revolve: OUTPUT './s.txt' is the scene itself: choose another name"},
        {"s.txt 'it\"s.txt'",
         "raycast_revolve: OUTPUT 'it\"s.txt' cannot name the meshes in the scene it writes: use a name without quotes"},
    };
    for (const auto& [arguments, message] : cases) {
        const RunResult run = run_tool("raycast_revolve", std::string(arguments) + " --along 8 --around 8", dir);
        EXPECT_EQ(run.exit_code, 2) << arguments;
        EXPECT_EQ(run.output, std::string(message) + "\n") << arguments;
    }
    // An option without its value says so ("unknown argument '--around'" had said otherwise).
    const RunResult no_value = run_tool("raycast_revolve", "s.txt o.txt --along 8 --around", dir);
    EXPECT_EQ(no_value.exit_code, 2);
    EXPECT_EQ(no_value.output, "raycast_revolve: --around needs a whole number from 3 to 100000\n");
    // A scene with classic Mac line breaks, which raycast reads, is turned as well.
    std::string mac = scene;
    for (char& c : mac)
        if (c == '\n') c = '\r';
    write_file(dir + "/mac.txt", mac);
    const RunResult turned = run_tool("raycast_revolve", "mac.txt out.txt --along 8 --around 8", dir);
    EXPECT_EQ(turned.exit_code, 0) << turned.output;
    EXPECT_EQ(turned.output.rfind("raycast_revolve: 4 surfaces", 0), 0u) << turned.output;
    for (const std::string& name : files_in(dir))
        if (name != "s.txt") std::remove((dir + "/" + name).c_str());
    const RunResult missing = run_tool("raycast_revolve", "s.txt no_such_folder/o.txt --along 8 --around 8", dir);
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_EQ(missing.output,
              "no_such_folder/o.txt: error: cannot write the scene: the folder 'no_such_folder' does not exist\n");
    EXPECT_EQ(read_file(dir + "/s.txt"), scene);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"s.txt"}));
}

// With OUTPUT in another folder, the scene's own relative mesh paths are rewritten to name the
// same files from there (they were copied as they were, and the new scene could not find its
// meshes); in the scene's own folder everything but the RevSurface blocks is copied byte for byte.
TEST(ToolsTest, RevolveKeepsTheScenesMeshesFoundFromAnotherFolder) {
    const std::string dir = temp_dir("tools/revolve_folders");
    ASSERT_EQ(run_command("mkdir -p '" + dir + "/scenes/meshes' '" + dir + "/out'").exit_code, 0);
    const char* const scene =
        "PerspectiveCamera { center 0 1 8 direction 0 0 -1 up 0 1 0 angle 30 width 16 height 12 }\n"
        "Lights { numLights 1 DirectionalLight { direction 0 -1 -1 color 1 1 1 } }\n"
        "Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }\n"
        "Group { numObjects 3 MaterialIndex 0\n"
        "  TriangleMesh { obj_file meshes/quad.obj }\n"
        "  TriangleMesh { obj_file \"meshes/quad.obj\" }  # the same file, quoted\n"
        "  RevSurface { profile BezierCurve { controls [ 0 0 0 ] [ 1 0.5 0 ] [ 1 1.5 0 ] [ 0 2 0 ] } }\n"
        "}\n";
    write_file(dir + "/scenes/s.txt", scene);
    write_file(dir + "/scenes/meshes/quad.obj", "v -2 -1 -2\nv 2 -1 -2\nv 2 2 -2\nv -2 2 -2\nf 1 2 3 4\n");
    const RunResult moved = run_tool("raycast_revolve", "scenes/s.txt out/o.txt --along 8 --around 8", dir);
    ASSERT_EQ(moved.exit_code, 0) << moved.output;
    EXPECT_EQ(moved.output,
              "raycast_revolve: 1 surfaces, 128 triangles (8 x 8 each)\n"
              "raycast_revolve: 2 mesh paths written relative to out/o.txt's folder\n");
    const std::string written = read_file(dir + "/out/o.txt");
    EXPECT_NE(written.find("TriangleMesh { obj_file ../scenes/meshes/quad.obj }\n"), std::string::npos) << written;
    EXPECT_NE(written.find("TriangleMesh { obj_file ../scenes/meshes/quad.obj }  # the same file, quoted\n"),
              std::string::npos) << written;
    EXPECT_NE(written.find("TriangleMesh { obj_file \"o.rev0.obj\" }"), std::string::npos) << written;
    // Found wherever raycast runs from, and the same picture as from the scene's own copy.
    for (const char* from : {"", "/out", "/scenes"}) {
        SCOPED_TRACE(from);
        const RunResult rendered = run_raycast("'" + dir + "/out/o.txt' '" + dir + "/o.ppm' --stats -q", dir + from);
        ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
        EXPECT_NE(rendered.output.find(" triangles=132 "), std::string::npos) << rendered.output;
    }
    const RunResult beside = run_tool("raycast_revolve", "s.txt o.txt --along 8 --around 8", dir + "/scenes");
    ASSERT_EQ(beside.exit_code, 0) << beside.output;
    EXPECT_EQ(beside.output, "raycast_revolve: 1 surfaces, 128 triangles (8 x 8 each)\n");
    const std::string copied = read_file(dir + "/scenes/o.txt");
    const std::string expected = std::string(scene).replace(
        std::string(scene).find("RevSurface"),
        std::string(scene).find(" }\n}\n") + 2 - std::string(scene).find("RevSurface"),
        "TriangleMesh { obj_file \"o.rev0.obj\" }");
    EXPECT_EQ(copied, expected);
    ASSERT_EQ(run_raycast("o.txt o.ppm -q", dir + "/scenes").exit_code, 0);
    EXPECT_EQ(read_file(dir + "/scenes/o.ppm"), read_file(dir + "/o.ppm"));
}

// The rewritten paths: a mesh that is a link keeps its own name (a later `ln -sf` still reaches
// it), a folder with a space, a vertical tab or a # in its name is quoted, and a path a scene
// cannot quote (a quote in it) is left with a warning. An OUTPUT that is a link is written
// through, and the meshes go beside the file it leads to; one into a missing folder is refused
// before any mesh is written.
TEST(ToolsTest, RevolveRewritesMeshPathsAsASceneCanReadThem) {
    const std::string dir = temp_dir("tools/revolve_paths");
    const std::string scene =
        "PerspectiveCamera { center 0 1 8 direction 0 0 -1 up 0 1 0 angle 30 width 16 height 12 }\n"
        "Lights { numLights 1 DirectionalLight { direction 0 -1 -1 color 1 1 1 } }\n"
        "Materials { numMaterials 1 Material { diffuseColor 1 1 1 } }\n"
        "Group { numObjects 2 MaterialIndex 0\n"
        "  TriangleMesh { obj_file m/quad.obj }\n"
        "  RevSurface { profile BezierCurve { controls [ 0 0 0 ] [ 1 0.5 0 ] [ 1 1.5 0 ] [ 0 2 0 ] } }\n"
        "}\n";
    const std::string quad = "v -2 -1 -2\nv 2 -1 -2\nv 2 2 -2\nv -2 2 -2\nf 1 2 3 4\n";
    ASSERT_EQ(run_command("cd '" + dir + "' && mkdir -p out 'sp ace/m' \"$(printf 'v\\vt')/m\" 'q\"d/m' link/m").exit_code, 0);
    for (const std::string folder : {"sp ace", "v\vt", "q\"d", "link"}) write_file(dir + "/" + folder + "/s.txt", scene);
    for (const std::string folder : {"sp ace", "v\vt", "q\"d"}) write_file(dir + "/" + folder + "/m/quad.obj", quad);
    write_file(dir + "/link/m/quad_v1.obj", quad);
    ASSERT_EQ(run_command("cd '" + dir + "/link/m' && ln -s quad_v1.obj quad.obj").exit_code, 0);
    const std::pair<std::string, std::string> cases[] = {
        {"sp ace", "obj_file \"../sp ace/m/quad.obj\""},
        {"v\vt", "obj_file \"../v\vt/m/quad.obj\""},
        {"link", "obj_file ../link/m/quad.obj"},
    };
    for (const auto& [folder, expected] : cases) {
        SCOPED_TRACE(folder);
        const RunResult run = run_tool("raycast_revolve", "'" + folder + "/s.txt' out/o.txt --along 8 --around 8", dir);
        ASSERT_EQ(run.exit_code, 0) << run.output;
        EXPECT_NE(read_file(dir + "/out/o.txt").find(expected), std::string::npos) << read_file(dir + "/out/o.txt");
        const RunResult rendered = run_raycast("o.txt o.ppm --stats -q", dir + "/out");
        ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
        EXPECT_NE(rendered.output.find(" triangles=130 "), std::string::npos) << rendered.output;
    }
    const RunResult unquotable = run_tool("raycast_revolve", "'q\"d/s.txt' out/o.txt --along 8 --around 8", dir);
    EXPECT_EQ(unquotable.exit_code, 0) << unquotable.output;
    EXPECT_NE(unquotable.output.find("q\"d/s.txt:5:27: warning: obj_file 'm/quad.obj' is copied as it is: from "),
              std::string::npos) << unquotable.output;
    // OUTPUT as a link: the scene lands where it leads, the meshes beside it.
    ASSERT_EQ(run_command("cd '" + dir + "' && mkdir elsewhere && ln -s ../elsewhere/e.txt out/e.txt && ln -s "
                          "../missing/x.txt out/x.txt").exit_code, 0);
    const RunResult linked = run_tool("raycast_revolve", "link/s.txt out/e.txt --along 8 --around 8", dir);
    ASSERT_EQ(linked.exit_code, 0) << linked.output;
    EXPECT_EQ(files_in(dir + "/elsewhere"), (std::set<std::string>{"e.txt", "e.rev0.obj"}));
    ASSERT_EQ(run_raycast("e.txt e.ppm -q", dir + "/elsewhere").exit_code, 0);
    const std::set<std::string> before = files_in(dir + "/out");
    const RunResult missing = run_tool("raycast_revolve", "link/s.txt out/x.txt --along 8 --around 8", dir);
    EXPECT_EQ(missing.exit_code, 1);
    EXPECT_EQ(missing.output, "out/x.txt: error: cannot write the scene: the folder 'out/../missing' does not exist\n");
    EXPECT_EQ(files_in(dir + "/out"), before);
    const RunResult device = run_tool("raycast_revolve", "link/s.txt /dev/null --along 8 --around 8", dir);
    EXPECT_EQ(device.exit_code, 2);
    EXPECT_EQ(device.output, "raycast_revolve: OUTPUT '/dev/null' must be a file: the meshes are written beside it\n");
}

}  // namespace
}  // namespace raycast::test
