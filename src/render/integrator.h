// The integrator seam: what colour a ray brings back. The render loop (render.h) makes camera
// rays, traces them (in SIMD packets where they are coherent) and hands each one, with its closest
// hit or a miss, to the radiance function chosen once for the render mode. A radiance function may
// trace more rays (shadow, reflected, transmitted; later, paths) through trace_ray and
// is_light_visible, and may record what it did in a RayTree for `raycast explain`.
//
// Adding an integrator: write a function with the RadianceFunction signature in integrators.cpp,
// give it a RenderMode, and return it from radiance_function_for(). It may call anything in
// scene/ (intersect, occluded, surface_at, illuminate) and render/shade.h; it never sees tiles,
// threads or images.
#pragma once

#include <cstdint>
#include <vector>

#include "math/ray.h"
#include "render/ray_tree.h"
#include "render/render_options.h"
#include "render/sampler.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"

namespace raycast {

/// Rays traced, by kind: one counter set per thread, summed at the end.
struct RayCounts {
    uint64_t primary = 0;       ///< camera rays
    uint64_t primary_hits = 0;  ///< camera rays that hit something
    uint64_t window_missed = 0;  ///< camera rays whose window was found to miss everything (also in primary)
    uint64_t shadow = 0;        ///< towards lights
    uint64_t secondary = 0;     ///< reflected and transmitted
    uint64_t occlusion = 0;     ///< ambient occlusion
    uint64_t nodes_visited = 0; ///< BVH nodes visited by camera rays (cost mode only)
    uint64_t truncated = 0;     ///< camera samples whose ray tree hit kMaxRaysPerSample
    RevSurfaceCounters rev_surface;  ///< surfaces of revolution: tests, Newton steps, failures

    uint64_t total() const { return primary + shadow + secondary + occlusion; }
    RayCounts& operator+=(const RayCounts& other);
};

/// The most shadow, secondary and occlusion rays one camera sample may trace. A ray tree doubles with every
/// bounce where a surface both reflects and refracts, so this keeps a deep --bounces finite; the
/// renderer warns when a sample reaches it.
constexpr uint32_t kMaxRaysPerSample = 1u << 16;

/// The lights whose answers a CameraShadows keeps, a bit each: the first this many of a render.
constexpr size_t kMaxCameraShadowLights = 64;

/// The answers to a camera hit's opaque shadow rays, found before shading by tracing them in a
/// packet with those of the neighbouring pixels (trace_camera_shadows): bit i of `known` says light
/// i's answer is here (it is not where shading needs no shadow ray), bit i of `blocked` what it
/// is. Only the camera ray's own hit uses them: shaded there already (`shaded`, `color`), or by the
/// radiance function, with the surface point the rays were traced from (surface_at of the hit, so
/// shading need not find it again). `surface` and `color` are set only where their flags say.
struct CameraShadows {
    uint64_t known = 0;
    uint64_t blocked = 0;
    bool surface_found = false;  ///< whether `surface` holds the hit's point (a hit not `shaded`)
    SurfacePoint surface;
    /// Whether the hit's colour is local shading alone (see shade_camera_hits_locally), found
    /// with these shadow rays: `color`.
    bool shaded = false;
    Vec3f color;
};
static_assert(kMaxCameraShadowLights <= 64, "CameraShadows keeps a light's answer in a bit of a uint64_t");

/// Everything a radiance function knows about the ray it is shading besides the ray itself.
struct TraceContext {
    int depth = 0;                    ///< 0 for a camera ray, +1 per reflection or refraction
    float weight = 1;                 ///< product of the multipliers' magnitudes along the path
    float index_of_refraction = 1;    ///< of the medium the ray travels through (vacuum outside)
    Sampler* sampler = nullptr;       ///< this camera sample's random numbers
    RayCounts* counts = nullptr;      ///< this thread's counters
    uint32_t* rays_left = nullptr;    ///< the camera sample's budget, shared by its whole ray tree
    uint64_t nodes_visited = 0;       ///< BVH nodes the camera ray visited (cost mode)
    RayTree* tree = nullptr;          ///< set by `explain`: every ray is recorded; null when rendering
    const CameraShadows* camera_shadows = nullptr;  ///< for depth 0, when the render loop traced them
    /// The render loop's packet tracer, for rays that leave one point together (ambient
    /// occlusion); null: they are traced one by one. Either way the answers are the same.
    const PacketTracer* tracer = nullptr;
    int record = -1;                  ///< this ray's record in `tree`
};

struct Integrator;

/// The colour that `ray` brings back, given its closest hit (hit.is_hit() false: a miss).
using RadianceFunction = Vec3f (*)(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context);

/// A scene, the settings that shape its rays, and the radiance function of the render mode.
struct Integrator {
    const Scene& scene;
    const std::vector<Light>& lights;  ///< render_lights: the scene's, or the options' in their place
    const RenderOptions& options;
    RadianceFunction radiance;
    float ao_distance = 0;  ///< how far ambient-occlusion rays look (resolved from the options)
    /// Per light, back_faces_skippable for the render's camera: which instances' back faces the
    /// shadow rays of camera hits may pass over (those from camera rays that start at its centre,
    /// leaving on the camera's side and ending clear of the boxes). None without opaque shadow
    /// rays or with RenderOptions::skip_back_faces off.
    std::vector<SkippableBackFaces> back_faces_skippable;
    Vec3f camera_center;  ///< of the render's camera
};

/// The integrator of the options' mode for the scene.
Integrator make_integrator(const Scene& scene, const RenderOptions& options);

/// The radiance function of a render mode (Shaded is the Whitted ray tracer; with 0 bounces and
/// no shadows it is the course's ray caster).
RadianceFunction radiance_function_for(RenderMode mode);

/// Whether every camera ray that hits nothing gets one colour in this mode, whatever its
/// direction, pixel or sample (the background, or black): then the render loop may colour pixels
/// whose rays it knows to miss without tracing them. Not so in cost mode, whose colour counts the
/// nodes each ray visited. A new mode must say.
bool misses_look_alike(RenderMode mode);

/// Traces a secondary ray (t > 0) of `kind` from the shading of `parent`'s ray, counts it,
/// records it when explaining, and returns what the integrator's radiance function makes of it.
/// `child` is the context the ray is traced with (depth, weight, index of refraction already set).
Vec3f trace_ray(const Integrator& integrator, const Ray& ray, RayKind kind, Vec3f multiplier, const TraceContext& parent,
                TraceContext child);

/// What reaches `position` from a light along `to_light` over `distance`: 1 (all of it) when
/// nothing is in the way, 0 when an opaque object is, and with transparent shadows the product
/// of the transparentColor of every surface crossed. Counts and records the shadow ray.
/// With skip_back_faces (the instances of Integrator::back_faces_skippable's entry for the light,
/// for a camera hit's ray that may use them), the back faces it marks are passed over, as
/// occluded() does.
Vec3f light_transmittance(const Integrator& integrator, Vec3f origin, Vec3f to_light, float distance,
                          TraceContext& context, const uint8_t* skip_back_faces = nullptr);

/// The render loop's shortcut for camera samples that need no more than local shading: for each
/// of rays[0..count) whose colour the radiance function would find with local shading alone
/// (shaded mode, a miss or a surface that neither reflects nor transmits, and shadow rays, if any,
/// traced ahead: `shadows` from trace_camera_shadows), sets colors[k] to exactly that colour,
/// counts its shadow rays in `counts` and sets shaded[k]; the others (shaded[k] false) go to the
/// radiance function. One loop over the packet skips the general path's set-up and calls per hit
/// (1.12x on a 1k-triangle render). The course's ray caster is entirely this.
void shade_camera_hits_locally(const Integrator& integrator, const Ray* rays, const Hit* hits, int count,
                               const CameraShadows* shadows, RayCounts& counts, Vec3f* colors, bool* shaded);

/// Whether the integrator's camera hits have shadow rays that trace_camera_shadows can trace ahead
/// in packets: shaded mode, opaque shadows, at least one light.
bool traces_camera_shadows(const Integrator& integrator);

/// How many camera packets' hits trace_camera_shadows takes at once, so that the shadow rays of
/// neighbouring packets towards a light share packets: the four 4x4 packets of the render loop's
/// 8x8 block. (Measured when blocks were packets side by side, 16x4 pixels: 4 packets were
/// 1.0-1.06x faster than 2, which were 1.02-1.07x faster than 1.)
constexpr int kCameraShadowPackets = 4;
constexpr int kMaxCameraShadowHits = kCameraShadowPackets * kMaxPacketLanes;

/// Shadow rays are coherent where camera rays are: from neighbouring hits towards one light. For
/// each light (the first kMaxCameraShadowLights), traces the shadow rays of the hits among rays[0..count) (count <=
/// kMaxCameraShadowHits) together, as packet any-hit queries of up to tracer.lanes() rays, from
/// exactly the origins local shading would use and only where it would trace one, and writes each
/// hit's answers to shadows[k]. The image is the same as with the rays traced one by one; the rays
/// are counted when shading uses their answers.
void trace_camera_shadows(const Integrator& integrator, const PacketTracer& tracer, const Ray* rays, const Hit* hits,
                          int count, CameraShadows* shadows);

/// What the render mode shows along `ray`, whose closest hit is `hit`, traced as a camera ray
/// (depth 0, weight 1, in vacuum): the colour of a pixel whose only ray this is. With `tree`,
/// every ray is recorded there (rays[0] is `ray`). For tests and tools.
Vec3f radiance_along(const Scene& scene, const RenderOptions& options, const Ray& ray, const Hit& hit,
                     RayCounts* counts = nullptr, RayTree* tree = nullptr);

}  // namespace raycast
