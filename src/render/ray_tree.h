// The tree of rays behind one pixel, for people learning ray tracing (MIT 6.837 shipped a
// ray-tree viewer for its ray-tracing assignment): every camera, shadow, reflected and
// transmitted ray, what it hit, the shading terms and the colour it carried. The integrators fill
// it while they trace (only when asked: rendering passes no tree); `raycast explain` prints it as
// JSON (docs/explain.md).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "math/vec.h"
#include "scene/camera.h"

namespace raycast {

enum class RayKind : uint8_t { Camera, Shadow, Reflected, Transmitted, Occlusion };

/// "camera", "shadow", "reflected", "transmitted" or "occlusion" (ambient occlusion).
const char* ray_kind_name(RayKind kind);

/// One light's share of the local shading at a hit.
struct LightTerm {
    uint32_t light = 0;    ///< index into the render's lights (render_lights: the scene's unless moved)
    Vec3f to_light;        ///< unit
    float distance = 0;    ///< infinity for a directional light
    Vec3f arriving;        ///< the light's colour at the point (after attenuation)
    Vec3f transmittance{1, 1, 1};  ///< what the shadow ray let through (0 when blocked)
    Vec3f diffuse;         ///< kd·max(0, N·L), before the light's colour
    Vec3f specular;        ///< ks·(the model's specular factor), before the light's colour
    Vec3f contribution;    ///< arriving ⊙ transmittance-gated (diffuse + specular)
    /// Whether a shadow ray was traced for it: with shadows on, none is where the light adds
    /// nothing (diffuse and specular both zero).
    bool shadow_ray = false;
};

/// One ray and what became of it.
struct RayRecord {
    RayKind kind = RayKind::Camera;
    int parent = -1;       ///< index of the ray whose shading traced this one
    int depth = 0;
    Vec3f origin, direction;
    float t_min = 0, t_max = 0;
    float weight = 1;                  ///< the path's weight when this ray was traced
    Vec3f multiplier{1, 1, 1};         ///< what its colour is multiplied by in its parent's
    float index_of_refraction = 1;     ///< of the medium it travels through

    // What it hit (camera, reflected and transmitted rays; a shadow ray records its blocker).
    bool hit = false;
    float t = 0;
    uint32_t object = 0;               ///< the object's number in file order
    uint32_t material = 0;
    Vec3f point;
    Vec3f normal;                      ///< as the surface defines it
    Vec3f shading_normal;              ///< after the back-face rule (flipped towards the viewer)
    bool back_face = false;            ///< the ray met the side the normal points away from

    // Shading (rays that hit).
    Vec3f ambient;                     ///< ambient ⊙ kd
    std::vector<LightTerm> lights;
    Vec3f local;                       ///< ambient + every light's contribution
    Vec3f reflected;                   ///< reflectiveColor ⊙ the reflected ray's colour
    Vec3f transmitted;                 ///< transparentColor ⊙ the transmitted ray's colour
    bool total_internal_reflection = false;
    std::string note;                  ///< why something was not traced or not shaded, if so

    // Shadow rays.
    Vec3f transmittance{1, 1, 1};      ///< 1: nothing in the way; 0: blocked

    Vec3f color;                       ///< what the ray brought back
};

/// The most rays the ray trees of one explained pixel hold, all samples together. With the weight
/// cutoff off, a glass scene's tree doubles with every bounce up to the sample's budget of rays
/// (kMaxRaysPerSample): at 80 bounces one pixel was 45,000 rays and 421 MB of JSON. The pixel's
/// colour is still that of every ray; the tree leaves the rest out and counts them.
inline constexpr size_t kMaxExplainedRays = 4096;

/// Every ray of one camera sample; rays[0] is the camera ray. A deque, so that a record stays
/// where it is while the rays traced from it are added.
struct RayTree {
    std::deque<RayRecord> rays;
    size_t capacity = kMaxExplainedRays;  ///< records kept; past it add() keeps none (at least 1)
    uint64_t unrecorded = 0;              ///< rays traced but not kept, past the capacity

    /// Appends a record and returns its index, or -1 when the tree is full (the ray is counted
    /// in `unrecorded`; rays traced from it are not offered).
    int add(RayRecord record) {
        if (rays.size() >= std::max<size_t>(capacity, 1)) {
            ++unrecorded;
            return -1;
        }
        rays.push_back(std::move(record));
        return static_cast<int>(rays.size()) - 1;
    }
};

/// The explanation of one pixel: its colour and one ray tree per sample.
struct PixelExplanation {
    std::string scene;          ///< the scene file
    std::string mode;           ///< the render mode's name
    int x = 0, y = 0;           ///< as asked: column, row with row 0 at the top
    int width = 0, height = 0;  ///< the image
    Camera camera;              ///< what the rays came through, to project points into the image
    int samples_per_pixel = 1;
    int bounces = 0;
    float weight_cutoff = 0;
    bool shadows = false, transparent_shadows = false;
    Vec3f color;                ///< the pixel's value before it becomes bytes
    uint8_t rgb8[3] = {0, 0, 0};  ///< the bytes the image holds
    std::vector<Vec2f> sample_offsets;  ///< where in the pixel each sample went
    std::vector<RayTree> samples;
};

/// The explanation as JSON (the format is documented in docs/explain.md). Numbers are written so
/// that they read back as the same floats; infinity is written as null.
std::string explanation_json(const PixelExplanation& explanation);

}  // namespace raycast
