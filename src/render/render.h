// The render loop: the image is cut into tiles that threads claim one at a time; each pixel's
// camera rays are made and traced (in SIMD packets where they are coherent), and each ray's hit
// goes to the radiance function of the render mode (render/integrator.h). One pass gives the
// colour and, when asked, the depth and normals images of the same rays. The result does not
// depend on the thread count, the tile size or the crop.
#pragma once

#include <cstdint>
#include <string>

#include "image/image.h"
#include "render/ray_tree.h"
#include "render/render_options.h"
#include "scene/scene.h"

namespace raycast {

struct RenderStats {
    uint64_t rays = 0;            ///< every ray traced: camera, shadow, reflected and transmitted
    uint64_t primary_rays = 0;    ///< camera rays
    /// Camera rays of windows that RenderOptions::skip_empty_windows found to miss everything,
    /// coloured without being traced one by one (counted in primary_rays and rays too).
    uint64_t window_missed_rays = 0;
    uint64_t shadow_rays = 0;
    uint64_t secondary_rays = 0;  ///< reflected and transmitted
    uint64_t occlusion_rays = 0;  ///< ambient occlusion
    uint64_t hits = 0;            ///< camera rays that hit something
    uint64_t nodes_visited = 0;   ///< BVH nodes (leaves) visited by camera rays (cost mode)
    uint64_t truncated_samples = 0;  ///< camera samples whose ray tree reached kMaxRaysPerSample
    double milliseconds = 0;
    bool cancelled = false;       ///< options.cancelled stopped it: the image is incomplete
    /// Surfaces of revolution, on every ray (shadow rays too): tests, Newton steps, and roots
    /// whose Newton polish did not converge (they keep their bracketed estimate).
    RevSurfaceCounters rev_surface;
    int threads = 1;
    std::string traversal;        ///< which path traced the primary rays, e.g. "packet-avx512"
};

/// The tile size the renderer takes when RenderOptions::tile_size is 0: 64 pixels a side, halved
/// (down to 16) while the frame would have fewer than 16 tiles per thread, so that the last tile
/// a thread works on alone is at most about a sixteenth of its share. Larger tiles mean fewer
/// claims of shared counters and fewer cache lines of the image that two threads write at once
/// (a row of a 16-pixel tile is 48 bytes): at 1024x1024 on two threads, tiles of 64 rendered
/// 1.04-1.12x faster than tiles of 16 (docs/performance.md).
int automatic_tile_size(int width, int height, int threads);

/// Renders the scene (or the crop window of it). Depth and Material modes ignore lights.
Image render_image(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

/// The same image as quantize(render_image(...)), byte for byte, written straight to 8 bits: a
/// quarter of the memory, and no second pass over the pixels.
ImageRgb8 render_image_rgb8(const Scene& scene, const RenderOptions& options, RenderStats* stats = nullptr);

/// Which images one pass makes.
struct FrameRequest {
    bool color = true;     ///< the image of the render mode
    bool depth = false;    ///< MIT's depth image (grey, near white; range from the options)
    bool normals = false;  ///< MIT's normals image (|n| per channel)
};

/// The images of one pass, each empty unless requested; each equals the render of its own mode
/// (render_image_rgb8 with mode Depth or Normals) byte for byte.
struct FrameImages {
    ImageRgb8 color, depth, normals;
};

/// One pass over the camera rays that makes every requested image.
FrameImages render_frame_rgb8(const Scene& scene, const RenderOptions& options, const FrameRequest& request,
                              RenderStats* stats = nullptr);

/// The distance, along the view direction, to what the centre of `camera`'s image sees (1 if it
/// sees nothing): where a thin lens focuses by default.
float auto_focus_distance(const Scene& scene, const Camera& camera);

/// Re-traces pixel (x, y) of the full frame (row 0 at the top, as --crop counts) alone and records
/// every ray: its colour and bytes are exactly those of the rendered image.
PixelExplanation explain_pixel(const Scene& scene, const RenderOptions& options, int x, int y);

}  // namespace raycast
