// raycast_revolve: a scene's surfaces of revolution as triangle meshes, to compare the exact
// intersection with a tessellation (in speed and in looks) or to hand the scene to a renderer that
// only takes meshes.
//   raycast_revolve SCENE OUTPUT.txt [--along N] [--around M]
// Writes OUTPUT.txt, a copy of SCENE in which the k-th `RevSurface { ... }` (k = 0, 1, ... in file
// order) is replaced by `TriangleMesh { obj_file "OUTPUT.revK.obj" }`, and those OBJ files beside
// it, with the surface's analytic normals at the vertices: N steps of the profile's parameter
// (default 256) by M steps around the axis (default 256). Everything else is copied byte for byte.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/limits.h"
#include "base/write_file.h"
#include "geometry/rev_surface.h"
#include "sceneio/lexer.h"
#include "sceneio/load_scene.h"
#include "sceneio/parse_scene.h"
#include "sceneio/text_check.h"
#include "sceneio/write_obj.h"

namespace raycast {
namespace {

void collect_profiles(const ObjectDesc& object, std::vector<const Curve*>& profiles) {
    if (object.kind == ObjectDesc::Kind::RevSurface) profiles.push_back(&object.curve);
    for (const ObjectDesc& child : object.children) collect_profiles(child, profiles);
}

struct Span {
    size_t begin, end;  // byte offsets of `RevSurface` and one past its closing brace
};

// Where each RevSurface block is in the text, in file order (the parser's order too).
std::vector<Span> rev_surface_spans(const std::string& text, const std::string& file) {
    std::vector<Span> spans;
    Lexer lexer(text, file);
    for (Token token = lexer.take(); !token.is_end(); token = lexer.take()) {
        if (!token.is("RevSurface")) continue;
        const int depth = lexer.depth();
        Token last = token;
        do {
            last = lexer.take();
        } while (!last.is_end() && !(last.is("}") && lexer.depth() == depth));
        spans.push_back({static_cast<size_t>(token.text.data() - text.data()),
                         static_cast<size_t>(last.text.data() - text.data()) + last.text.size()});
    }
    return spans;
}

std::string base_name(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

int count_option(const char* text, const char* name) {
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    if (*text == '\0' || *end != '\0' || value < 3 || value > 100000) {
        std::fprintf(stderr, "raycast_revolve: %s needs a whole number from 3 to 100000, got '%s'\n", name, text);
        std::exit(2);
    }
    return static_cast<int>(value);
}

int run(int argc, char** argv) {
    if (argc < 3) {
        std::fputs("usage: raycast_revolve SCENE OUTPUT.txt [--along N] [--around M]\n", stderr);
        return 2;
    }
    const std::string scene = argv[1], output = argv[2];
    int along = 256, around = 256;
    for (int i = 3; i < argc; ++i) {
        if (i + 1 < argc && std::strcmp(argv[i], "--along") == 0)
            along = count_option(argv[++i], "--along");
        else if (i + 1 < argc && std::strcmp(argv[i], "--around") == 0)
            around = count_option(argv[++i], "--around");
        else {
            std::fprintf(stderr, "raycast_revolve: unknown argument '%s'\n", argv[i]);
            return 2;
        }
    }
    // Each option alone may be 100000, but not both: 10^10 vertices would not fit in memory, nor
    // their numbers in an OBJ index. 2^24 vertices a surface is about a gigabyte of mesh in
    // memory, and its OBJ file some 3 GB.
    constexpr long long kMaxVertices = 1LL << 24;
    const long long vertices = (static_cast<long long>(along) + 1) * around;
    if (vertices > kMaxVertices) {
        std::fprintf(stderr,
                     "raycast_revolve: --along %d by --around %d makes %lld vertices a surface, more than the "
                     "limit of %lld\n",
                     along, around, vertices, kMaxVertices);
        return 2;
    }
    // Checked before any file is written: the output must not be the scene (its curves were
    // lost), its name must fit in the scene's quoted obj_file names, and its folder must take it
    // (the OBJ files, gigabytes, had been written before a failure to write the scene).
    struct stat scene_info, output_info;
    if (output == scene || (::stat(scene.c_str(), &scene_info) == 0 && ::stat(output.c_str(), &output_info) == 0 &&
                            scene_info.st_dev == output_info.st_dev && scene_info.st_ino == output_info.st_ino)) {
        std::fprintf(stderr, "raycast_revolve: OUTPUT '%s' is the scene itself: choose another name\n", output.c_str());
        return 2;
    }
    if (base_name(output).find_first_of("\"\n\r") != std::string::npos || base_name(output).empty()) {
        std::fprintf(stderr, "raycast_revolve: OUTPUT '%s' cannot name the meshes in the scene it writes: use a name "
                             "without quotes\n", output.c_str());
        return 2;
    }
    const size_t slash = output.find_last_of('/');
    const std::string folder = slash == std::string::npos ? "." : (slash == 0 ? "/" : output.substr(0, slash));
    if (::access(folder.c_str(), W_OK) != 0)
        throw InputError(output, "cannot write the scene: the folder '" + folder + "' " +
                                     (errno == ENOENT ? std::string("does not exist") : std::strerror(errno)));
    // As the parser reads it (classic Mac line breaks as LF: one byte for one, so the spans hold).
    std::string converted;
    const std::string text(as_unix_text(read_text_file(scene, "scene file", kMaxSceneFileBytes), converted));
    const SceneDesc desc = parse_scene(text, scene);
    std::vector<const Curve*> profiles;
    if (desc.root) collect_profiles(*desc.root, profiles);
    const std::vector<Span> spans = rev_surface_spans(text, scene);
    if (spans.size() != profiles.size()) throw InputError(scene, "could not find every RevSurface block in the text");
    std::string result = text;
    const std::string stem = output.size() > 4 && output.compare(output.size() - 4, 4, ".txt") == 0
                                 ? output.substr(0, output.size() - 4)
                                 : output;
    size_t triangles = 0;
    for (size_t k = profiles.size(); k-- > 0;) {
        const std::string obj = stem + ".rev" + std::to_string(k) + ".obj";
        const TriangleMesh mesh = tessellate_rev_surface(*profiles[k], along, around);
        write_obj_file(obj, mesh);
        triangles += mesh.triangle_count();
        result.replace(spans[k].begin, spans[k].end - spans[k].begin,
                       "TriangleMesh { obj_file \"" + base_name(obj) + "\" }");
    }
    write_file_atomically(output, std::string_view(result), "the scene");
    std::printf("raycast_revolve: %zu surfaces, %zu triangles (%d x %d each)\n", profiles.size(), triangles, along,
                around);
    return 0;
}

}  // namespace
}  // namespace raycast

int main(int argc, char** argv) {
    try {
        return raycast::run(argc, argv);
    } catch (const raycast::InputError& error) {
        for (const raycast::Diagnostic& d : error.diagnostics()) std::fputs(raycast::format_diagnostic(d).c_str(), stderr);
        return 1;
    } catch (const std::bad_alloc&) {
        std::fputs("raycast_revolve: error: out of memory\n", stderr);
        return 1;
    }
}
