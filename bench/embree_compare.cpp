// raycast_embree_bench: traces the primary rays of a raycast scene with Intel Embree 3, for the
// comparison in docs/performance.md (bench/run.sh runs it).
//   raycast_embree_bench SCENE [--size WxH] [--threads N] [--repeat N] [--expect-hit-fraction F]
// The scene file is read with raycast's own parser and OBJ loader, and every pixel's ray comes from
// raycast's make_camera/camera_ray, so Embree traces exactly the rays raycast traces. Embree builds
// with RTC_BUILD_QUALITY_HIGH on --threads threads; the rays are then traced on --threads
// std::threads that claim 16x16 tiles, twice: rtcIntersect1 one ray at a time, and rtcIntersect16
// over 4x4 pixel blocks. Only closest hits are computed (no shading). Each figure is the best of
// --repeat runs. Prints one line of key=value pairs; exits 3 when the hit fraction of
// rtcIntersect1 differs from --expect-hit-fraction (raycast's, at the 4 digits raycast prints).
// Embree's two paths need not agree to the ray: rtcIntersect16 may differ by a ray or two on
// silhouette edges, so packet16_hits is reported but not checked.
#include <embree3/rtcore.h>

#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "base/error.h"
#include "base/timer.h"
#include "math/mat4.h"
#include "scene/camera.h"
#include "sceneio/load_scene.h"

namespace {

using namespace raycast;

constexpr int kTile = 16;

struct Options {
    std::string scene_path;
    int width = 0, height = 0;
    int threads = 2;
    int repeat = 3;
    bool has_expected = false;
    double expected_hit_fraction = 0;
};

[[noreturn]] void usage(const char* message) {
    std::fprintf(stderr,
                 "raycast_embree_bench: %s\nusage: raycast_embree_bench SCENE [--size WxH] [--threads N] "
                 "[--repeat N] [--expect-hit-fraction F]\n",
                 message);
    std::exit(2);
}

Options parse_options(int argc, char** argv) {
    Options options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--size" && has_value) {
            if (std::sscanf(argv[++i], "%dx%d", &options.width, &options.height) != 2 || options.width < 1 ||
                options.height < 1)
                usage("--size needs WxH");
        } else if (arg == "--threads" && has_value) {
            options.threads = std::atoi(argv[++i]);
            if (options.threads < 1) usage("--threads needs a positive number");
        } else if (arg == "--repeat" && has_value) {
            options.repeat = std::atoi(argv[++i]);
            if (options.repeat < 1) usage("--repeat needs a positive number");
        } else if (arg == "--expect-hit-fraction" && has_value) {
            options.has_expected = true;
            options.expected_hit_fraction = std::atof(argv[++i]);
        } else if (!arg.empty() && arg[0] != '-' && options.scene_path.empty()) {
            options.scene_path = arg;
        } else {
            usage(("unknown or incomplete argument '" + arg + "'").c_str());
        }
    }
    if (options.scene_path.empty()) usage("no scene file given");
    return options;
}

// Embree's advice for its traversal kernels: denormals flushed to zero on every tracing thread.
void set_flush_to_zero() {
#if defined(__SSE2__)
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

// The scene's triangles in world space: groups flattened, transforms applied to the vertices.
struct WorldTriangles {
    std::vector<Vec3f> positions;
    std::vector<uint32_t> indices;
};

void flatten(const SceneDesc& desc, const ObjectDesc& object, const Mat4& world_from_object, WorldTriangles& out) {
    switch (object.kind) {
        case ObjectDesc::Kind::Group:
            for (const ObjectDesc& child : object.children) flatten(desc, child, world_from_object, out);
            return;
        case ObjectDesc::Kind::Transform:
            for (const ObjectDesc& child : object.children)
                flatten(desc, child, world_from_object * object.world_from_object, out);
            return;
        case ObjectDesc::Kind::Triangle: {
            const uint32_t base = static_cast<uint32_t>(out.positions.size());
            for (const Vec3f& v : object.vertices) out.positions.push_back(transform_point(world_from_object, v));
            out.indices.insert(out.indices.end(), {base, base + 1, base + 2});
            return;
        }
        case ObjectDesc::Kind::TriangleMesh: {
            const TriangleMesh& mesh = desc.meshes[static_cast<size_t>(object.mesh)].mesh;
            const uint32_t base = static_cast<uint32_t>(out.positions.size());
            const bool identity = world_from_object.is_identity();
            for (const Vec3f& p : mesh.positions)
                out.positions.push_back(identity ? p : transform_point(world_from_object, p));
            for (uint32_t index : mesh.indices) out.indices.push_back(base + index);
            return;
        }
        case ObjectDesc::Kind::Curve:
            return;  // draws nothing
        case ObjectDesc::Kind::Sphere:
        case ObjectDesc::Kind::Plane:
        case ObjectDesc::Kind::RevSurface:
            throw std::runtime_error(object.location.file + ":" + std::to_string(object.location.line) +
                                     ": only triangles are compared with Embree; this scene has a sphere, plane or "
                                     "surface of revolution");
    }
}

void report_embree_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "raycast_embree_bench: Embree error %d: %s\n", static_cast<int>(code), message);
    std::exit(1);
}

// Runs tile(index) for every 16x16 tile on `threads` std::threads (the caller's among them).
template <typename TileFn>
void for_each_tile(int width, int height, int threads, TileFn&& tile) {
    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    const int count = tiles_x * tiles_y;
    std::atomic<int> next{0};
    auto worker = [&](int worker_index) {
        set_flush_to_zero();
        for (int index = next++; index < count; index = next++) {
            const int x0 = (index % tiles_x) * kTile, y0 = (index / tiles_x) * kTile;
            tile(x0, y0, std::min(width, x0 + kTile), std::min(height, y0 + kTile), worker_index);
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (std::thread& thread : pool) thread.join();
}

struct TraceResult {
    double ms = 0;
    uint64_t hits = 0;
};

// Per-thread hit counters, each on its own cache line.
struct alignas(64) Counter {
    uint64_t hits = 0;
};

TraceResult trace_single(RTCScene scene, const Camera& camera, int threads) {
    std::vector<Counter> counters(static_cast<size_t>(threads));
    Timer timer;
    for_each_tile(camera.width, camera.height, threads, [&](int x0, int y0, int x1, int y1, int worker) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        uint64_t hits = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const Ray ray = camera_ray(camera, static_cast<float>(x) + camera.pixel_offset,
                                           static_cast<float>(y) + camera.pixel_offset);
                RTCRayHit rh;
                rh.ray.org_x = ray.origin.x;
                rh.ray.org_y = ray.origin.y;
                rh.ray.org_z = ray.origin.z;
                rh.ray.dir_x = ray.direction.x;
                rh.ray.dir_y = ray.direction.y;
                rh.ray.dir_z = ray.direction.z;
                rh.ray.tnear = std::max(camera.t_min, 0.0f);
                rh.ray.tfar = INFINITY;
                rh.ray.time = 0;
                rh.ray.mask = 0xffffffffu;
                rh.ray.id = 0;
                rh.ray.flags = 0;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(scene, &context, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
            }
        counters[static_cast<size_t>(worker)].hits += hits;
    });
    TraceResult result;
    result.ms = timer.elapsed_ms();
    for (const Counter& c : counters) result.hits += c.hits;
    return result;
}

TraceResult trace_packets16(RTCScene scene, const Camera& camera, int threads) {
    std::vector<Counter> counters(static_cast<size_t>(threads));
    Timer timer;
    for_each_tile(camera.width, camera.height, threads, [&](int x0, int y0, int x1, int y1, int worker) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        alignas(64) RTCRayHit16 rh;
        alignas(64) int valid[16];
        uint64_t hits = 0;
        for (int by = y0; by < y1; by += 4)
            for (int bx = x0; bx < x1; bx += 4) {
                for (int lane = 0; lane < 16; ++lane) {
                    const int x = bx + lane % 4, y = by + lane / 4;
                    const bool inside = x < x1 && y < y1;
                    valid[lane] = inside ? -1 : 0;
                    const Ray ray = camera_ray(camera, static_cast<float>(inside ? x : bx) + camera.pixel_offset,
                                               static_cast<float>(inside ? y : by) + camera.pixel_offset);
                    rh.ray.org_x[lane] = ray.origin.x;
                    rh.ray.org_y[lane] = ray.origin.y;
                    rh.ray.org_z[lane] = ray.origin.z;
                    rh.ray.dir_x[lane] = ray.direction.x;
                    rh.ray.dir_y[lane] = ray.direction.y;
                    rh.ray.dir_z[lane] = ray.direction.z;
                    rh.ray.tnear[lane] = std::max(camera.t_min, 0.0f);
                    rh.ray.tfar[lane] = INFINITY;
                    rh.ray.time[lane] = 0;
                    rh.ray.mask[lane] = 0xffffffffu;
                    rh.ray.id[lane] = 0;
                    rh.ray.flags[lane] = 0;
                    rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect16(valid, scene, &context, &rh);
                for (int lane = 0; lane < 16; ++lane)
                    hits += valid[lane] && rh.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
            }
        counters[static_cast<size_t>(worker)].hits += hits;
    });
    TraceResult result;
    result.ms = timer.elapsed_ms();
    for (const Counter& c : counters) result.hits += c.hits;
    return result;
}

template <typename TraceFn>
TraceResult best_of(int repeat, TraceFn&& trace) {
    TraceResult best = trace();
    for (int i = 1; i < repeat; ++i) {
        const TraceResult next = trace();
        if (next.hits != best.hits) throw std::runtime_error("two runs of the same rays found different hits");
        best.ms = std::min(best.ms, next.ms);
    }
    return best;
}

int run(const Options& options) {
    set_flush_to_zero();
    Timer load_timer;
    SceneLoadOptions load_options;
    load_options.threads = options.threads;
    SceneDesc desc = load_scene_file(options.scene_path, load_options);
    const double load_ms = load_timer.elapsed_ms();
    if (!desc.camera) throw std::runtime_error(options.scene_path + ": the scene has no camera");
    const int width = options.width > 0 ? options.width : desc.camera->width;
    const int height = options.height > 0 ? options.height : desc.camera->height;
    if (width < 1 || height < 1) throw std::runtime_error(options.scene_path + ": no image size: give --size WxH");
    const Camera camera = make_camera(*desc.camera, width, height, Conventions::course());

    // Building: copying the world-space triangles into Embree's buffers, then the BVH build. The
    // device's thread count is Embree's TBB arena for the build; tracing runs on our own threads.
    const std::string config = "threads=" + std::to_string(options.threads);
    RTCDevice device = rtcNewDevice(config.c_str());
    if (!device) throw std::runtime_error("rtcNewDevice failed");
    rtcSetDeviceErrorFunction(device, report_embree_error, nullptr);
    Timer build_timer;
    WorldTriangles world;
    if (desc.root) flatten(desc, *desc.root, Mat4{}, world);
    desc = SceneDesc{};  // the meshes live in Embree's buffers from here on
    const size_t triangle_count = world.indices.size() / 3;
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    if (triangle_count > 0) {
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), world.positions.size()));
        for (size_t i = 0; i < world.positions.size(); ++i) {
            vertices[3 * i] = world.positions[i].x;
            vertices[3 * i + 1] = world.positions[i].y;
            vertices[3 * i + 2] = world.positions[i].z;
        }
        auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangle_count));
        std::memcpy(indices, world.indices.data(), world.indices.size() * sizeof(uint32_t));
        world = WorldTriangles{};
        rtcCommitGeometry(geometry);
        rtcAttachGeometry(scene, geometry);
        rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene);
    const double build_ms = build_timer.elapsed_ms();

    const int threads = options.threads;
    const TraceResult single = best_of(options.repeat, [&] { return trace_single(scene, camera, threads); });
    const TraceResult packets = best_of(options.repeat, [&] { return trace_packets16(scene, camera, threads); });
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);

    const double rays = static_cast<double>(width) * static_cast<double>(height);
    const double hit_fraction = static_cast<double>(single.hits) / rays;
    // raycast prints its hit fraction rounded to 4 digits: equal means equal at that precision.
    const bool match = !options.has_expected || std::fabs(hit_fraction - options.expected_hit_fraction) < 0.00006;
    std::printf("embree-bench embree=%s triangles=%zu threads=%d size=%dx%d load_ms=%.3f build_ms=%.3f "
                "single_ms=%.3f single_mrays_per_s=%.3f packet16_ms=%.3f packet16_mrays_per_s=%.3f rays=%.0f "
                "hits=%llu packet16_hits=%llu hit_fraction=%.4f",
                RTC_VERSION_STRING, triangle_count, threads, width, height, load_ms, build_ms, single.ms,
                rays / (single.ms * 1000), packets.ms, rays / (packets.ms * 1000), rays,
                static_cast<unsigned long long>(single.hits), static_cast<unsigned long long>(packets.hits),
                hit_fraction);
    if (options.has_expected)
        std::printf(" expected_hit_fraction=%.4f hit_match=%s", options.expected_hit_fraction, match ? "yes" : "no");
    std::printf("\n");
    if (!match)
        std::fprintf(stderr, "raycast_embree_bench: hit fraction %.6f differs from raycast's %.4f\n", hit_fraction,
                     options.expected_hit_fraction);
    return match ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
    const Options options = parse_options(argc, argv);
    try {
        return run(options);
    } catch (const InputError& error) {
        for (const Diagnostic& d : error.diagnostics()) std::fputs(format_diagnostic(d).c_str(), stderr);
        return 1;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "raycast_embree_bench: %s\n", error.what());
        return 1;
    }
}
