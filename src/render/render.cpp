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

    Image render(RenderStats* stats) {
        Timer timer;
        Image image(frame_.width, frame_.height);
        if (options_.mode == RenderMode::Depth) depth_.assign(image.pixels.size(), INFINITY);
        const int tile = std::max(1, options_.tile_size);
        const int tiles_x = (frame_.width + tile - 1) / tile, tiles_y = (frame_.height + tile - 1) / tile;
        const size_t tile_count = static_cast<size_t>(tiles_x) * static_cast<size_t>(tiles_y);
        const int threads = std::max(1, options_.threads);
        std::vector<WorkerTotals> totals(static_cast<size_t>(threads));
        std::atomic<size_t> tiles_done{0};
        parallel_for(tile_count, threads, [&](size_t index, int worker) {
            const int tx = static_cast<int>(index % static_cast<size_t>(tiles_x));
            const int ty = static_cast<int>(index / static_cast<size_t>(tiles_x));
            render_tile(image, tx * tile, ty * tile, std::min(frame_.width, (tx + 1) * tile),
                        std::min(frame_.height, (ty + 1) * tile), totals[static_cast<size_t>(worker)]);
            const size_t done = ++tiles_done;
            if (options_.progress) options_.progress(static_cast<double>(done) / static_cast<double>(tile_count));
        });
        if (options_.mode == RenderMode::Depth) finish_depth(image);
        if (stats) {
            *stats = RenderStats{};
            for (const WorkerTotals& t : totals) {
                stats->rays += t.rays;
                stats->hits += t.hits;
                stats->nodes_visited += t.nodes_visited;
            }
            stats->milliseconds = timer.elapsed_ms();
            stats->threads = threads;
            stats->traversal = tracer_.isa() == PacketIsa::None ? std::string("single-ray")
                                                                : std::string("packet-") + packet_isa_name(tracer_.isa());
        }
        return image;
    }

private:
    struct WorkerTotals {
        uint64_t rays = 0, hits = 0, nodes_visited = 0;
        char padding[40];  // keep each thread's counters on its own cache line
    };

    void render_tile(Image& image, int x_begin, int y_begin, int x_end, int y_end, WorkerTotals& totals) {
        // Blocks of pixels small enough to form one packet of coherent rays.
        const int block_w = packet_width_ >= 16 ? 4 : (packet_width_ >= 4 ? 2 : 1);
        const int block_h = packet_width_ / block_w > 0 ? packet_width_ / block_w : 1;
        Ray rays[kMaxPacketLanes];
        Hit hits[kMaxPacketLanes];
        uint64_t nodes[kMaxPacketLanes];
        int pixel_x[kMaxPacketLanes], pixel_y[kMaxPacketLanes];
        for (int by = y_begin; by < y_end; by += block_h)
            for (int bx = x_begin; bx < x_end; bx += block_w)
                for (int s = 0; s < spp_; ++s) {
                    int count = 0;
                    for (int y = by; y < std::min(by + block_h, y_end); ++y)
                        for (int x = bx; x < std::min(bx + block_w, x_end); ++x) {
                            pixel_x[count] = x;
                            pixel_y[count] = y;
                            rays[count] = primary_ray(x, y, s);
                            hits[count] = Hit{};
                            nodes[count] = 0;
                            ++count;
                        }
                    trace(rays, hits, nodes, count);
                    for (int k = 0; k < count; ++k) {
                        totals.rays += 1;
                        totals.hits += hits[k].is_hit() ? 1 : 0;
                        totals.nodes_visited += nodes[k];
                        Vec3f& pixel = image.at(pixel_x[k], pixel_y[k]);
                        const Vec3f color = pixel_value(rays[k], hits[k], nodes[k], pixel_x[k], pixel_y[k]);
                        pixel = s == 0 ? color : pixel + color;
                        if (s == spp_ - 1 && spp_ > 1) pixel = pixel / static_cast<float>(spp_);
                    }
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
};

}  // namespace

Image render_image(const Scene& scene, const RenderOptions& options, RenderStats* stats) {
    return Renderer(scene, options).render(stats);
}

}  // namespace raycast
