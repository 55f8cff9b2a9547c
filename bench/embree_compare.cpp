// raycast_embree_bench: traces the rays of a raycast scene with Intel Embree 3 and, with --raycast,
// the same kinds of rays with raycast's own queries, for docs/performance.md (bench/run.sh runs it).
//   raycast_embree_bench SCENE [--size WxH] [--threads N] [--repeat N] [--expect-hit-fraction F]
//                              [--ao-rays N] [--raycast]
// The scene file is read with raycast's own parser and OBJ loader, and every pixel's ray comes from
// raycast's make_camera/camera_ray, so Embree traces exactly the rays raycast traces. Embree builds
// with RTC_BUILD_QUALITY_HIGH on --threads threads; the rays are then traced on --threads
// threads (raycast's parallel_for) that claim 64x64 tiles:
//   - primary rays, closest hit: rtcIntersect1 one ray at a time, rtcIntersect16 over 4x4 blocks;
//   - ambient-occlusion rays, any hit: from each primary hit, --ao-rays (16) cosine-distributed
//     directions about the geometric normal (facing the camera), drawn as raycast's --mode ao
//     draws them (a hit's directions together, in vector loops), from the hit point moved off the
//     surface as raycast moves shadow-ray origins, up to a tenth of the scene box's diagonal;
//     rtcOccluded1 one at a time, rtcOccluded16 the rays of one hit together. The "all rays"
//     figure counts primary and AO rays over the time of both passes.
// Nothing is shaded. Each figure is the best of --repeat runs. With --raycast, Embree's scene is
// released, the scene is loaded again and built by build_scene, and the same passes run through
// raycast's intersect/occluded (one ray at a time) and PacketTracer (packets: camera rays in 8x8
// blocks of four 4x4 packets, which walk the BVH together as the renderer's do), plus shadow rays
// towards the scene's first light (one ray at a time, and each primary packet's together).
// With --paired N, neither of the above: both scenes stay in memory, and N pairs of passes compare
// Embree's rays with raycast's renders as the command line makes them (shaded, an image written to
// memory): rtcIntersect1 with --no-packets, rtcIntersect1 + rtcOccluded1 with --mode ao, and
// rtcIntersect16 with the packet render. The two passes of a pair run a moment apart (each after a
// rest of 60 ms and an untimed pass of its own: pass_at_rest), the first of them in turn, so that
// the machine's drift over minutes (10-30% on a shared virtual machine) falls on both; each pair
// gives the ratio of raycast's Mrays/s to Embree's.
// Prints key=value pairs (one line); exits 3 when the hit fraction of rtcIntersect1 differs from
// --expect-hit-fraction (raycast's, at the 4 digits raycast prints). Embree's two paths need not
// agree to the ray: rtcIntersect16 may differ by a ray or two on silhouette edges, so
// packet16_hits is reported but not checked; raycast's paths must agree exactly (exit 4 if not).
#include <embree3/rtcore.h>

#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "base/error.h"
#include "base/parallel.h"
#include "base/timer.h"
#include "math/mat4.h"
#include "render/render.h"
#include "render/sampler.h"
#include "render/shade.h"
#include "scene/build_scene.h"
#include "scene/camera.h"
#include "scene/intersect_packet.h"
#include "sceneio/load_scene.h"

namespace {

using namespace raycast;

// raycast's own tile size at 1024x1024 (render.h's automatic_tile_size). Both sides gain from
// tiles larger than 16: on this benchmark's machine Embree's 1M figures were 1.03-1.09x higher
// with 64 than with 16, raycast's renders 1.04-1.12x.
constexpr int kTile = 64;
// The most AO rays a hit may have (--ao-rays).
constexpr int kMaxAoRays = 64;

struct Options {
    std::string scene_path;
    int width = 0, height = 0;
    int threads = 2;
    int repeat = 3;
    int ao_rays = 16;
    int paired = 0;  ///< pairs of passes in the --paired comparison (0: the passes above instead)
    bool trace_raycast = false;
    bool has_expected = false;
    double expected_hit_fraction = 0;
};

[[noreturn]] void usage(const char* message) {
    std::fprintf(stderr,
                 "raycast_embree_bench: %s\nusage: raycast_embree_bench SCENE [--size WxH] [--threads N] "
                 "[--repeat N] [--expect-hit-fraction F] [--ao-rays N] [--raycast | --paired N]\n",
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
        } else if (arg == "--ao-rays" && has_value) {
            options.ao_rays = std::atoi(argv[++i]);
            if (options.ao_rays < 1 || options.ao_rays > kMaxAoRays)
                usage(("--ao-rays needs a number from 1 to " + std::to_string(kMaxAoRays)).c_str());
        } else if (arg == "--paired" && has_value) {
            options.paired = std::atoi(argv[++i]);
            if (options.paired < 1) usage("--paired needs a positive number of pairs");
        } else if (arg == "--raycast") {
            options.trace_raycast = true;
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
    if (options.paired > 0 && options.trace_raycast) usage("--paired and --raycast are two different runs");
    return options;
}

// Embree's advice for its traversal kernels: denormals flushed to zero on every tracing thread.
// raycast's command line renders with them off.
void set_flush_to_zero(bool on = true) {
#if defined(__SSE2__)
    _MM_SET_FLUSH_ZERO_MODE(on ? _MM_FLUSH_ZERO_ON : _MM_FLUSH_ZERO_OFF);
    _MM_SET_DENORMALS_ZERO_MODE(on ? _MM_DENORMALS_ZERO_ON : _MM_DENORMALS_ZERO_OFF);
#else
    (void)on;
#endif
}

// This thread's flush-to-zero mode for a scope, put back after it: Embree's tiles and raycast's
// renders share raycast's threads (for_each_tile), and each must find the mode it runs with.
class FlushToZeroScope {
public:
    explicit FlushToZeroScope(bool on) { set_flush_to_zero(on); }
    ~FlushToZeroScope() {
#if defined(__SSE2__)
        _mm_setcsr(saved_);
#endif
    }
    FlushToZeroScope(const FlushToZeroScope&) = delete;
    FlushToZeroScope& operator=(const FlushToZeroScope&) = delete;

private:
#if defined(__SSE2__)
    unsigned saved_ = _mm_getcsr();
#endif
};

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

// Runs tile(x0, y0, x1, y1, worker) for every kTile x kTile tile on `threads` threads: raycast's
// own (base/parallel.h), so that both sides' passes get their threads alike (kept from one pass
// to the next, awake for a while after one). Starting std::threads in every pass had put their
// start, and the wait for an idle processor to wake, into Embree's times only. Each tile runs
// with flush-to-zero and denormals-are-zero, as Embree asks (FlushToZeroScope).
template <typename TileFn>
void for_each_tile(int width, int height, int threads, TileFn&& tile) {
    const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;
    const size_t count = static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y);
    parallel_for(count, threads, [&](size_t item, int worker) {
        const int index = static_cast<int>(item);
        const int x0 = (index % tiles_x) * kTile, y0 = (index / tiles_x) * kTile;
        const FlushToZeroScope embree_mode(true);
        tile(x0, y0, std::min(width, x0 + kTile), std::min(height, y0 + kTile), worker);
    });
}

struct TraceResult {
    double ms = 0;
    uint64_t hits = 0;  // primary rays that hit
    uint64_t rays = 0;  // every ray traced: primary, and any ambient-occlusion or shadow rays
};

// Per-thread totals, each on its own cache line.
struct alignas(64) Counter {
    uint64_t hits = 0, rays = 0;
};

// Times one pass over the image: tile(x0, y0, x1, y1, counter) for every tile, on `threads`.
template <typename TileFn>
TraceResult timed_pass(const Camera& camera, int threads, TileFn&& tile) {
    std::vector<Counter> counters(static_cast<size_t>(threads));
    Timer timer;
    for_each_tile(camera.width, camera.height, threads, [&](int x0, int y0, int x1, int y1, int worker) {
        tile(x0, y0, x1, y1, counters[static_cast<size_t>(worker)]);
    });
    TraceResult result;
    result.ms = timer.elapsed_ms();
    for (const Counter& c : counters) {
        result.hits += c.hits;
        result.rays += c.rays;
    }
    return result;
}

template <typename TraceFn>
TraceResult best_of(int repeat, TraceFn&& trace) {
    TraceResult best = trace();
    for (int i = 1; i < repeat; ++i) {
        const TraceResult next = trace();
        if (next.hits != best.hits || next.rays != best.rays)
            throw std::runtime_error("two runs of the same rays found different hits");
        best.ms = std::min(best.ms, next.ms);
    }
    return best;
}

double mrays_per_s(const TraceResult& r) { return static_cast<double>(r.rays) / (r.ms * 1000); }

Ray pixel_ray(const Camera& camera, int x, int y) {
    return camera_ray(camera, static_cast<float>(x) + camera.pixel_offset, static_cast<float>(y) + camera.pixel_offset);
}

// Packets of neighbouring pixels, as raycast's renderer forms them: 4x4 for 16 lanes, 2x4 for 8,
// 2x2 for 4, in blocks of `packets` such packets (1, or 4 side by side in 2x2: an 8x8 block of
// 4x4 packets). Calls block(pixel_x, pixel_y, count) for every block of the tile, the pixels
// packet by packet, row by row within a packet.
template <typename BlockFn>
void for_each_block(int x0, int y0, int x1, int y1, int lanes, int packets, BlockFn&& block) {
    const int packet_w = lanes >= 16 ? 4 : (lanes >= 4 ? 2 : 1);
    const int packet_h = lanes / packet_w;
    const int across = packets >= 4 ? 2 : 1, down = packets >= 4 ? 2 : 1;
    const int block_w = packet_w * across, block_h = packet_h * down;
    int xs[64], ys[64];
    for (int by = y0; by < y1; by += block_h)
        for (int bx = x0; bx < x1; bx += block_w) {
            int count = 0;
            for (int py = by; py < std::min(by + block_h, y1); py += packet_h)
                for (int px = bx; px < std::min(bx + block_w, x1); px += packet_w)
                    for (int y = py; y < std::min(py + packet_h, y1); ++y)
                        for (int x = px; x < std::min(px + packet_w, x1); ++x) {
                            xs[count] = x;
                            ys[count] = y;
                            ++count;
                        }
            block(xs, ys, count);
        }
}

// Ambient-occlusion rays: the same distribution for both tracers

// The `count` AO rays (at most kMaxAoRays) of pixel `pixel`'s hit at `position` with unit normal
// `normal` (facing the viewer), drawn as raycast's --mode ao draws them
// (ambient_occlusion_radiance, render/integrators.cpp), for both tracers alike: the numbers of
// camera sample 0's Sampler, the directions made together by sample_cosine_hemisphere_n (vector
// loops), each ray starting at the hit moved off the surface by offset_ray_origin_by (along
// `normal`, to the side of the ray; --mode ao moves it along the geometric normal, the same line
// on the bench's meshes, which have no vertex normals).
// `travel_scale` is ray_travel_scale of the camera ray: what raycast's hit_travel_scale gives for
// the bench's meshes, whose corners (within about 1.1 of the origin) are smaller than the camera
// ray's travel.
void ao_rays_of_hit(Vec3f position, Vec3f normal, float travel_scale, uint32_t pixel, int count, Ray* rays) {
    if (count < 1 || count > kMaxAoRays) throw std::logic_error("ao_rays_of_hit: count outside 1..kMaxAoRays");
    float u0[kMaxAoRays], u1[kMaxAoRays], dx[kMaxAoRays], dy[kMaxAoRays], dz[kMaxAoRays];
    Sampler sampler(pixel, 0);
    sampler.next_2d_n(count, u0, u1);
    sample_cosine_hemisphere_n(HemisphereBasis(normal), count, u0, u1, dx, dy, dz);
    const float offset = ray_offset_distance(position, travel_scale);
    for (int i = 0; i < count; ++i) {
        const Vec3f direction{dx[i], dy[i], dz[i]};
        rays[i] = {offset_ray_origin_by(position, normal, direction, offset), direction};
    }
}

// A unit normal turned to face where the ray came from.
Vec3f facing(Vec3f normal, const Ray& ray) {
    const Vec3f n = normalize(normal);
    return dot(n, ray.direction) > 0 ? -n : n;
}

// ---------------------------------------------------------------------------------------------
// Embree

void init_ray(RTCRay& ray, const Ray& r, float t_near, float t_far) {
    ray.org_x = r.origin.x;
    ray.org_y = r.origin.y;
    ray.org_z = r.origin.z;
    ray.dir_x = r.direction.x;
    ray.dir_y = r.direction.y;
    ray.dir_z = r.direction.z;
    ray.tnear = t_near;
    ray.tfar = t_far;
    ray.time = 0;
    ray.mask = 0xffffffffu;
    ray.id = 0;
    ray.flags = 0;
}

void init_ray16(RTCRay16& rays, int lane, const Ray& r, float t_near, float t_far) {
    rays.org_x[lane] = r.origin.x;
    rays.org_y[lane] = r.origin.y;
    rays.org_z[lane] = r.origin.z;
    rays.dir_x[lane] = r.direction.x;
    rays.dir_y[lane] = r.direction.y;
    rays.dir_z[lane] = r.direction.z;
    rays.tnear[lane] = t_near;
    rays.tfar[lane] = t_far;
    rays.time[lane] = 0;
    rays.mask[lane] = 0xffffffffu;
    rays.id[lane] = 0;
    rays.flags[lane] = 0;
}

// Primary rays are traced as coherent, AO rays as incoherent, as Embree advises.
struct EmbreeContexts {
    RTCIntersectContext coherent, incoherent;

    EmbreeContexts() {
        rtcInitIntersectContext(&coherent);
        coherent.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        rtcInitIntersectContext(&incoherent);
    }
};

struct EmbreePasses {
    RTCScene scene;
    const Camera& camera;
    int threads;
    int ao_rays;
    float ao_length;

    // One ray at a time: primary rays, and the AO rays of each hit when `with_ao`.
    TraceResult single(bool with_ao) const {
        return timed_pass(camera, threads, [&](int x0, int y0, int x1, int y1, Counter& counter) {
            EmbreeContexts contexts;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const Ray ray = pixel_ray(camera, x, y);
                    RTCRayHit rh;
                    init_ray(rh.ray, ray, std::max(camera.t_min, 0.0f), INFINITY);
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(scene, &contexts.coherent, &rh);
                    ++counter.rays;
                    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
                    ++counter.hits;
                    if (!with_ao) continue;
                    const Vec3f position = ray.origin + ray.direction * rh.ray.tfar;
                    const Vec3f normal = facing({rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z}, ray);
                    const float travel = ray_travel_scale(ray.origin, ray.direction, rh.ray.tfar);
                    const uint32_t pixel = static_cast<uint32_t>(y * camera.width + x);
                    Ray probes[kMaxAoRays];
                    ao_rays_of_hit(position, normal, travel, pixel, ao_rays, probes);
                    for (int i = 0; i < ao_rays; ++i) {
                        RTCRay shadow;
                        init_ray(shadow, probes[i], 0, ao_length);
                        rtcOccluded1(scene, &contexts.incoherent, &shadow);
                    }
                    counter.rays += static_cast<uint64_t>(ao_rays);
                }
        });
    }

    // 4x4 blocks with rtcIntersect16, and the AO rays of each hit with rtcOccluded16.
    TraceResult packets(bool with_ao) const {
        return timed_pass(camera, threads, [&](int x0, int y0, int x1, int y1, Counter& counter) {
            EmbreeContexts contexts;
            alignas(64) RTCRayHit16 rh;
            alignas(64) RTCRay16 shadow;
            alignas(64) int valid[16];
            Ray rays[16];
            for_each_block(x0, y0, x1, y1, 16, 1, [&](const int* xs, const int* ys, int count) {
                for (int lane = 0; lane < 16; ++lane) {
                    valid[lane] = lane < count ? -1 : 0;
                    rays[lane] = pixel_ray(camera, xs[lane < count ? lane : 0], ys[lane < count ? lane : 0]);
                    init_ray16(rh.ray, lane, rays[lane], std::max(camera.t_min, 0.0f), INFINITY);
                    rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
                }
                rtcIntersect16(valid, scene, &contexts.coherent, &rh);
                counter.rays += static_cast<uint64_t>(count);
                for (int lane = 0; lane < count; ++lane) {
                    if (rh.hit.geomID[lane] == RTC_INVALID_GEOMETRY_ID) continue;
                    ++counter.hits;
                    if (!with_ao) continue;
                    const Ray& ray = rays[lane];
                    const Vec3f position = ray.origin + ray.direction * rh.ray.tfar[lane];
                    const Vec3f normal = facing({rh.hit.Ng_x[lane], rh.hit.Ng_y[lane], rh.hit.Ng_z[lane]}, ray);
                    const float travel = ray_travel_scale(ray.origin, ray.direction, rh.ray.tfar[lane]);
                    const uint32_t pixel = static_cast<uint32_t>(ys[lane] * camera.width + xs[lane]);
                    Ray probes[kMaxAoRays];
                    ao_rays_of_hit(position, normal, travel, pixel, ao_rays, probes);
                    for (int first = 0; first < ao_rays; first += 16) {
                        alignas(64) int ao_valid[16];
                        for (int i = 0; i < 16; ++i) {
                            const bool live = first + i < ao_rays;
                            ao_valid[i] = live ? -1 : 0;
                            init_ray16(shadow, i, probes[live ? first + i : first], 0, ao_length);
                        }
                        rtcOccluded16(ao_valid, scene, &contexts.incoherent, &shadow);
                    }
                    counter.rays += static_cast<uint64_t>(ao_rays);
                }
            });
        });
    }
};

// ---------------------------------------------------------------------------------------------
// raycast

struct RaycastPasses {
    const Scene& scene;
    const PacketTracer& tracer;
    const Camera& camera;
    int threads;
    int ao_rays;
    float ao_length;

    // What the extra rays of a primary hit are: none, AO rays, or a shadow ray to the first light.
    enum class Extra { None, Ao, Shadow };

    // One ray at a time through intersect() and occluded().
    TraceResult single(Extra extra) const {
        return timed_pass(camera, threads, [&](int x0, int y0, int x1, int y1, Counter& counter) {
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const Ray ray = pixel_ray(camera, x, y);
                    Hit hit;
                    intersect(scene, ray, camera.t_min, hit);
                    ++counter.rays;
                    if (!hit.is_hit()) continue;
                    ++counter.hits;
                    if (extra == Extra::None) continue;
                    const SurfacePoint surface = surface_at(scene, ray, hit);
                    const Vec3f normal = facing(surface.normal, ray);
                    const float travel = ray_travel_scale(ray.origin, ray.direction, hit.t);
                    if (extra == Extra::Shadow) {
                        const Illumination light = illuminate(scene.lights[0], surface.position);
                        occluded(scene, {offset_ray_origin(surface.position, normal, light.to_light, travel), light.to_light}, 0,
                                 light.distance);
                        ++counter.rays;
                        continue;
                    }
                    const uint32_t pixel = static_cast<uint32_t>(y * camera.width + x);
                    Ray probes[kMaxAoRays];
                    ao_rays_of_hit(surface.position, normal, travel, pixel, ao_rays, probes);
                    for (int i = 0; i < ao_rays; ++i) occluded(scene, probes[i], 0, ao_length);
                    counter.rays += static_cast<uint64_t>(ao_rays);
                }
        });
    }

    // Packets of neighbouring pixels through PacketTracer: primary rays, then the AO rays of each
    // hit (lanes() at a time), or the shadow rays of the packet's hits together.
    TraceResult packets(Extra extra) const {
        const int lanes = tracer.lanes();
        return timed_pass(camera, threads, [&](int x0, int y0, int x1, int y1, Counter& counter) {
            constexpr int kBlockRays = kMaxSharedPackets * kMaxPacketLanes;
            Ray rays[kBlockRays], extra_rays[kMaxPacketLanes];
            Hit hits[kBlockRays];
            float t_max[kMaxPacketLanes];
            bool blocked[kMaxPacketLanes];
            // Blocks of kMaxSharedPackets packets, traced together as the renderer traces them.
            for_each_block(x0, y0, x1, y1, lanes, kMaxSharedPackets, [&](const int* xs, const int* ys, int count) {
                for (int k = 0; k < count; ++k) {
                    rays[k] = pixel_ray(camera, xs[k], ys[k]);
                    hits[k] = Hit{};
                }
                tracer.intersect_packets(rays, count, camera.t_min, hits);
                counter.rays += static_cast<uint64_t>(count);
                for (int first = 0; first < count; first += lanes) {  // then each packet's extra rays
                    int shadows = 0;
                    for (int k = first; k < std::min(count, first + lanes); ++k) {
                        if (!hits[k].is_hit()) continue;
                        ++counter.hits;
                        if (extra == Extra::None) continue;
                        const SurfacePoint surface = surface_at(scene, rays[k], hits[k]);
                        const Vec3f normal = facing(surface.normal, rays[k]);
                        const float travel = ray_travel_scale(rays[k].origin, rays[k].direction, hits[k].t);
                        if (extra == Extra::Shadow) {
                            const Illumination light = illuminate(scene.lights[0], surface.position);
                            extra_rays[shadows] = {offset_ray_origin(surface.position, normal, light.to_light, travel),
                                                   light.to_light};
                            t_max[shadows++] = light.distance;
                            continue;
                        }
                        const uint32_t pixel = static_cast<uint32_t>(ys[k] * camera.width + xs[k]);
                        Ray probes[kMaxAoRays];
                        ao_rays_of_hit(surface.position, normal, travel, pixel, ao_rays, probes);
                        for (int i = 0; i < lanes; ++i) t_max[i] = ao_length;
                        for (int i0 = 0; i0 < ao_rays; i0 += lanes)
                            tracer.occluded(probes + i0, std::min(lanes, ao_rays - i0), 0, t_max, blocked);
                        counter.rays += static_cast<uint64_t>(ao_rays);
                    }
                    if (shadows > 0) {
                        tracer.occluded(extra_rays, shadows, 0, t_max, blocked);
                        counter.rays += static_cast<uint64_t>(shadows);
                    }
                }
            });
        });
    }
};

// ---------------------------------------------------------------------------------------------
// --paired: Embree's passes and raycast's renders, a moment apart

// One render as `raycast SCENE OUT --stats` makes it (the colour image only, in memory): its
// render_ms and rays= as TraceResult's ms and rays, and the camera rays that hit.
TraceResult render_pass(const Scene& scene, const RenderOptions& options) {
    // The calling thread has Embree's mode from the start of the run; the helpers have it only
    // inside Embree's tiles.
    const FlushToZeroScope command_line_mode(false);
    RenderStats stats;
    render_frame_rgb8(scene, options, FrameRequest{}, &stats);
    TraceResult result;
    result.ms = stats.milliseconds;
    result.rays = stats.rays;
    result.hits = stats.hits;
    return result;
}

// Each pass of a pair starts with the other's threads at rest, and right after an untimed pass of
// its own. raycast's helper threads stay awake for a while after a render, yielding their
// processors between looks (base/parallel.h): an Embree pass that followed at once shared the two
// processors with them, and the pairs in which raycast went first read up to twice as fast as
// those in which Embree did (1k triangles, packets: 1.4-1.8 against 0.6-0.9). So each pass waits
// until they sleep. The untimed pass then puts each side as it is in its own runs, where one pass
// follows another: the processors awake, and raycast's helpers awake as the command line's load
// and build leave them for its render. (Waking only raycast's helpers before its render, untimed,
// had moved the pairs' ratios by more than the margins in question.)
template <typename PassFn>
TraceResult pass_at_rest(PassFn&& pass) {
    std::this_thread::sleep_for(std::chrono::milliseconds(3 * kHelperStayAwakeMilliseconds));
    pass();
    return pass();
}

// `pairs` pairs of one Embree pass and one raycast render, each after an untimed one of its own
// (pass_at_rest); which of the two goes first alternates from pair to pair. Prints, as
// " paired_NAME=r1,r2,... paired_NAME_best=b", the pairs' ratios of raycast's Mrays/s to
// Embree's and the ratio of the two sides' best passes.
template <typename EmbreeFn, typename RaycastFn>
void print_paired(const char* name, int pairs, EmbreeFn&& embree_fn, RaycastFn&& raycast_fn) {
    auto embree = [&] { return pass_at_rest(embree_fn); };
    auto raycast = [&] { return pass_at_rest(raycast_fn); };
    std::string ratios;
    double best_embree = 0, best_raycast = 0;
    for (int pair = 0; pair < pairs; ++pair) {
        TraceResult e, r;
        if (pair % 2 == 0) {
            e = embree();
            r = raycast();
        } else {
            r = raycast();
            e = embree();
        }
        best_embree = std::max(best_embree, mrays_per_s(e));
        best_raycast = std::max(best_raycast, mrays_per_s(r));
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%s%.4f", pair > 0 ? "," : "", mrays_per_s(r) / mrays_per_s(e));
        ratios += buffer;
    }
    std::printf(" paired_%s=%s paired_%s_best=%.4f", name, ratios.c_str(), name, best_raycast / best_embree);
}

// The --paired run: Embree's scene is built (by the caller), then raycast's from the same file,
// and the three comparisons of the targets run pair by pair. Prints their ratios.
void run_paired(const Options& options, const EmbreePasses& embree, const SceneLoadOptions& load_options, int width,
                int height) {
    SceneBuildOptions build_options;
    build_options.width = width;
    build_options.height = height;
    build_options.threads = options.threads;
    const Scene ours = build_scene(load_scene_file(options.scene_path, load_options), build_options);
    RenderOptions single, ao, packets;
    single.threads = ao.threads = packets.threads = options.threads;
    single.packet_isa = PacketIsa::None;
    ao.mode = RenderMode::AmbientOcclusion;
    ao.ao_samples = options.ao_rays;
    const int n = options.paired;
    std::printf(" paired_runs=%d raycast_packets=%s", n, packet_isa_name(packets.packet_isa));
    print_paired("single", n, [&] { return embree.single(false); }, [&] { return render_pass(ours, single); });
    print_paired("ao", n, [&] { return embree.single(true); }, [&] { return render_pass(ours, ao); });
    print_paired("packets", n, [&] { return embree.packets(false); }, [&] { return render_pass(ours, packets); });
}

std::string mrays_field(const char* name, const TraceResult& r) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, " %s_mrays_per_s=%.3f", name, mrays_per_s(r));
    return buffer;
}

float box_diagonal(const Bounds3f& b) { return length(b.upper - b.lower); }

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
    RTCBounds embree_bounds;
    rtcGetSceneBounds(scene, &embree_bounds);
    const Bounds3f scene_box{{embree_bounds.lower_x, embree_bounds.lower_y, embree_bounds.lower_z},
                             {embree_bounds.upper_x, embree_bounds.upper_y, embree_bounds.upper_z}};

    const int threads = options.threads, repeat = options.repeat;
    const EmbreePasses embree{scene, camera, threads, options.ao_rays, 0.1f * box_diagonal(scene_box)};
    if (options.paired > 0) {
        std::printf("embree-bench embree=%s triangles=%zu threads=%d size=%dx%d load_ms=%.3f build_ms=%.3f",
                    RTC_VERSION_STRING, triangle_count, threads, width, height, load_ms, build_ms);
        run_paired(options, embree, load_options, width, height);
        std::printf("\n");
        rtcReleaseScene(scene);
        rtcReleaseDevice(device);
        return 0;
    }
    const TraceResult single = best_of(repeat, [&] { return embree.single(false); });
    const TraceResult packets = best_of(repeat, [&] { return embree.packets(false); });
    const TraceResult ao_single = best_of(repeat, [&] { return embree.single(true); });
    const TraceResult ao_packets = best_of(repeat, [&] { return embree.packets(true); });
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);

    const double rays = static_cast<double>(width) * static_cast<double>(height);
    const double hit_fraction = static_cast<double>(single.hits) / rays;
    // raycast prints its hit fraction rounded to 4 digits: equal means equal at that precision.
    const bool match = !options.has_expected || std::fabs(hit_fraction - options.expected_hit_fraction) < 0.00006;
    std::printf("embree-bench embree=%s triangles=%zu threads=%d size=%dx%d load_ms=%.3f build_ms=%.3f "
                "single_ms=%.3f single_mrays_per_s=%.3f packet16_ms=%.3f packet16_mrays_per_s=%.3f rays=%.0f "
                "hits=%llu packet16_hits=%llu hit_fraction=%.4f ao_rays_per_hit=%d ao_length=%g",
                RTC_VERSION_STRING, triangle_count, threads, width, height, load_ms, build_ms, single.ms,
                mrays_per_s(single), packets.ms, mrays_per_s(packets), rays,
                static_cast<unsigned long long>(single.hits), static_cast<unsigned long long>(packets.hits),
                hit_fraction, options.ao_rays, static_cast<double>(embree.ao_length));
    std::printf("%s%s", mrays_field("ao_single", ao_single).c_str(), mrays_field("ao_packet16", ao_packets).c_str());
    if (options.has_expected)
        std::printf(" expected_hit_fraction=%.4f hit_match=%s", options.expected_hit_fraction, match ? "yes" : "no");

    bool raycast_agrees = true;
    if (options.trace_raycast) {
        // raycast's turn, after Embree's memory is gone: the same file, loaded and built again.
        SceneBuildOptions build_options;
        build_options.width = width;
        build_options.height = height;
        build_options.threads = threads;
        const Scene ours = build_scene(load_scene_file(options.scene_path, load_options), build_options);
        const PacketTracer tracer(ours, best_packet_isa());
        const float ao_length =
            ours.instance_bvh.empty() ? 0.0f : 0.1f * box_diagonal(ours.instance_bvh.nodes[0].bounds);
        const RaycastPasses passes{ours, tracer, ours.camera, threads, options.ao_rays, ao_length};
        using Extra = RaycastPasses::Extra;
        const TraceResult r_single = best_of(repeat, [&] { return passes.single(Extra::None); });
        const TraceResult r_packets = best_of(repeat, [&] { return passes.packets(Extra::None); });
        const TraceResult r_ao_single = best_of(repeat, [&] { return passes.single(Extra::Ao); });
        const TraceResult r_ao_packets = best_of(repeat, [&] { return passes.packets(Extra::Ao); });
        std::printf(" raycast_packets=%s raycast_hits=%llu%s%s%s%s", packet_isa_name(tracer.isa()),
                    static_cast<unsigned long long>(r_single.hits), mrays_field("raycast_single", r_single).c_str(),
                    mrays_field("raycast_packet", r_packets).c_str(), mrays_field("raycast_ao_single", r_ao_single).c_str(),
                    mrays_field("raycast_ao_packet", r_ao_packets).c_str());
        raycast_agrees = r_packets.hits == r_single.hits && r_ao_single.hits == r_single.hits &&
                         r_ao_packets.hits == r_single.hits;
        if (!ours.lights.empty()) {
            const TraceResult r_shadow_single = best_of(repeat, [&] { return passes.single(Extra::Shadow); });
            const TraceResult r_shadow_packets = best_of(repeat, [&] { return passes.packets(Extra::Shadow); });
            std::printf("%s%s", mrays_field("raycast_shadow_single", r_shadow_single).c_str(),
                        mrays_field("raycast_shadow_packet", r_shadow_packets).c_str());
            raycast_agrees = raycast_agrees && r_shadow_single.rays == r_shadow_packets.rays;
        }
    }
    std::printf("\n");
    if (!match)
        std::fprintf(stderr, "raycast_embree_bench: hit fraction %.6f differs from raycast's %.4f\n", hit_fraction,
                     options.expected_hit_fraction);
    if (!raycast_agrees) std::fprintf(stderr, "raycast_embree_bench: raycast's single rays and packets disagree\n");
    return !raycast_agrees ? 4 : (match ? 0 : 3);
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
