// The render loop: the image is cut into tiles that threads claim one at a time; each pixel's
// primary rays are traced and shaded. The result does not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "image/image.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"

namespace raycast {

/// What each pixel shows.
enum class RenderMode {
    Shaded,    ///< the lit image
    Normals,   ///< |n| per channel of the unit world normal; background black (MIT 6.837's normals image)
    Depth,     ///< clamp((far − t)/(far − near)) as grey; background black (MIT 6.837's depth image)
    Material,  ///< a distinct flat colour per material
    Cost,      ///< BVH nodes visited, as a heat map
};

/// A window of the image in pixel coordinates with y = 0 at the top (as image viewers number
/// rows): columns [x0, x1), rows [y0, y1).
struct CropWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct RenderOptions {
    int threads = 1;
    int tile_size = 16;
    RenderMode mode = RenderMode::Shaded;
    int samples_per_pixel = 1;  ///< stratified over an n×n grid when n² = spp, else a jittered row
    bool shadows = false;
    float depth_near = 0, depth_far = 0;  ///< Depth mode; both 0: the range of the visible hits
    /// How primary rays are traced: SIMD packets of an instruction set, or None for one ray at a
    /// time. The image is the same either way. Default: the best this CPU runs.
    PacketIsa packet_isa = best_packet_isa();
    bool has_crop = false;
    CropWindow crop;      ///< render only this window (the image has the window's size)
    /// Called now and then from the rendering threads with the fraction done (0..1).
    std::function<void(double)> progress;
};

struct RenderStats {
    uint64_t rays = 0;            ///< primary rays
    uint64_t hits = 0;            ///< primary rays that hit something
    uint64_t nodes_visited = 0;   ///< BVH nodes (leaves) visited
    double milliseconds = 0;
    /// Surfaces of revolution, on every ray (shadow rays too): tests, Newton steps, and roots
    /// whose Newton polish did not converge (they keep their bracketed estimate).
    RevSurfaceCounters rev_surface;
    int threads = 1;
    std::string traversal;        ///< which path traced the primary rays, e.g. "packet-avx512"
};

/// Renders the scene (or the crop window of it). Depth and Material modes ignore lights.
Image render_image(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

/// The same image as quantize(render_image(...)), byte for byte, written straight to 8 bits: a
/// quarter of the memory, and no second pass over the pixels.
ImageRgb8 render_image_rgb8(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

}  // namespace raycast
