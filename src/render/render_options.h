// What a render is asked to do: the mode, the rays it may trace (shadows, bounces), samples,
// threads, tiles and crop. Shared by the render loop and the integrators.
#pragma once

#include <functional>

#include "scene/intersect_packet.h"
#include "scene/scene.h"

namespace raycast {

/// The deepest recursion --bounces may ask for: each bounce is a stack frame of the radiance
/// function, so this bounds the stack, and no picture needs more.
constexpr int kMaxBounces = 1000;

/// What each pixel shows.
enum class RenderMode {
    Shaded,    ///< the lit image: Phong shading, plus shadows and mirror and glass rays when asked
    Normals,   ///< |n| per channel of the unit world normal; background black (MIT 6.837's normals image)
    Depth,     ///< clamp((far − t)/(far − near)) as grey; background black (MIT 6.837's depth image)
    Material,  ///< a distinct flat colour per material
    Cost,      ///< BVH nodes visited, as a heat map
    AmbientOcclusion,  ///< the share of cosine-distributed rays from each hit that escape, as grey
};

/// "shaded", "normals", "depth", "material", "cost" or "ao".
const char* render_mode_name(RenderMode mode);

/// A window of the image in pixel coordinates with y = 0 at the top (as image viewers number
/// rows): columns [x0, x1), rows [y0, y1).
struct CropWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct RenderOptions {
    int threads = 1;
    int tile_size = 0;  ///< pixels per side of a tile; 0: automatic_tile_size's choice
    RenderMode mode = RenderMode::Shaded;
    int samples_per_pixel = 1;  ///< stratified over an n×n grid when n² = spp, else a jittered row
    bool shadows = false;       ///< a shadow ray towards every light from every shaded hit
    /// Shadow rays pass through transparent surfaces, times their transparentColor (MIT's
    /// -transparent_shadows); else any surface blocks the light (MIT's assignment: opaque shadows).
    bool transparent_shadows = false;
    /// Reflected and transmitted rays are traced while a ray's depth is below this (0: local
    /// shading only, the course's ray caster) ...
    int bounces = 0;
    /// ... and while the path's weight, the product of the magnitudes of the reflective and
    /// transparent colours along it, is at least this.
    float weight_cutoff = 0.001f;
    /// Ambient occlusion: rays per camera sample's hit, and how far they look (0: a tenth of the
    /// diagonal of the scene's bounding box).
    int ao_samples = 16;
    float ao_distance = 0;
    float depth_near = 0, depth_far = 0;  ///< Depth mode; both 0: the range of the visible hits
    /// How primary rays are traced: SIMD packets of an instruction set, or None for one ray at a
    /// time. The image is the same either way. Default: the best this CPU runs.
    PacketIsa packet_isa = best_packet_isa();
    bool has_crop = false;
    CropWindow crop;      ///< render only this window (the image has the window's size)
    /// Pixels whose camera rays can be seen to miss the whole scene as a group (a pinhole
    /// camera: window_misses_scene) get the miss colour without being traced.
    /// The image is the same either way (tests compare); false traces every ray, for those tests.
    bool skip_empty_windows = true;
    /// The shadow rays of camera hits pass over the back faces of closed meshes where that cannot
    /// change their answer (scene/back_faces.h: both ends outside the mesh); false tests every
    /// face, for the tests that compare.
    bool skip_back_faces = true;
    /// Called now and then from the rendering threads with the fraction done (0..1).
    std::function<void(double)> progress;
    /// Called once, from a rendering thread, when a camera sample first reaches kMaxRaysPerSample
    /// (render/integrator.h): mirrors and glass deep in --bounces can make a render take hours,
    /// and the count of such samples (RenderStats::truncated_samples) comes only at the end.
    std::function<void()> reaching_ray_limit;
    /// Asked before each tile; once it returns true the rest of the image is left undone and
    /// RenderStats::cancelled is set (the viewer drops a render when a newer one is asked for).
    std::function<bool()> cancelled;
    /// Renders through this camera instead of the scene's (the viewer's orbiting camera); it
    /// must outlive the render.
    const Camera* camera = nullptr;
    /// Lights the render uses instead of the scene's (the viewer's moved lights); they must
    /// outlive the render. Directional lights' directions unit, as build_scene makes them.
    const std::vector<Light>* lights = nullptr;
};

/// The camera a render with these options looks through.
inline const Camera& render_camera(const Scene& scene, const RenderOptions& options) {
    return options.camera ? *options.camera : scene.camera;
}

/// The lights a render with these options shades with.
inline const std::vector<Light>& render_lights(const Scene& scene, const RenderOptions& options) {
    return options.lights ? *options.lights : scene.lights;
}

}  // namespace raycast
