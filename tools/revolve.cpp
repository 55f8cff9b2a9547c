// raycast_revolve: a scene's surfaces of revolution as triangle meshes, to compare the exact
// intersection with a tessellation (in speed and in looks) or to hand the scene to a renderer that
// only takes meshes.
//   raycast_revolve SCENE OUTPUT.txt [--along N] [--around M]
// Writes OUTPUT.txt, a copy of SCENE in which the k-th `RevSurface { ... }` (k = 0, 1, ... in file
// order) is replaced by `TriangleMesh { obj_file "OUTPUT.revK.obj" }`, and those OBJ files beside
// it, with the surface's analytic normals at the vertices: N steps of the profile's parameter
// (default 256) by M steps around the axis (default 256). Everything else is copied byte for byte,
// except, when OUTPUT is in another folder than SCENE, the scene's relative obj_file paths, which
// are rewritten to name the same files from OUTPUT's folder.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "base/command_line.h"
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

// A piece of the scene's text to replace: [begin, end) by `text`.
struct Edit {
    size_t begin, end;
    std::string text;
};

// The folder a path is in, made absolute and canonical ("" when it cannot be).
std::string canonical_folder(const std::string& path) {
    char* resolved = ::realpath(folder_of(path).c_str(), nullptr);
    if (!resolved) return {};
    std::string result(resolved);
    std::free(resolved);
    return result;
}

// `target` (absolute, canonical) as seen from the folder `from` (the same): "../mesh/a.obj".
std::string relative_to(const std::string& target, const std::string& from) {
    auto parts = [](const std::string& path) {
        std::vector<std::string> out;
        for (size_t at = 0; at < path.size();) {
            const size_t next = std::min(path.find('/', at), path.size());
            if (next > at) out.push_back(path.substr(at, next - at));
            at = next + 1;
        }
        return out;
    };
    const std::vector<std::string> to = parts(target), here = parts(from);
    size_t common = 0;
    while (common < to.size() && common < here.size() && to[common] == here[common]) ++common;
    std::string result;
    for (size_t i = common; i < here.size(); ++i) result += "../";
    for (size_t i = common; i < to.size(); ++i) result += (i > common ? "/" : "") + to[i];
    return result;
}

// The edits that keep the scene's own meshes found from OUTPUT's folder, which is not the scene's:
// a relative obj_file path names the file the scene loads now (load_scene's rule: as written,
// next to the scene, in its folder's parent), written relative to OUTPUT's folder (the file's own
// name kept, a link among them too). A path that names no file is copied as it is; one that
// cannot be written back (it would hold a quote or a line break) too, with a warning.
std::vector<Edit> mesh_path_edits(const std::string& text, const std::string& scene, const std::string& output) {
    std::vector<Edit> edits;
    const std::string output_folder = canonical_folder(output);
    if (output_folder.empty() || output_folder == canonical_folder(scene)) return edits;
    Lexer lexer(text, scene);
    for (Token token = lexer.take(); !token.is_end(); token = lexer.take()) {
        if (!token.is("obj_file")) continue;
        const Token path = lexer.take();
        std::string_view written = path.text;
        if (written.size() >= 2 && written.front() == '"' && written.back() == '"')
            written = written.substr(1, written.size() - 2);
        if (written.empty() || written.front() == '/' || written.front() == '"') continue;
        const std::string found = find_mesh_file(std::string(written), scene);
        const std::string folder = found.empty() ? std::string() : canonical_folder(found);
        if (folder.empty()) continue;
        const std::string moved = relative_to(folder + "/" + base_name(found), output_folder);
        if (moved == written) continue;
        if (moved.find_first_of("\"\n\r") != std::string::npos) {
            std::fprintf(stderr,
                         "%s:%d:%d: warning: obj_file %s is copied as it is: from %s's folder it would be '%s', "
                         "which a scene cannot quote\n",
                         scene.c_str(), path.line, path.column, quote_token(path.text).c_str(), output.c_str(),
                         moved.c_str());
            continue;
        }
        // Quoted where the lexer would end the token (its spaces, braces, a comment's #).
        const bool quoted = moved.find_first_of(" \t\v\f{}#") != std::string::npos;
        const size_t begin = static_cast<size_t>(path.text.data() - text.data());
        edits.push_back({begin, begin + path.text.size(), quoted ? "\"" + moved + "\"" : moved});
    }
    return edits;
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

constexpr const char* kUsage =
    "usage: raycast_revolve SCENE OUTPUT.txt [--along N] [--around M]\n"
    "Writes OUTPUT.txt, SCENE with each RevSurface replaced by a TriangleMesh, and the meshes beside it\n"
    "(OUTPUT.rev0.obj, OUTPUT.rev1.obj, ...): N steps along the profile by M around the axis, each\n"
    "from 3 to 100000 (default 256 and 256).\n";

int run(int argc, char** argv) {
    const std::vector<std::string> args = split_attached_values(argc, argv);  // "--along=8" as "--along 8"
    if (asks_for_help(args)) {
        std::fputs(kUsage, stdout);
        return 0;
    }
    if (args.size() < 2) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    const std::string scene = args[0], given_output = args[1];
    int along = 256, around = 256;
    for (size_t i = 2; i < args.size(); ++i) {
        if (i + 1 < args.size() && args[i] == "--along")
            along = count_option(args[++i].c_str(), "--along");
        else if (i + 1 < args.size() && args[i] == "--around")
            around = count_option(args[++i].c_str(), "--around");
        else if (args[i] == "--along" || args[i] == "--around") {
            std::fprintf(stderr, "raycast_revolve: %s needs a whole number from 3 to 100000\n", args[i].c_str());
            return 2;
        } else {
            std::fprintf(stderr, "raycast_revolve: unknown argument '%s'\n", args[i].c_str());
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
    // Checked before any file is written: the output must be a file (the meshes go beside it) and
    // not the scene (its curves were lost), its name must fit in the scene's quoted obj_file names,
    // and its folder must take it (the OBJ files, gigabytes, had been written before a failure to
    // write the scene). A link is written through (base/write_file.h), and the meshes go beside
    // the file it leads to.
    const WriteTarget destination = write_target(given_output);
    if (destination.in_place) {
        std::fprintf(stderr, "raycast_revolve: OUTPUT '%s' must be a file: the meshes are written beside it\n",
                     given_output.c_str());
        return 2;
    }
    if (destination.error != 0)
        throw InputError(given_output, std::string("cannot write the scene: ") + std::strerror(destination.error));
    const std::string& output = destination.file;
    struct stat scene_info, output_info;
    if (output == scene || (::stat(scene.c_str(), &scene_info) == 0 && ::stat(output.c_str(), &output_info) == 0 &&
                            scene_info.st_dev == output_info.st_dev && scene_info.st_ino == output_info.st_ino)) {
        std::fprintf(stderr, "raycast_revolve: OUTPUT '%s' is the scene itself: choose another name\n",
                     given_output.c_str());
        return 2;
    }
    if (base_name(output).find_first_of("\"\n\r") != std::string::npos || base_name(output).empty()) {
        std::fprintf(stderr, "raycast_revolve: OUTPUT '%s' cannot name the meshes in the scene it writes: use a name "
                             "without quotes\n", given_output.c_str());
        return 2;
    }
    const std::string folder = folder_of(output);
    if (::access(folder.c_str(), W_OK) != 0)
        throw InputError(given_output, "cannot write the scene: the folder '" + folder + "' " +
                                           (errno == ENOENT ? std::string("does not exist") : std::strerror(errno)));
    // As the parser reads it (classic Mac line breaks as LF: one byte for one, so the spans hold).
    std::string converted;
    const std::string text(as_unix_text(read_text_file(scene, "scene file", kMaxSceneFileBytes), converted));
    const SceneDesc desc = parse_scene(text, scene);
    std::vector<const Curve*> profiles;
    if (desc.root) collect_profiles(*desc.root, profiles);
    const std::vector<Span> spans = rev_surface_spans(text, scene);
    if (spans.size() != profiles.size()) throw InputError(scene, "could not find every RevSurface block in the text");
    std::vector<Edit> edits = mesh_path_edits(text, scene, output);
    const size_t moved_paths = edits.size();
    const std::string stem = output.size() > 4 && output.compare(output.size() - 4, 4, ".txt") == 0
                                 ? output.substr(0, output.size() - 4)
                                 : output;
    size_t triangles = 0;
    for (size_t k = profiles.size(); k-- > 0;) {
        const std::string obj = stem + ".rev" + std::to_string(k) + ".obj";
        const TriangleMesh mesh = tessellate_rev_surface(*profiles[k], along, around);
        write_obj_file(obj, mesh);
        triangles += mesh.triangle_count();
        edits.push_back({spans[k].begin, spans[k].end, "TriangleMesh { obj_file \"" + base_name(obj) + "\" }"});
    }
    // From the last to the first, so that each edit's offsets still hold.
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    std::string result = text;
    for (const Edit& edit : edits) result.replace(edit.begin, edit.end - edit.begin, edit.text);
    write_file_atomically(given_output, std::string_view(result), "the scene");
    std::printf("raycast_revolve: %zu surfaces, %zu triangles (%d x %d each)\n", profiles.size(), triangles, along,
                around);
    if (moved_paths > 0)
        std::printf("raycast_revolve: %zu mesh paths written relative to %s's folder\n", moved_paths,
                    given_output.c_str());
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
