#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "base/limits.h"
#include "base/parallel.h"
#include "base/simd_clones.h"
#include "base/timer.h"
#include "render/integrator.h"
#include "render/sampler.h"
#include "scene/camera_window.h"
#include "scene/intersect_packet.h"

namespace raycast {

namespace {

// Pixel (x, y) of the camera's full frame, y = 0 at the bottom, is pixel number y·width + x: the
// seed of its samples, so a pixel is the same whatever tile, thread or crop renders it.
uint32_t pixel_index(const Camera& camera, int x, int y) {
    return static_cast<uint32_t>(y) * static_cast<uint32_t>(camera.width) + static_cast<uint32_t>(x);
}

// The point of the image plane, in pixel units, of a sample of pixel (x, y) of the full frame
// that lies at `offset` inside it (pixel_sample_offset): the pixel's own point is
// (x + pixel_offset, y + pixel_offset), and samples spread ±½ around it.
Vec2f camera_point_at_offset(const Camera& camera, int x, int y, Vec2f offset) {
    return {static_cast<float>(x) + camera.pixel_offset + (offset.x - 0.5f),
            static_cast<float>(y) + camera.pixel_offset + (offset.y - 0.5f)};
}

// The point that sample `s` of pixel (x, y) of the full frame goes through.
Vec2f camera_sample_point(const Camera& camera, const SampleGrid& grid, int x, int y, int s) {
    return camera_point_at_offset(camera, x, y, pixel_sample_offset(grid, pixel_index(camera, x, y), s));
}

// The camera rays of sample `s` of `count` pixels of a pinhole camera, (x[k], y[k]) of the full
// frame: camera_sample_point's and camera_ray_at's, the same bits, made together. Its own function
// so that it is built for AVX2 and AVX-512 too (base/simd_clones.h): the three hashes of each
// sample need 32-bit multiplies, which the baseline's SSE2 has no vector form of, and one sample
// at a time this was 7% of a --spp 16 render at 1M triangles. The sample's cell of the grid is
// the same for every pixel and is found once: with pixel_sample_offset's integer divisions and its
// test for a grid of one cell inside it, the loop was not vectorised (1.09-1.16x on --spp 16).
constexpr int kMaxPinholeSampleRays = 64;  // a render block's pixels
RAYCAST_SIMD_CLONES
void pinhole_sample_rays(const Camera& camera, const SampleGrid& grid, const int* x, const int* y, int count, int s,
                         Ray* rays) {
    RAYCAST_DCHECK(count <= kMaxPinholeSampleRays);
    float a[kMaxPinholeSampleRays], b[kMaxPinholeSampleRays];
    // One sample per pixel takes the pixels' centres (render_tile), so the grid has several cells:
    // pixel_sample_offset is then offset_in_cell.
    RAYCAST_DCHECK(grid.columns * grid.rows > 1);
    const SampleCell cell = sample_cell(grid, s);
    for (int k = 0; k < count; ++k) {
        const Vec2f offset = offset_in_cell(cell, sample_jitter(pixel_index(camera, x[k], y[k]), s));
        const Vec2f point = camera_point_at_offset(camera, x[k], y[k], offset);
        a[k] = camera_plane_x(camera, point.x);
        b[k] = camera_plane_y(camera, point.y);
    }
    camera_rays_at(camera, a, b, count, rays);
}

// The camera ray of sample `s` of pixel (x, y) of the full frame.
Ray camera_sample_ray(const Camera& camera, const SampleGrid& grid, int x, int y, int s) {
    if (grid.columns * grid.rows == 1 && camera.lens_radius <= 0)
        return camera_ray(camera, static_cast<float>(x) + camera.pixel_offset, static_cast<float>(y) + camera.pixel_offset);
    const Vec2f point = camera_sample_point(camera, grid, x, y, s);
    const Vec2f lens = lens_sample(pixel_index(camera, x, y), s);
    return camera_ray(camera, point.x, point.y, lens.x, lens.y);
}

// The colour that camera sample `s` of a pixel brings back, given its ray and closest hit: a
// fresh trace context (depth 0, weight 1, vacuum, this sample's random numbers and ray budget)
// handed to the mode's radiance function. With `tree`, every ray is recorded in it.
Vec3f shade_camera_sample(const Integrator& integrator, uint32_t index, int s, const Ray& ray, const Hit& hit,
                          uint64_t nodes_visited, RayCounts& counts, RayTree* tree,
                          const CameraShadows* shadows = nullptr, const PacketTracer* tracer = nullptr) {
    Sampler sampler(index, s);
    uint32_t budget = kMaxRaysPerSample;
    TraceContext context;
    context.sampler = &sampler;
    context.counts = &counts;
    context.rays_left = &budget;
    context.nodes_visited = nodes_visited;
    context.tree = tree;
    context.camera_shadows = shadows;
    context.tracer = tracer;
    if (tree) {
        RayRecord record;
        record.origin = ray.origin;
        record.direction = ray.direction;
        record.t_min = render_camera(integrator.scene, integrator.options).t_min;
        record.t_max = INFINITY;
        context.record = tree->add(std::move(record));
    }
    return integrator.radiance(integrator, ray, hit, context);
}

// Depth images: clamp((far − t)/(far − near)) as grey, near white, misses black. The range is the
// options' or, when both are 0, that of the visible hits.
void depth_to_grey(const std::vector<float>& depths, const RenderOptions& options, Image& image) {
    float near = options.depth_near, far = options.depth_far;
    if (near == 0 && far == 0) {
        near = INFINITY;
        far = -INFINITY;
        for (float t : depths)
            if (std::isfinite(t)) {
                near = std::min(near, t);
                far = std::max(far, t);
            }
    }
    for (size_t i = 0; i < depths.size(); ++i) {
        const float t = depths[i];
        if (!std::isfinite(t)) continue;
        const float grey = far > near ? std::clamp((far - t) / (far - near), 0.0f, 1.0f) : 1.0f;
        image.pixels[i] = {grey, grey, grey};
    }
}

// The part of the camera's frame being rendered.
struct Frame {
    int width, height;   // of the output images
    int x_offset;        // output pixel (i, j) is camera pixel (i + x_offset, j + y_offset)
    int y_offset;
};

Frame frame_of(const Camera& camera, const RenderOptions& options) {
    if (!options.has_crop) return {camera.width, camera.height, 0, 0};
    const CropWindow& c = options.crop;
    return {c.x1 - c.x0, c.y1 - c.y0, c.x0, camera.height - c.y1};
}

// Where a pass writes: colour as floats or bytes, normals as bytes, depths as distances.
struct Targets {
    Image* color_floats = nullptr;
    ImageRgb8* color_bytes = nullptr;
    ImageRgb8* normal_bytes = nullptr;
    std::vector<float>* depths = nullptr;  // t of each pixel's last sample that hit; infinity: none
};

class Renderer {
public:
    Renderer(const Scene& scene, const RenderOptions& options)
        : scene_(scene),
          options_(options),
          integrator_(make_integrator(scene, options)),
          normals_{scene, render_lights(scene, options), options, radiance_function_for(RenderMode::Normals), 0, {}, {}},
          // A packet holds sample s of each pixel of a block: neighbouring rays, coherent with or
          // without jitter or a lens. The cost mode counts nodes per ray, so it traces ray by ray.
          tracer_(scene, options.mode != RenderMode::Cost ? options.packet_isa : PacketIsa::None),
          camera_(render_camera(scene, options)),
          frame_(frame_of(camera_, options)),
          spp_(std::max(1, options.samples_per_pixel)),
          grid_(spp_),
          packet_width_(tracer_.lanes()),
          // Shadow rays from a packet's hits are as coherent as the packet: traced together too.
          camera_shadows_(packet_width_ > 1 && traces_camera_shadows(integrator_)),
          skip_empty_windows_(options.skip_empty_windows && misses_look_alike(options.mode) &&
                              camera_window(camera_, 0, 1, 0, 1).bounded) {
        if (!skip_empty_windows_) return;
        // The colours of a pixel whose every sample misses: the same for every ray
        // (misses_look_alike), so found once with any, and summed and averaged over the samples
        // exactly as render_tile sums them.
        RayCounts unused;
        const Ray ray = camera_sample_ray(camera_, grid_, 0, 0, 0);
        const Vec3f color = shade_camera_sample(integrator_, 0, 0, ray, Hit{}, 0, unused, nullptr);
        const Vec3f normal = shade_camera_sample(normals_, 0, 0, ray, Hit{}, 0, unused, nullptr);
        miss_color_ = color;
        miss_normal_ = normal;
        for (int s = 1; s < spp_; ++s) {
            miss_color_ = miss_color_ + color;
            miss_normal_ = miss_normal_ + normal;
        }
        if (spp_ > 1) {
            miss_color_ = miss_color_ / static_cast<float>(spp_);
            miss_normal_ = miss_normal_ / static_cast<float>(spp_);
        }
    }

    int width() const { return frame_.width; }
    int height() const { return frame_.height; }

    // Renders into the targets, which have the frame's size. `timer` started before the images
    // were allocated: the render time includes them.
    void render(const Targets& targets, const Timer& timer, RenderStats* stats) {
        targets_ = targets;
        const int threads = std::max(1, options_.threads);
        const int tile = options_.tile_size > 0 ? options_.tile_size
                                                : automatic_tile_size(frame_.width, frame_.height, threads);
        const int tiles_x = (frame_.width + tile - 1) / tile, tiles_y = (frame_.height + tile - 1) / tile;
        const size_t tile_count = static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y);
        std::vector<WorkerState> workers(static_cast<size_t>(threads));
        std::atomic<size_t> tiles_done{0};
        std::atomic<bool> stopped{false};
        std::atomic<bool> told_ray_limit{false};
        parallel_for(tile_count, threads, [&](size_t index, int worker) {
            if (stopped.load(std::memory_order_relaxed)) return;
            if (options_.cancelled && options_.cancelled()) {
                stopped = true;
                return;
            }
            const int tx = static_cast<int>(index % static_cast<size_t>(tiles_x));
            const int ty = static_cast<int>(index / static_cast<size_t>(tiles_x));
            const int x0 = tx * tile, y0 = ty * tile;
            const int x1 = std::min(frame_.width, (tx + 1) * tile), y1 = std::min(frame_.height, (ty + 1) * tile);
            WorkerState& state = workers[static_cast<size_t>(worker)];
            if (camera_shadows_)
                render_tile<true>(x0, y0, x1, y1, state);
            else
                render_tile<false>(x0, y0, x1, y1, state);
            if (options_.reaching_ray_limit && state.counts.truncated > 0 && !told_ray_limit.exchange(true))
                options_.reaching_ray_limit();
            const size_t done = ++tiles_done;
            if (options_.progress) options_.progress(static_cast<double>(done) / static_cast<double>(tile_count));
        });
        if (stats) {
            RayCounts counts;
            for (const WorkerState& w : workers) counts += w.counts;
            *stats = RenderStats{};
            stats->rays = counts.total();
            stats->primary_rays = counts.primary;
            stats->window_missed_rays = counts.window_missed;
            stats->shadow_rays = counts.shadow;
            stats->secondary_rays = counts.secondary;
            stats->occlusion_rays = counts.occlusion;
            stats->hits = counts.primary_hits;
            stats->nodes_visited = counts.nodes_visited;
            stats->truncated_samples = counts.truncated;
            stats->rev_surface = counts.rev_surface;
            stats->milliseconds = timer.elapsed_ms();
            stats->cancelled = stopped;
            stats->threads = threads;
            stats->traversal = tracer_.isa() == PacketIsa::None ? std::string("single-ray")
                                                                : std::string("packet-") + packet_isa_name(tracer_.isa());
        }
    }

private:
    // One per thread, each on its own cache lines: a thread updates its counters for every
    // pixel, and sharing a line with another thread's would make the two cores fight over it.
    struct alignas(64) WorkerState {
        RayCounts counts;
        // The tile's finished pixels, row by row, copied to the images at the end: neighbouring
        // tiles, rendered by different threads at once, share cache lines of the image (a row of
        // 16 pixels is 48 bytes), which pixel-by-pixel writes would bounce between cores.
        std::vector<Vec3f> tile_colors, tile_normals;
        // Image-plane coordinates of the tile's columns and rows (camera_plane_x/y), when every
        // pixel has one ray through its own point: found once each rather than per pixel.
        std::vector<float> plane_x, plane_y;
        std::vector<uint8_t> empty_parts;  // per part of the tile: whether its rays all miss
    };

    // The side of the square parts of a tile that are checked for rays that all miss: 16 pixels,
    // a whole number of render blocks (8x8).
    static constexpr int kEmptyWindow = 16;
    // The side of a render block (see render_tile).
    static constexpr int kBlockSide = 8;

    // kShadowsAhead is camera_shadows_: each case has its own copy of the loop.
    template <bool kShadowsAhead>
    void render_tile(int x_begin, int y_begin, int x_end, int y_end, WorkerState& worker) {
        constexpr int kBlockPixels = kBlockSide * kBlockSide;
        static_assert(!kShadowsAhead || kBlockPixels == kMaxCameraShadowHits, "a block's hits fill the shadow packets");
        static_assert(kBlockPixels <= kMaxPinholeSampleRays, "pinhole_sample_rays makes a block's rays at once");
        const int tile_width = x_end - x_begin;
        take_rev_surface_counters();  // drop whatever this thread counted before it rendered
        const size_t tile_pixels = static_cast<size_t>(tile_width) * static_cast<size_t>(y_end - y_begin);
        worker.tile_colors.resize(tile_pixels);
        if (targets_.normal_bytes) worker.tile_normals.resize(tile_pixels);
        // Windows whose rays all miss (sees_nothing) get the miss colours without being traced:
        // the whole tile, or else each part of kEmptyWindow pixels square that sees nothing.
        const int parts_x = (tile_width + kEmptyWindow - 1) / kEmptyWindow;
        const int parts_y = (y_end - y_begin + kEmptyWindow - 1) / kEmptyWindow;
        worker.empty_parts.assign(static_cast<size_t>(parts_x) * static_cast<size_t>(parts_y), 0);
        if (skip_empty_windows_) {
            if (sees_nothing(x_begin, y_begin, x_end, y_end)) {
                std::fill(worker.empty_parts.begin(), worker.empty_parts.end(), 1);
            } else if (parts_x * parts_y > 1) {
                for (int py = 0; py < parts_y; ++py)
                    for (int px = 0; px < parts_x; ++px) {
                        const int x0 = x_begin + px * kEmptyWindow, y0 = y_begin + py * kEmptyWindow;
                        worker.empty_parts[static_cast<size_t>(py * parts_x + px)] =
                            sees_nothing(x0, y0, std::min(x0 + kEmptyWindow, x_end), std::min(y0 + kEmptyWindow, y_end));
                    }
            }
        }
        // Blocks of 8x8 pixels, four of the widest packet's 4x4 (kMaxPacketLanes): traced as four
        // packets of 16 that walk the BVH together (PacketTracer::intersect_packets; the render
        // 1.06x faster at 100k and 1M triangles than with one packet a block), as packets of 8
        // (4x2 each) or 4 (rows of 4). Whatever the kernel, the work around the trace is done for
        // the block together: its camera rays made at once (square roots and divisions in SIMD),
        // its hits shaded 16 at a time, its bookkeeping paid once. Blocks of one packet each (8
        // pixels for AVX2 and single rays, 4 for SSE2) had measured 1.04-1.14x slower than blocks
        // of 4x4 with AVX2, 1.26x with SSE2, 1.04-1.07x ray by ray. With shadow rays traced ahead,
        // trace_camera_shadows fills its shadow packets from the whole block.
        constexpr int packet_w = 4, packet_h = kMaxPacketLanes / packet_w;
        static_assert(packet_w * packet_h == kMaxPacketLanes, "a packet of the widest kernel is 4x4 pixels");
        static_assert(kBlockSide % packet_w == 0 && kBlockSide % packet_h == 0, "a block is whole packets");
        static_assert((kBlockSide / packet_w) * (kBlockSide / packet_h) == kMaxSharedPackets,
                      "a block's packets walk the BVH together");
        static_assert(packet_w == packet_h, "blocks of one packet are square too");
        // Single rays keep blocks of 4x4: with 8x8, the 1k render ray by ray measured 0.97x.
        const int block_side = packet_width_ > 1 ? kBlockSide : packet_w;
        const Camera& camera = camera_;
        static_assert(kEmptyWindow % kBlockSide == 0, "a tile's parts of kEmptyWindow pixels hold whole blocks");
        const bool pixel_centres = spp_ == 1 && camera.lens_radius <= 0;
        if (pixel_centres) {
            worker.plane_x.resize(static_cast<size_t>(tile_width));
            worker.plane_y.resize(static_cast<size_t>(y_end - y_begin));
            for (int x = x_begin; x < x_end; ++x)
                worker.plane_x[static_cast<size_t>(x - x_begin)] =
                    camera_plane_x(camera, static_cast<float>(x + frame_.x_offset) + camera.pixel_offset);
            for (int y = y_begin; y < y_end; ++y)
                worker.plane_y[static_cast<size_t>(y - y_begin)] =
                    camera_plane_y(camera, static_cast<float>(y + frame_.y_offset) + camera.pixel_offset);
        }
        Ray rays[kBlockPixels];
        Hit hits[kBlockPixels];
        uint64_t nodes[kBlockPixels];
        int camera_x[kBlockPixels], camera_y[kBlockPixels];
        size_t slot[kBlockPixels];  // the pixel's place in the tile
        Vec3f colors[kBlockPixels], normals[kBlockPixels];
        // What shade_camera_hits_locally returns for a block. Here rather than in the loop: a
        // Vec3f starts as zeros, and zeroing them per block was 0.5% of a 1k-triangle render.
        Vec3f local_colors[kBlockPixels];
        bool shaded[kBlockPixels];
        CameraShadows shadows[kBlockPixels];
        for (int by = y_begin; by < y_end; by += block_side)
            for (int bx = x_begin; bx < x_end; bx += block_side) {
                const int block_x_end = std::min(bx + block_side, x_end), block_y_end = std::min(by + block_side, y_end);
                // Blocks lie within one part: kEmptyWindow is a multiple of their width and height.
                if (worker.empty_parts[static_cast<size_t>((by - y_begin) / kEmptyWindow * parts_x +
                                                           (bx - x_begin) / kEmptyWindow)]) {
                    for (int y = by; y < block_y_end; ++y) {  // row by row (a pixel at a time was 3% of a 1M render)
                        const size_t row = static_cast<size_t>(y - y_begin) * static_cast<size_t>(tile_width);
                        const size_t first = row + static_cast<size_t>(bx - x_begin), last = row + static_cast<size_t>(block_x_end - x_begin);
                        std::fill(worker.tile_colors.begin() + first, worker.tile_colors.begin() + last, miss_color_);
                        if (targets_.normal_bytes)
                            std::fill(worker.tile_normals.begin() + first, worker.tile_normals.begin() + last, miss_normal_);
                    }
                    const uint64_t missed = static_cast<uint64_t>((block_x_end - bx) * (block_y_end - by)) *
                                            static_cast<uint64_t>(spp_);
                    worker.counts.primary += missed;
                    worker.counts.window_missed += missed;
                    continue;
                }
                int count = 0;
                for (int py = by; py < block_y_end; py += packet_h)  // a packet's pixels together
                    for (int px = bx; px < block_x_end; px += packet_w)
                        for (int y = py; y < std::min(py + packet_h, y_end); ++y)
                            for (int x = px; x < std::min(px + packet_w, x_end); ++x) {
                                camera_x[count] = x + frame_.x_offset;
                                camera_y[count] = y + frame_.y_offset;
                                slot[count] = static_cast<size_t>(y - y_begin) * static_cast<size_t>(tile_width) +
                                              static_cast<size_t>(x - x_begin);
                                ++count;
                            }
                for (int s = 0; s < spp_; ++s) {
                    if (pixel_centres) {
                        float a[kBlockPixels], b[kBlockPixels];
                        for (int k = 0; k < count; ++k) {
                            a[k] = worker.plane_x[static_cast<size_t>(camera_x[k] - frame_.x_offset - x_begin)];
                            b[k] = worker.plane_y[static_cast<size_t>(camera_y[k] - frame_.y_offset - y_begin)];
                        }
                        camera_rays_at(camera, a, b, count, rays);
                    } else if (camera.lens_radius <= 0) {
                        pinhole_sample_rays(camera, grid_, camera_x, camera_y, count, s, rays);
                    } else {
                        for (int k = 0; k < count; ++k) rays[k] = camera_sample_ray(camera, grid_, camera_x[k], camera_y[k], s);
                    }
                    for (int k = 0; k < count; ++k) {
                        hits[k] = Hit{};
                        nodes[k] = 0;
                    }
                    trace_camera_rays(rays, hits, nodes, count);
                    if (kShadowsAhead) trace_camera_shadows(integrator_, tracer_, rays, hits, count, shadows);
                    for (int first = 0; first < count; first += kMaxPacketLanes)
                        shade_camera_hits_locally(integrator_, rays + first, hits + first,
                                                  std::min(kMaxPacketLanes, count - first),
                                                  kShadowsAhead ? shadows + first : nullptr, worker.counts,
                                                  local_colors + first, shaded + first);
                    // Counted in locals, added once per block: worker.counts escapes to the
                    // shading calls below, so counting there would read and write memory per pixel.
                    uint64_t block_hits = 0, block_nodes = 0;
                    for (int k = 0; k < count; ++k) {
                        block_hits += hits[k].is_hit() ? 1 : 0;
                        block_nodes += nodes[k];
                    }
                    RayCounts& counts = worker.counts;
                    counts.primary += static_cast<uint64_t>(count);
                    counts.primary_hits += block_hits;
                    counts.nodes_visited += block_nodes;
                    for (int k = 0; k < count; ++k) {
                        const Vec3f color =
                            shaded[k] ? local_colors[k]
                                      : shade_camera_sample(integrator_, pixel_index(camera, camera_x[k], camera_y[k]),
                                                            s, rays[k], hits[k], nodes[k], counts, nullptr,
                                                            kShadowsAhead ? &shadows[k] : nullptr, &tracer_);
                        colors[k] = s == 0 ? color : colors[k] + color;
                        if (targets_.normal_bytes) {
                            const Vec3f normal = shade_camera_sample(normals_, pixel_index(camera, camera_x[k], camera_y[k]),
                                                                     s, rays[k], hits[k], nodes[k], counts, nullptr);
                            normals[k] = s == 0 ? normal : normals[k] + normal;
                        }
                        if (targets_.depths && hits[k].is_hit()) {
                            const size_t pixel = static_cast<size_t>(camera_y[k] - frame_.y_offset) *
                                                     static_cast<size_t>(frame_.width) +
                                                 static_cast<size_t>(camera_x[k] - frame_.x_offset);
                            (*targets_.depths)[pixel] = hits[k].t;
                        }
                    }
                }
                for (int k = 0; k < count; ++k) {
                    worker.tile_colors[slot[k]] = spp_ > 1 ? colors[k] / static_cast<float>(spp_) : colors[k];
                    if (targets_.normal_bytes)
                        worker.tile_normals[slot[k]] = spp_ > 1 ? normals[k] / static_cast<float>(spp_) : normals[k];
                }
            }
        store_tile(x_begin, y_begin, x_end, y_end, worker.tile_colors.data(), targets_.color_floats,
                   targets_.color_bytes);
        if (targets_.normal_bytes)
            store_tile(x_begin, y_begin, x_end, y_end, worker.tile_normals.data(), nullptr, targets_.normal_bytes);
        worker.counts.rev_surface += take_rev_surface_counters();
    }

    // Whether every camera ray of the frame's pixels [x_begin, x_end) × [y_begin, y_end) misses
    // everything (window_misses_scene): the window holds every sample's point, each within half
    // a pixel of its pixel's own point (camera_sample_point), with half a pixel to spare.
    bool sees_nothing(int x_begin, int y_begin, int x_end, int y_end) const {
        const float x0 = static_cast<float>(x_begin + frame_.x_offset) + camera_.pixel_offset - 1;
        const float x1 = static_cast<float>(x_end + frame_.x_offset) + camera_.pixel_offset;
        const float y0 = static_cast<float>(y_begin + frame_.y_offset) + camera_.pixel_offset - 1;
        const float y1 = static_cast<float>(y_end + frame_.y_offset) + camera_.pixel_offset;
        return window_misses_scene(scene_, camera_window(camera_, x0, x1, y0, y1));
    }

    static void store_tile(int x_begin, int y_begin, int x_end, int y_end, const Vec3f* colors, Image* floats,
                           ImageRgb8* bytes) {
        for (int y = y_begin; y < y_end; ++y) {
            if (floats) {
                std::copy(colors, colors + (x_end - x_begin), &floats->at(x_begin, y));
                colors += x_end - x_begin;
                continue;
            }
            if (!bytes) return;
            to_bytes(colors, static_cast<size_t>(x_end - x_begin), bytes->at(x_begin, y));
            colors += x_end - x_begin;
        }
    }

    void trace_camera_rays(const Ray* rays, Hit* hits, uint64_t* nodes, int count) const {
        if (packet_width_ > 1) {
            const int shared = kMaxSharedPackets * packet_width_;
            for (int first = 0; first < count; first += shared)
                tracer_.intersect_packets(rays + first, std::min(shared, count - first), camera_.t_min, hits + first);
            return;
        }
        const bool count_nodes = options_.mode == RenderMode::Cost;
        for (int k = 0; k < count; ++k) {
            TraceCounters counters;
            intersect(scene_, rays[k], camera_.t_min, hits[k], count_nodes ? &counters : nullptr);
            nodes[k] = counters.nodes_visited;
        }
    }

    const Scene& scene_;
    const RenderOptions& options_;
    const Integrator integrator_;
    const Integrator normals_;  // the normals image made in the same pass
    PacketTracer tracer_;
    const Camera& camera_;
    Frame frame_;
    int spp_ = 1;
    SampleGrid grid_;  // how the samples share a pixel
    int packet_width_ = 1;
    bool camera_shadows_ = false;
    bool skip_empty_windows_ = false;
    Vec3f miss_color_, miss_normal_;  // a pixel's colours when all its samples miss
    Targets targets_;
};

}  // namespace

int automatic_tile_size(int width, int height, int threads) {
    auto tiles = [&](int tile) {
        return static_cast<int64_t>((width + tile - 1) / tile) * static_cast<int64_t>((height + tile - 1) / tile);
    };
    int tile = 64;
    while (tile > 16 && tiles(tile) < 16 * static_cast<int64_t>(std::max(1, threads))) tile /= 2;
    return tile;
}

Image render_image(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    const Timer timer;
    Renderer renderer(scene, options);
    Image image(renderer.width(), renderer.height());
    if (options.mode != RenderMode::Depth) {
        renderer.render(Targets{&image, nullptr, nullptr, nullptr}, timer, stats);
        return image;
    }
    // The grey levels need every pixel's distance first.
    std::vector<float> depths(static_cast<size_t>(image.width) * static_cast<size_t>(image.height), INFINITY);
    renderer.render(Targets{&image, nullptr, nullptr, &depths}, timer, stats);
    depth_to_grey(depths, options, image);
    return image;
}

ImageRgb8 render_image_rgb8(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    return std::move(render_frame_rgb8(scene, options, FrameRequest{}, stats).color);
}

FrameImages render_frame_rgb8(const Scene& scene, const RenderOptions& options, const FrameRequest& request,
                              RenderStats* stats) {
    const Timer timer;
    Renderer renderer(scene, options);
    const int width = renderer.width(), height = renderer.height();
    FrameImages images;
    const bool depth_mode = options.mode == RenderMode::Depth;
    // Depth's grey levels need every pixel's distance first: its colour goes through floats.
    Image depth_floats;
    std::vector<float> depths;
    if (request.depth || (request.color && depth_mode)) {
        depth_floats = Image(width, height);
        depths.assign(static_cast<size_t>(width) * static_cast<size_t>(height), INFINITY);
    }
    if (request.color && !depth_mode) images.color = ImageRgb8(width, height);
    if (request.normals) images.normals = ImageRgb8(width, height);
    Targets targets;
    targets.color_bytes = images.color.rgb.empty() ? nullptr : &images.color;
    targets.normal_bytes = request.normals ? &images.normals : nullptr;
    targets.depths = depths.empty() ? nullptr : &depths;
    renderer.render(targets, timer, stats);
    if (!depths.empty()) {
        depth_to_grey(depths, options, depth_floats);
        if (request.color && depth_mode) images.color = quantize(depth_floats);
        if (request.depth) images.depth = quantize(depth_floats);
    }
    return images;
}

float auto_focus_distance(const Scene& scene, const Camera& camera) {
    const Ray ray = camera_ray(camera, camera.cx, camera.cy);
    Hit hit;
    intersect(scene, ray, camera.t_min, hit);
    if (!hit.is_hit() || !(hit.t > 0)) return 1.0f;
    // A plane seen at a grazing angle can lie farther than the coordinate limit: the focus is
    // then as good as at infinity, and kept where the lens's rays can still be made.
    return std::min(hit.t * dot(ray.direction, camera.direction), kMaxCoordinate);
}

PixelExplanation explain_pixel(const Scene& scene, const RenderOptions& options, int x, int y) {
    const Camera& camera = render_camera(scene, options);
    PixelExplanation explanation;
    explanation.mode = render_mode_name(options.mode);
    explanation.x = x;
    explanation.y = y;
    explanation.width = camera.width;
    explanation.height = camera.height;
    explanation.camera = camera;
    explanation.samples_per_pixel = std::max(1, options.samples_per_pixel);
    explanation.bounces = options.bounces;
    explanation.weight_cutoff = options.weight_cutoff;
    explanation.shadows = options.shadows;
    explanation.transparent_shadows = options.transparent_shadows;
    const int camera_y = camera.height - 1 - y;  // the camera counts rows from the bottom
    const uint32_t index = pixel_index(camera, x, camera_y);
    const Integrator integrator = make_integrator(scene, options);
    const int spp = explanation.samples_per_pixel;
    const SampleGrid grid(spp);
    Vec3f sum;
    for (int s = 0; s < spp; ++s) {
        const Ray ray = camera_sample_ray(camera, grid, x, camera_y, s);
        Hit hit;
        TraceCounters counters;
        intersect(scene, ray, camera.t_min, hit, options.mode == RenderMode::Cost ? &counters : nullptr);
        RayCounts counts;
        RayTree tree;
        tree.capacity = std::max<size_t>(1, kMaxExplainedRays / static_cast<size_t>(spp));
        const Vec3f color = shade_camera_sample(integrator, index, s, ray, hit, counters.nodes_visited, counts, &tree);
        sum = s == 0 ? color : sum + color;
        explanation.sample_offsets.push_back(spp == 1 && camera.lens_radius <= 0 ? Vec2f{0.5f, 0.5f}
                                                                                  : pixel_sample_offset(grid, index, s));
        explanation.samples.push_back(std::move(tree));
    }
    explanation.color = spp > 1 ? sum / static_cast<float>(spp) : sum;
    if (options.mode == RenderMode::Depth) {
        // The grey level depends on the range: the options', or that of the whole image's hits.
        RenderOptions whole = options;
        whole.has_crop = false;
        whole.progress = nullptr;
        const Image image = render_image(scene, whole, nullptr);
        explanation.color = image.at(x, camera_y);
    }
    to_bytes(explanation.color, explanation.rgb8);
    return explanation;
}

}  // namespace raycast
