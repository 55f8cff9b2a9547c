// raycast_tinyobj_bench: how long tinyobjloader takes to load an OBJ file, next to raycast's own
// loader (sceneio/load_obj.h) on the same file in the same process, for docs/performance.md.
//   raycast_tinyobj_bench OBJ [--repeat N] [--threads N]
// tinyobjloader (single-threaded, triangulating) is compiled here with the project's flags. Each
// figure is the best of --repeat loads (default 3) of a file already in the page cache (an untimed
// read comes first). raycast is timed on 1 thread and on --threads threads (default 2). Prints one
// line of key=value pairs.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/timer.h"
#include "sceneio/load_obj.h"

namespace {

// Loads with tinyobjloader; returns the triangle count (faces are triangulated as fans).
size_t load_with_tinyobj(const std::string& path) {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warnings, errors;
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, path.c_str(), nullptr, true))
        throw std::runtime_error("tinyobjloader cannot load " + path + ": " + errors);
    size_t triangles = 0;
    for (const tinyobj::shape_t& shape : shapes) triangles += shape.mesh.num_face_vertices.size();
    return triangles;
}

template <typename LoadFn>
double best_ms(int repeat, LoadFn&& load) {
    double best = 0;
    for (int i = 0; i < repeat; ++i) {
        raycast::Timer timer;
        load();
        const double ms = timer.elapsed_ms();
        best = i == 0 ? ms : std::min(best, ms);
    }
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path;
    int repeat = 3, threads = 2;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--repeat" && i + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++i]));
        } else if (arg == "--threads" && i + 1 < argc) {
            threads = std::max(1, std::atoi(argv[++i]));
        } else if (path.empty() && !arg.empty() && arg[0] != '-') {
            path = arg;
        } else {
            std::fputs("usage: raycast_tinyobj_bench OBJ [--repeat N] [--threads N]\n", stderr);
            return 2;
        }
    }
    if (path.empty()) {
        std::fputs("usage: raycast_tinyobj_bench OBJ [--repeat N] [--threads N]\n", stderr);
        return 2;
    }
    try {
        {
            // Brings the file into the page cache, so that no loader pays for the disk.
            std::ifstream file(path, std::ios::binary);
            std::vector<char> block(1 << 20);
            while (file.read(block.data(), static_cast<std::streamsize>(block.size())) || file.gcount() > 0) {
            }
        }
        size_t tinyobj_triangles = 0, raycast_triangles = 0;
        const double tinyobj_ms = best_ms(repeat, [&] { tinyobj_triangles = load_with_tinyobj(path); });
        raycast::ObjLoadOptions one;
        one.threads = 1;
        const double raycast_1t_ms =
            best_ms(repeat, [&] { raycast_triangles = raycast::load_obj_file(path, one).triangle_count(); });
        raycast::ObjLoadOptions many;
        many.threads = threads;
        const double raycast_nt_ms = best_ms(repeat, [&] { raycast::load_obj_file(path, many); });
        if (tinyobj_triangles != raycast_triangles)
            std::fprintf(stderr, "raycast_tinyobj_bench: tinyobjloader read %zu triangles, raycast %zu\n",
                         tinyobj_triangles, raycast_triangles);
        std::printf("tinyobj-bench triangles=%zu tinyobj_ms=%.3f raycast_1t_ms=%.3f raycast_threads=%d "
                    "raycast_ms=%.3f speedup_1t=%.2f speedup=%.2f\n",
                    raycast_triangles, tinyobj_ms, raycast_1t_ms, threads, raycast_nt_ms, tinyobj_ms / raycast_1t_ms,
                    tinyobj_ms / raycast_nt_ms);
        return tinyobj_triangles == raycast_triangles ? 0 : 3;
    } catch (const raycast::InputError& error) {
        for (const raycast::Diagnostic& d : error.diagnostics()) std::fputs(raycast::format_diagnostic(d).c_str(), stderr);
        return 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "raycast_tinyobj_bench: %s\n", error.what());
        return 1;
    }
}
