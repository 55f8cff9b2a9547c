#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "base/parallel.h"
#include "base/timer.h"
#include "render/shade.h"
#include "scene/intersect_packet.h"

namespace raycast {

namespace {

// A small, well-mixed hash (the "lowbias32" of Chris Wellons' hash prospector): random numbers
// seeded by pixel and sample, so an image never depends on which thread rendered what.
uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

float unit_float(uint32_t bits) { return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f); }

// Where sample `s` of `spp` falls inside the pixel, in [0, 1)²: one jittered point per cell of
// an n×n grid when spp = n², else per cell of a 1×spp row. spp = 1 is the pixel's own point.
Vec2f sample_offset(uint32_t pixel_index, int s, int spp) {
    if (spp == 1) return {0.5f, 0.5f};
    int columns = static_cast<int>(std::lround(std::sqrt(static_cast<double>(spp))));
    if (columns * columns != spp) columns = spp;
    const int rows = spp / columns;
    const uint32_t seed = hash32(pixel_index * 0x9e3779b9U + static_cast<uint32_t>(s));
    const float jitter_x = unit_float(hash32(seed ^ 0x68bc21ebU));
    const float jitter_y = unit_float(hash32(seed ^ 0x02e5be93U));
    return {(static_cast<float>(s % columns) + jitter_x) / static_cast<float>(columns),
            (static_cast<float>(s / columns) + jitter_y) / static_cast<float>(rows)};
}

Vec3f material_color(uint32_t material) {
    // Golden-ratio hues: neighbouring indices get clearly different colours.
    const float hue = std::fmod(0.13f + 0.618034f * static_cast<float>(material), 1.0f) * 6;
    const float f = hue - std::floor(hue);
    const int sector = static_cast<int>(hue) % 6;
    const float v = 0.9f, p = 0.25f, q = v - (v - p) * f, t = p + (v - p) * f;
    switch (sector) {
        case 0: return {v, t, p};
        case 1: return {q, v, p};
        case 2: return {p, v, t};
        case 3: return {p, q, v};
        case 4: return {t, p, v};
        default: return {v, p, q};
    }
}

// Nodes visited on a fixed logarithmic scale (1 → dark blue, 4096 → white), so that crops of
// one image share a scale and merge exactly.
Vec3f cost_color(uint64_t nodes) {
    const float x = std::clamp(std::log2(static_cast<float>(nodes) + 1) / 12.0f, 0.0f, 1.0f);
    if (x < 0.25f) return {0, 0, 0.2f + 3.2f * x};
    if (x < 0.5f) return {4 * (x - 0.25f), 0, 1 - 4 * (x - 0.25f)};
    if (x < 0.75f) return {1, 4 * (x - 0.5f), 0};
    return {1, 1, 4 * (x - 0.75f)};
}

struct Frame {
    int width, height;   // of the output image
    int x_offset;        // output pixel (i, j) is camera pixel (i + x_offset, j + y_offset)
    int y_offset;
};

class Renderer {
public:
    Renderer(const Scene& scene, const RenderOptions& options)
        : scene_(scene),
          options_(options),
          // Packets hold one ray per pixel; samples and lenses scatter rays, and the cost mode
          // counts nodes per ray, so those trace ray by ray.
          tracer_(scene, options.samples_per_pixel == 1 && scene.camera.lens_radius <= 0 &&
                                 options.mode != RenderMode::Cost
                             ? options.packet_isa
                             : PacketIsa::None) {
        const Camera& camera = scene.camera;
        frame_ = {camera.width, camera.height, 0, 0};
        if (options.has_crop) {
            const CropWindow& c = options.crop;
            frame_ = {c.x1 - c.x0, c.y1 - c.y0, c.x0, camera.height - c.y1};
        }
        spp_ = std::max(1, options.samples_per_pixel);
        packet_width_ = tracer_.lanes();
    }

    int width() const { return frame_.width; }
    int height() const { return frame_.height; }

    // Renders into exactly one of the two images, which has the frame's size. `timer` started
    // before the image was allocated: the render time includes it.
    void render(Image* floats, ImageRgb8* bytes, const Timer& timer, RenderStats* stats) {
        floats_ = floats;
        bytes_ = bytes;
        const size_t pixel_count = static_cast<size_t>(frame_.width) * static_cast<size_t>(frame_.height);
        if (options_.mode == RenderMode::Depth) depth_.assign(pixel_count, INFINITY);
        const int tile = std::max(1, options_.tile_size);
        const int tiles_x = (frame_.width + tile - 1) / tile, tiles_y = (frame_.height + tile - 1) / tile;
        const size_t tile_count = static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y);
        const int threads = std::max(1, options_.threads);
        std::vector<WorkerTotals> totals(static_cast<size_t>(threads));
        std::atomic<size_t> tiles_done{0};
        parallel_for(tile_count, threads, [&](size_t index, int worker) {
            const int tx = static_cast<int>(index % static_cast<size_t>(tiles_x));
            const int ty = static_cast<int>(index / static_cast<size_t>(tiles_x));
            render_tile(tx * tile, ty * tile, std::min(frame_.width, (tx + 1) * tile),
                        std::min(frame_.height, (ty + 1) * tile), totals[static_cast<size_t>(worker)]);
            const size_t done = ++tiles_done;
            if (options_.progress) options_.progress(static_cast<double>(done) / static_cast<double>(tile_count));
        });
        if (options_.mode == RenderMode::Depth) finish_depth(*floats_);
        if (stats) {
            *stats = RenderStats{};
            for (const WorkerTotals& t : totals) {
                stats->rays += t.rays;
                stats->hits += t.hits;
                stats->nodes_visited += t.nodes_visited;
                stats->rev_surface += t.rev_surface;
            }
            stats->milliseconds = timer.elapsed_ms();
            stats->threads = threads;
            stats->traversal = tracer_.isa() == PacketIsa::None ? std::string("single-ray")
                                                                : std::string("packet-") + packet_isa_name(tracer_.isa());
        }
    }

private:
    // One per thread, each on its own cache lines: a thread updates its counters for every
    // pixel, and sharing a line with another thread's would make the two cores fight over it.
    struct alignas(64) WorkerTotals {
        uint64_t rays = 0, hits = 0, nodes_visited = 0;
        RevSurfaceCounters rev_surface;  // the intersection's thread-local tally, taken after each tile
        // The tile's finished pixels, row by row, copied to the image at the end: neighbouring
        // tiles, rendered by different threads at once, share cache lines of the image (a row of
        // 16 pixels is 48 bytes), which pixel-by-pixel writes would bounce between cores.
        std::vector<Vec3f> tile_pixels;
    };

    void render_tile(int x_begin, int y_begin, int x_end, int y_end, WorkerTotals& totals) {
        const int tile_width = x_end - x_begin;
        take_rev_surface_counters();  // drop whatever this thread counted before it rendered
        totals.tile_pixels.resize(static_cast<size_t>(tile_width) * static_cast<size_t>(y_end - y_begin));
        // Blocks of pixels small enough to form one packet of coherent rays.
        const int block_w = packet_width_ >= 16 ? 4 : (packet_width_ >= 4 ? 2 : 1);
        const int block_h = packet_width_ / block_w > 0 ? packet_width_ / block_w : 1;
        Ray rays[kMaxPacketLanes];
        Hit hits[kMaxPacketLanes];
        uint64_t nodes[kMaxPacketLanes];
        int pixel_x[kMaxPacketLanes], pixel_y[kMaxPacketLanes];
        Vec3f sums[kMaxPacketLanes];
        for (int by = y_begin; by < y_end; by += block_h)
            for (int bx = x_begin; bx < x_end; bx += block_w) {
                int count = 0;
                for (int y = by; y < std::min(by + block_h, y_end); ++y)
                    for (int x = bx; x < std::min(bx + block_w, x_end); ++x) {
                        pixel_x[count] = x;
                        pixel_y[count] = y;
                        ++count;
                    }
                for (int s = 0; s < spp_; ++s) {
                    for (int k = 0; k < count; ++k) {
                        rays[k] = primary_ray(pixel_x[k], pixel_y[k], s);
                        hits[k] = Hit{};
                        nodes[k] = 0;
                    }
                    trace(rays, hits, nodes, count);
                    for (int k = 0; k < count; ++k) {
                        totals.rays += 1;
                        totals.hits += hits[k].is_hit() ? 1 : 0;
                        totals.nodes_visited += nodes[k];
                        const Vec3f color = pixel_value(rays[k], hits[k], nodes[k], pixel_x[k], pixel_y[k]);
                        sums[k] = s == 0 ? color : sums[k] + color;
                    }
                }
                for (int k = 0; k < count; ++k)
                    totals.tile_pixels[static_cast<size_t>(pixel_y[k] - y_begin) * static_cast<size_t>(tile_width) +
                                       static_cast<size_t>(pixel_x[k] - x_begin)] =
                        spp_ > 1 ? sums[k] / static_cast<float>(spp_) : sums[k];
            }
        store_tile(x_begin, y_begin, x_end, y_end, totals.tile_pixels.data());
        totals.rev_surface += take_rev_surface_counters();
    }

    void store_tile(int x_begin, int y_begin, int x_end, int y_end, const Vec3f* colors) {
        for (int y = y_begin; y < y_end; ++y) {
            if (floats_) {
                std::copy(colors, colors + (x_end - x_begin), &floats_->at(x_begin, y));
                colors += x_end - x_begin;
                continue;
            }
            uint8_t* byte = bytes_->at(x_begin, y);
            for (int x = x_begin; x < x_end; ++x, ++colors, byte += 3) to_bytes(*colors, byte);
        }
    }

    Ray primary_ray(int x, int y, int s) const {
        const Camera& camera = scene_.camera;
        const int cam_x = x + frame_.x_offset, cam_y = y + frame_.y_offset;
        const uint32_t pixel_index = static_cast<uint32_t>(cam_y) * static_cast<uint32_t>(camera.width) +
                                     static_cast<uint32_t>(cam_x);
        const Vec2f offset = sample_offset(pixel_index, s, spp_);
        // The pixel's own point is (x + pixel_offset, y + pixel_offset); samples spread ±½ around it.
        const float px = static_cast<float>(cam_x) + camera.pixel_offset + (offset.x - 0.5f);
        const float py = static_cast<float>(cam_y) + camera.pixel_offset + (offset.y - 0.5f);
        if (spp_ == 1 && camera.lens_radius <= 0)
            return camera_ray(camera, static_cast<float>(cam_x) + camera.pixel_offset,
                              static_cast<float>(cam_y) + camera.pixel_offset);
        const uint32_t lens_seed = hash32(pixel_index ^ hash32(static_cast<uint32_t>(s) + 0x5bd1e995U));
        return camera_ray(camera, px, py, unit_float(hash32(lens_seed)), unit_float(hash32(lens_seed + 1)));
    }

    void trace(const Ray* rays, Hit* hits, uint64_t* nodes, int count) const {
        const bool count_nodes = options_.mode == RenderMode::Cost;
        if (packet_width_ > 1) {
            tracer_.intersect(rays, count, scene_.camera.t_min, hits);
            return;
        }
        for (int k = 0; k < count; ++k) {
            TraceCounters counters;
            intersect(scene_, rays[k], scene_.camera.t_min, hits[k], count_nodes ? &counters : nullptr);
            nodes[k] = counters.nodes_visited;
        }
    }

    Vec3f pixel_value(const Ray& ray, const Hit& hit, uint64_t nodes, int x, int y) {
        switch (options_.mode) {
            case RenderMode::Shaded:
                return hit.is_hit() ? shade(scene_, ray, hit, options_.shadows) : scene_.background;
            case RenderMode::Normals:
                return hit.is_hit() ? abs(surface_at(scene_, ray, hit).normal) : Vec3f{};
            case RenderMode::Depth:
                // The grey level needs the depth range, known only when every pixel is traced.
                if (hit.is_hit()) depth_[static_cast<size_t>(y) * static_cast<size_t>(frame_.width) + static_cast<size_t>(x)] = hit.t;
                return {};
            case RenderMode::Material:
                return hit.is_hit() ? material_color(surface_at(scene_, ray, hit).material) : Vec3f{};
            case RenderMode::Cost:
                return cost_color(nodes);
        }
        return {};
    }

    void finish_depth(Image& image) const {
        float near = options_.depth_near, far = options_.depth_far;
        if (near == 0 && far == 0) {
            near = INFINITY;
            far = -INFINITY;
            for (float t : depth_)
                if (std::isfinite(t)) {
                    near = std::min(near, t);
                    far = std::max(far, t);
                }
        }
        for (size_t i = 0; i < depth_.size(); ++i) {
            const float t = depth_[i];
            if (!std::isfinite(t)) continue;
            const float grey = far > near ? std::clamp((far - t) / (far - near), 0.0f, 1.0f) : 1.0f;
            image.pixels[i] = {grey, grey, grey};
        }
    }

    const Scene& scene_;
    const RenderOptions& options_;
    PacketTracer tracer_;
    Frame frame_;
    int spp_ = 1;
    int packet_width_ = 1;
    std::vector<float> depth_;
    Image* floats_ = nullptr;
    ImageRgb8* bytes_ = nullptr;
};

}  // namespace

Image render_image(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    const Timer timer;
    Renderer renderer(scene, options);
    Image image(renderer.width(), renderer.height());
    renderer.render(&image, nullptr, timer, stats);
    return image;
}

ImageRgb8 render_image_rgb8(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    // Depth's grey levels need every pixel's distance first: that goes through the float image.
    if (options.mode == RenderMode::Depth) return quantize(render_image(scene, options, stats));
    const Timer timer;
    Renderer renderer(scene, options);
    ImageRgb8 image(renderer.width(), renderer.height());
    renderer.render(nullptr, &image, timer, stats);
    return image;
}

}  // namespace raycast
