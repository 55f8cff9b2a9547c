// The radiance functions of the render modes (render/integrator.h): the Whitted ray tracer of
// the Shaded mode, and the debugging views.
#include <algorithm>
#include <cmath>
#include <limits>

#include "base/simd_clones.h"
#include "render/integrator.h"
#include "render/shade.h"

namespace raycast {

RayCounts& RayCounts::operator+=(const RayCounts& other) {
    primary += other.primary;
    primary_hits += other.primary_hits;
    window_missed += other.window_missed;
    shadow += other.shadow;
    secondary += other.secondary;
    occlusion += other.occlusion;
    nodes_visited += other.nodes_visited;
    truncated += other.truncated;
    rev_surface += other.rev_surface;
    return *this;
}

namespace {

// The record of the context's ray; null when no tree is kept, or when the tree was full (the ray
// was counted as unrecorded, and so are those traced from it).
RayRecord* record_of(const TraceContext& context) {
    return context.tree && context.record >= 0 ? &context.tree->rays[static_cast<size_t>(context.record)] : nullptr;
}

// Takes one ray from the camera sample's budget; false when it is spent (the first time, the
// sample is counted as truncated).
bool take_ray(const TraceContext& context) {
    if (*context.rays_left == 0) return false;
    if (--*context.rays_left == 0) ++context.counts->truncated;
    return true;
}

// Records the surface a ray hit, for explain.
void record_surface(const TraceContext& context, const Hit& hit, const SurfacePoint& surface) {
    RayRecord* record = record_of(context);
    if (!record || !hit.is_hit()) return;
    record->hit = true;
    record->t = hit.t;
    record->object = hit.object;
    record->material = surface.material;
    record->point = surface.position;
    record->normal = record->shading_normal = surface.normal;
}

// A ray's colour, recorded for explain.
Vec3f finish(const TraceContext& context, Vec3f color) {
    if (RayRecord* record = record_of(context)) record->color = color;
    return color;
}

// Where the hit is and how it is oriented towards the ray, recorded for explain.
struct ShadingFrame {
    SurfacePoint surface;
    Vec3f normal;     // the shading normal: flipped towards the viewer on back faces with shade_back
    Vec3f to_viewer;  // unit, −direction
    bool back_face;   // the ray met the side the surface normal points away from
    float travel_scale;  // hit_travel_scale of the point: for offsetting new rays
};

// `known` is the hit's surface point when the render loop already found it (trace_camera_shadows).
ShadingFrame shading_frame(const Scene& scene, const Ray& ray, const Hit& hit, const SurfacePoint* known = nullptr) {
    // Built in place: a copy of the point just written field by field would read it back in
    // wider pieces than were stored, which the processor cannot forward from its store buffer.
    // Each arm initialises the frame's point where it lies, surface_at's result included: a
    // conditional between *known and surface_at(...) would make a temporary point and copy it.
    ShadingFrame frame = known ? ShadingFrame{*known, {}, {}, false, 0}
                               : ShadingFrame{surface_at(scene, ray, hit), {}, {}, false, 0};
    // Likewise the normal comes from where it was written long ago when the point was known: the
    // copy above stores 16 bytes at a time, and the normal straddles two such stores.
    frame.normal = known ? known->normal : frame.surface.normal;
    frame.to_viewer = normalize(-ray.direction);
    frame.back_face = dot(frame.normal, frame.to_viewer) < 0;
    frame.travel_scale = hit_travel_scale(ray.origin, ray.direction, hit.t, frame.surface.geometry_scale);
    if (frame.back_face && scene.conventions.shade_back_faces) frame.normal = -frame.normal;
    return frame;
}

// MIT's rule without -shade_back: a hit on a back face is black and unlit (no shadow rays, no
// secondary rays). The Whitted function, the shadows traced ahead and the render loop's shortcut
// all ask it.
bool blackens_back_faces(const Conventions& conventions) {
    return conventions.black_back_faces && !conventions.shade_back_faces;
}

// Whether shading needs a shadow ray towards a light: a shadow ray can only take the light's
// share away, so where the share is nothing (the surface faces away from the light and shows no
// highlight of it) none is traced. Local shading and the packets traced ahead of it ask this alike.
bool needs_shadow_ray(const Scene& scene, const Material& material, Vec3f normal, Vec3f to_viewer,
                      const Illumination& arriving) {
    const Vec3f c = arriving.color;
    const bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);  // inf·0 is NaN
    return !(finite && reflects_no_light(material, scene.conventions.specular, normal, arriving.to_light, to_viewer));
}

bool needs_shadow_ray(const Scene& scene, const Material& material, const ShadingFrame& frame,
                      const Illumination& arriving) {
    return needs_shadow_ray(scene, material, frame.normal, frame.to_viewer, arriving);
}

// Light `light`'s transmittance from a camera hit whose shadow ray the render loop traced ahead
// (trace_camera_shadows): the answer it found, the ray counted and budgeted as
// light_transmittance counts one. False when there is no such answer.
bool prepared_transmittance(TraceContext& context, size_t light, Vec3f& transmittance) {
    const CameraShadows* prepared = context.depth == 0 ? context.camera_shadows : nullptr;
    if (!prepared || light >= kMaxCameraShadowLights || !((prepared->known >> light) & 1)) return false;
    transmittance = Vec3f{1, 1, 1};
    if (!take_ray(context)) return true;
    ++context.counts->shadow;
    if ((prepared->blocked >> light) & 1) transmittance = Vec3f{0, 0, 0};
    return true;
}

// What the shadow rays of camera hits towards light `light` may skip (scene/back_faces.h), or
// null when nothing.
const SkippableBackFaces* skippable_for(const Integrator& integrator, size_t light) {
    if (light >= integrator.back_faces_skippable.size()) return nullptr;
    const SkippableBackFaces& skippable = integrator.back_faces_skippable[light];
    return skippable.instances.empty() ? nullptr : &skippable;
}

// Whether the shadow ray of a hit of `camera_ray` may skip them: the camera ray starts at the
// camera's centre, and the shadow ray leaves the hit's plane on the camera's side, `offset` off
// it, and ends clear of the boxes after `distance`. local_shading and trace_camera_shadows ask it
// with the same numbers.
[[gnu::always_inline]] inline bool camera_shadow_may_skip(const Integrator& integrator,
                                                          const SkippableBackFaces& skippable, const Ray& camera_ray,
                                                          Vec3f geometric_normal, Vec3f to_light, float offset,
                                                          float distance) {
    return camera_ray.origin == integrator.camera_center &&
           origin_on_camera_side(geometric_normal, to_light, -camera_ray.direction) &&
           ends_clear_of_boxes(skippable, offset, distance);
}

// Ambient plus the diffuse and specular share of every light, with no shadow rays: local_shading
// below when it traces and records nothing (the same operations in the same order).
// shade_camera_hits_locally does the same for a packet's hits, an operation at a time.
Vec3f unshadowed_local_shading(const Integrator& integrator, const Material& material, const ShadingFrame& frame) {
    const Scene& scene = integrator.scene;
    Vec3f color = scene.ambient * material.diffuse;
    for (const Light& light : integrator.lights) {
        const Illumination arriving = illuminate(light, frame.surface.position);
        const LightReflection terms =
            reflect_light_terms(material, scene.conventions.specular, frame.normal, arriving.to_light, frame.to_viewer);
        color += arriving.color * (terms.diffuse + terms.specular);
    }
    return color;
}

// Ambient plus every light, each gated by its shadow ray when shadows are on: the course's
// ray caster is this with no shadows and no ambient.
Vec3f local_shading(const Integrator& integrator, const Ray& ray, const ShadingFrame& frame, TraceContext& context) {
    const Scene& scene = integrator.scene;
    const Material& material = scene.materials[frame.surface.material];
    RayRecord* record = record_of(context);
    if (!integrator.options.shadows && !record) return unshadowed_local_shading(integrator, material, frame);
    const Vec3f ambient = scene.ambient * material.diffuse;
    Vec3f color = ambient;
    // Every shadow ray leaves the point by the same distance, found for the first one traced
    // here (a camera hit's may all have been traced ahead).
    float offset = -1;
    for (size_t i = 0; i < integrator.lights.size(); ++i) {
        const Illumination arriving = illuminate(integrator.lights[i], frame.surface.position);
        Vec3f transmittance{1, 1, 1};
        const bool shadow_ray = integrator.options.shadows && needs_shadow_ray(scene, material, frame, arriving);
        if (shadow_ray && !prepared_transmittance(context, i, transmittance)) {
            if (offset < 0) offset = ray_offset_distance(frame.surface.position, frame.travel_scale);
            const Vec3f origin =
                offset_ray_origin_by(frame.surface.position, frame.surface.geometric_normal, arriving.to_light, offset);
            const SkippableBackFaces* skippable = context.depth == 0 ? skippable_for(integrator, i) : nullptr;
            const bool may_skip = skippable && camera_shadow_may_skip(integrator, *skippable, ray,
                                                                      frame.surface.geometric_normal,
                                                                      arriving.to_light, offset, arriving.distance);
            transmittance = light_transmittance(integrator, origin, arriving.to_light, arriving.distance, context,
                                                may_skip ? skippable->instances.data() : nullptr);
        }
        const bool lit = transmittance != Vec3f{0, 0, 0};
        LightReflection terms{};
        if (lit || record)
            terms = reflect_light_terms(material, scene.conventions.specular, frame.normal, arriving.to_light,
                                        frame.to_viewer);
        Vec3f contribution{};
        if (lit) {
            contribution = arriving.color * (terms.diffuse + terms.specular);
            if (transmittance != Vec3f{1, 1, 1}) contribution = contribution * transmittance;
            color += contribution;
        }
        if (record)
            record->lights.push_back({static_cast<uint32_t>(i), arriving.to_light, arriving.distance, arriving.color,
                                      transmittance, terms.diffuse, terms.specular, contribution, shadow_ray});
    }
    if (record) {
        record->ambient = ambient;
        record->local = color;
    }
    return color;
}

// The Whitted ray tracer (MIT 6.837 assignment 4): local shading, plus reflectiveColor times the
// colour along the mirror direction, plus transparentColor times the colour along the refracted
// direction, each traced while the depth is below the bounce limit and the path's weight stays at
// or above the cutoff. With 0 bounces and no shadows this is exactly the course's ray caster.
//
// The hit and the miss are two functions: a miss (most of many frames) costs a test and the
// background, not the stack frame that shading a hit needs.
Vec3f whitted_hit_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context);

Vec3f whitted_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context) {
    if (!hit.is_hit()) return finish(context, integrator.scene.background);
    return whitted_hit_radiance(integrator, ray, hit, context);
}

[[gnu::noinline]] Vec3f whitted_hit_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit,
                                             TraceContext& context) {
    const Scene& scene = integrator.scene;
    RayRecord* record = record_of(context);
    const CameraShadows* prepared = context.depth == 0 ? context.camera_shadows : nullptr;
    const ShadingFrame frame = shading_frame(scene, ray, hit, prepared && prepared->surface_found ? &prepared->surface : nullptr);
    record_surface(context, hit, frame.surface);
    if (record) {
        record->shading_normal = frame.normal;
        record->back_face = frame.back_face;
    }
    if (frame.back_face && blackens_back_faces(scene.conventions)) {
        if (record) record->note = "back face: black without shade_back (MIT's rule)";
        return finish(context, {0, 0, 0});
    }
    Vec3f color = local_shading(integrator, ray, frame, context);

    const Material& material = scene.materials[frame.surface.material];
    const bool reflects = material.reflective != Vec3f{0, 0, 0};
    const bool transmits = material.transparent != Vec3f{0, 0, 0};
    if ((reflects || transmits) && context.depth >= integrator.options.bounces) {
        if (record) record->note = "reflected and transmitted rays not traced: the bounce limit is reached";
    } else if (reflects || transmits) {
        const Vec3f direction = normalize(ray.direction);
        // The normal as the surface defines it (interpolated on smooth meshes), before any flip for
        // shading: MIT's rule for telling entering from leaving.
        const Vec3f normal = frame.surface.normal;
        const Vec3f plane_normal = frame.surface.geometric_normal;  // which side new rays leave on
        const float offset = ray_offset_distance(frame.surface.position, frame.travel_scale);
        if (reflects) {
            TraceContext child = context;
            child.depth = context.depth + 1;
            child.weight = context.weight * length(material.reflective);
            if (child.weight >= integrator.options.weight_cutoff) {
                const Vec3f mirrored = mirror_direction(direction, normal);
                const Ray reflected{offset_ray_origin_by(frame.surface.position, plane_normal, mirrored, offset),
                                    mirrored};
                const Vec3f incoming = trace_ray(integrator, reflected, RayKind::Reflected, material.reflective, context, child);
                const Vec3f term = material.reflective * incoming;
                color += term;
                if (record) record->reflected = term;
            } else if (record) {
                record->note = "reflected ray not traced: its weight is below the cutoff";
            }
        }
        if (transmits) {
            // Objects sit in vacuum: a ray against the normal enters the material,
            // one along it leaves (MIT's convention, whatever the back-face rule did to shading).
            const bool entering = dot(direction, normal) < 0;
            TraceContext child = context;
            child.depth = context.depth + 1;
            child.weight = context.weight * length(material.transparent);
            child.index_of_refraction = entering ? material.index_of_refraction : 1.0f;
            Vec3f refracted;
            const float from = entering ? 1.0f : material.index_of_refraction;
            if (child.weight < integrator.options.weight_cutoff) {
                if (record) record->note = "transmitted ray not traced: its weight is below the cutoff";
            } else if (!refract_direction(direction, normal, from, child.index_of_refraction, refracted)) {
                if (record) record->total_internal_reflection = true;
            } else {
                const Ray transmitted{
                    offset_ray_origin_by(frame.surface.position, plane_normal, refracted, offset), refracted};
                const Vec3f incoming =
                    trace_ray(integrator, transmitted, RayKind::Transmitted, material.transparent, context, child);
                const Vec3f term = material.transparent * incoming;
                color += term;
                if (record) record->transmitted = term;
            }
        }
    }
    return finish(context, color);
}

Vec3f normals_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context) {
    if (!hit.is_hit()) return finish(context, {});
    const SurfacePoint surface = surface_at(integrator.scene, ray, hit);
    record_surface(context, hit, surface);
    return finish(context, abs(surface.normal));
}

// Depth images need the range of every pixel's distance: the render loop keeps the distances
// and makes the grey levels at the end, so a ray's own colour is black here.
Vec3f depth_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context) {
    if (context.tree && hit.is_hit()) record_surface(context, hit, surface_at(integrator.scene, ray, hit));
    return finish(context, {});
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

Vec3f material_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context) {
    if (!hit.is_hit()) return finish(context, {});
    const SurfacePoint surface = surface_at(integrator.scene, ray, hit);
    record_surface(context, hit, surface);
    return finish(context, material_color(surface.material));
}

// Ambient occlusion: the share of `ao_samples` rays, cosine-distributed about the normal turned
// towards the viewer, that travel `ao_distance` without meeting anything, as grey. A miss is black.
Vec3f ambient_occlusion_radiance(const Integrator& integrator, const Ray& ray, const Hit& hit, TraceContext& context) {
    if (!hit.is_hit()) return finish(context, {});
    const Scene& scene = integrator.scene;
    const SurfacePoint surface = surface_at(scene, ray, hit);
    record_surface(context, hit, surface);
    const Vec3f normal = dot(surface.normal, ray.direction) > 0 ? -surface.normal : surface.normal;
    const float offset = ray_offset_distance(surface.position,
                                             hit_travel_scale(ray.origin, ray.direction, hit.t, surface.geometry_scale));
    const int samples = std::max(1, integrator.options.ao_samples);
    // The rays leave one point, so they share the top of the BVH and most of the boxes near the
    // point: with the render loop's tracer they go in packets, whose box tests serve them all.
    const int lanes = context.tracer ? context.tracer->lanes() : 1;
    const HemisphereBasis basis(normal);
    int open = 0;
    bool budget_left = true;
    for (int first = 0; first < samples && budget_left; first += lanes) {
        const int wanted = std::min(lanes, samples - first);
        int count = 0;
        while (count < wanted && take_ray(context)) ++count;
        budget_left = count == wanted;
        if (count == 0) break;
        context.counts->occlusion += static_cast<uint64_t>(count);
        // The packet's directions together (the numbers, then the directions, each a loop over
        // independent lanes), then its rays.
        static_assert(kMaxPacketLanes <= kMaxDirectionsAtOnce, "a packet's directions are drawn at once");
        float dx[kMaxPacketLanes], dy[kMaxPacketLanes], dz[kMaxPacketLanes];
        draw_cosine_directions(*context.sampler, basis, count, dx, dy, dz);
        Ray probes[kMaxPacketLanes];
        float t_max[kMaxPacketLanes];
        bool blocked[kMaxPacketLanes];
        for (int k = 0; k < count; ++k) {
            const Vec3f direction{dx[k], dy[k], dz[k]};
            probes[k] = {offset_ray_origin_by(surface.position, surface.geometric_normal, direction, offset), direction};
            t_max[k] = integrator.ao_distance;
        }
        if (context.tracer)
            context.tracer->occluded(probes, count, 0, t_max, blocked);
        else if (count == 1)
            blocked[0] = occluded(scene, probes[0], 0, integrator.ao_distance);
        for (int k = 0; k < count; ++k) {
            open += blocked[k] ? 0 : 1;
            if (context.tree) {
                RayRecord record;
                record.kind = RayKind::Occlusion;
                record.parent = context.record;
                record.origin = probes[k].origin;
                record.direction = probes[k].direction;
                record.t_max = integrator.ao_distance;
                record.transmittance = record.color = blocked[k] ? Vec3f{0, 0, 0} : Vec3f{1, 1, 1};
                context.tree->add(std::move(record));
            }
        }
    }
    const float grey = static_cast<float>(open) / static_cast<float>(samples);
    return finish(context, {grey, grey, grey});
}

// Nodes visited on a fixed logarithmic scale (1 → dark blue, 4096 → white), so that crops of
// one image share a scale and merge exactly.
Vec3f cost_radiance(const Integrator&, const Ray&, const Hit&, TraceContext& context) {
    const float x = std::clamp(std::log2(static_cast<float>(context.nodes_visited) + 1) / 12.0f, 0.0f, 1.0f);
    if (x < 0.25f) return finish(context, {0, 0, 0.2f + 3.2f * x});
    if (x < 0.5f) return finish(context, {4 * (x - 0.25f), 0, 1 - 4 * (x - 0.25f)});
    if (x < 0.75f) return finish(context, {1, 4 * (x - 0.5f), 0});
    return finish(context, {1, 1, 4 * (x - 0.75f)});
}

}  // namespace

RadianceFunction radiance_function_for(RenderMode mode) {
    switch (mode) {
        case RenderMode::Shaded: return whitted_radiance;
        case RenderMode::Normals: return normals_radiance;
        case RenderMode::Depth: return depth_radiance;
        case RenderMode::Material: return material_radiance;
        case RenderMode::Cost: return cost_radiance;
        case RenderMode::AmbientOcclusion: return ambient_occlusion_radiance;
    }
    return whitted_radiance;
}

bool misses_look_alike(RenderMode mode) {
    switch (mode) {
        case RenderMode::Shaded: return true;            // the background
        case RenderMode::Normals: return true;           // black
        case RenderMode::Depth: return true;             // black, and no distance
        case RenderMode::Material: return true;          // black
        case RenderMode::AmbientOcclusion: return true;  // black
        case RenderMode::Cost: return false;             // the nodes the ray visited
    }
    return false;
}

Integrator make_integrator(const Scene& scene, const RenderOptions& options) {
    Integrator integrator{scene, render_lights(scene, options), options, radiance_function_for(options.mode), 0, {}, {}};
    integrator.ao_distance = options.ao_distance;
    const Camera& camera = render_camera(scene, options);
    integrator.camera_center = camera.center;
    if (options.shadows && !options.transparent_shadows && options.skip_back_faces)
        for (const Light& light : integrator.lights)
            integrator.back_faces_skippable.push_back(back_faces_skippable(scene, camera, light));
    if (!(integrator.ao_distance > 0)) {
        // A tenth of the scene's diagonal; with nothing bounded (planes only), no limit.
        const float diagonal = scene.bounds.is_empty() ? INFINITY : length(scene.bounds.extent());
        integrator.ao_distance = std::isfinite(diagonal) && diagonal > 0 ? diagonal / 10 : INFINITY;
    }
    return integrator;
}

const char* render_mode_name(RenderMode mode) {
    switch (mode) {
        case RenderMode::Shaded: return "shaded";
        case RenderMode::Normals: return "normals";
        case RenderMode::Depth: return "depth";
        case RenderMode::Material: return "material";
        case RenderMode::Cost: return "cost";
        case RenderMode::AmbientOcclusion: return "ao";
    }
    return "shaded";
}

Vec3f trace_ray(const Integrator& integrator, const Ray& ray, RayKind kind, Vec3f multiplier, const TraceContext& parent,
                TraceContext child) {
    if (!take_ray(child)) {
        if (RayRecord* record = record_of(parent)) record->note = "ray not traced: the sample reached its limit of rays";
        return {0, 0, 0};
    }
    ++child.counts->secondary;
    Hit hit;
    intersect(integrator.scene, ray, 0, hit);
    if (child.tree) {
        RayRecord record;
        record.kind = kind;
        record.parent = parent.record;
        record.depth = child.depth;
        record.origin = ray.origin;
        record.direction = ray.direction;
        record.t_min = 0;
        record.t_max = INFINITY;
        record.weight = child.weight;
        record.multiplier = multiplier;
        record.index_of_refraction = child.index_of_refraction;
        child.record = child.tree->add(std::move(record));  // -1 when the tree is full
    }
    return integrator.radiance(integrator, ray, hit, child);
}

Vec3f light_transmittance(const Integrator& integrator, Vec3f origin, Vec3f to_light, float distance,
                          TraceContext& context, const uint8_t* skip_back_faces) {
    const Scene& scene = integrator.scene;
    int shadow_record = -1;
    if (context.tree) {
        RayRecord record;
        record.kind = RayKind::Shadow;
        record.parent = context.record;
        record.depth = context.depth;
        record.origin = origin;
        record.direction = to_light;
        record.t_min = 0;
        record.t_max = distance;
        record.weight = context.weight;
        shadow_record = context.tree->add(std::move(record));
    }
    const auto finish = [&](Vec3f transmittance, const Hit* blocker, const Ray& ray) {
        if (shadow_record >= 0) {
            RayRecord& record = context.tree->rays[static_cast<size_t>(shadow_record)];
            record.transmittance = transmittance;
            record.color = transmittance;
            if (blocker) {
                const SurfacePoint surface = surface_at(scene, ray, *blocker);
                record.hit = true;
                record.t = blocker->t;
                record.object = blocker->object;
                record.material = surface.material;
                record.point = surface.position;
                record.normal = record.shading_normal = surface.normal;
            }
        }
        return transmittance;
    };
    const Ray ray{origin, to_light};
    if (!take_ray(context)) return finish({1, 1, 1}, nullptr, ray);
    ++context.counts->shadow;
    if (!integrator.options.transparent_shadows) {
        if (!context.tree) return occluded(scene, ray, 0, distance, skip_back_faces) ? Vec3f{0, 0, 0} : Vec3f{1, 1, 1};
        // Explaining: the same answer, but with the blocker named (the nearest hit, which may be
        // a back face when the one that answered is farther).
        if (skip_back_faces && !occluded(scene, ray, 0, distance, skip_back_faces)) return finish({1, 1, 1}, nullptr, ray);
        Hit hit;
        intersect(scene, ray, 0, hit);
        if (hit.is_hit() && hit.t < distance) return finish({0, 0, 0}, &hit, ray);
        return finish({1, 1, 1}, nullptr, ray);
    }
    // Transparent shadows: walk from surface to surface towards the light, each transparent one
    // filtering the light by its transparentColor, an opaque one stopping it.
    const bool point_light = std::isfinite(distance);
    const Vec3f light_position = point_light ? origin + to_light * distance : Vec3f{};
    Vec3f transmittance{1, 1, 1};
    Ray segment = ray;
    float remaining = distance;
    for (;;) {
        Hit hit;
        intersect(scene, segment, 0, hit);
        if (!hit.is_hit() || !(hit.t < remaining)) return finish(transmittance, nullptr, ray);
        const SurfacePoint surface = surface_at(scene, segment, hit);
        transmittance = transmittance * scene.materials[surface.material].transparent;
        if (transmittance == Vec3f{0, 0, 0} || !take_ray(context)) return finish({0, 0, 0}, &hit, segment);
        ++context.counts->shadow;
        segment.origin = offset_ray_origin(surface.position, surface.geometric_normal, to_light,
                                           hit_travel_scale(segment.origin, segment.direction, hit.t,
                                                            surface.geometry_scale));
        if (point_light) remaining = length(light_position - segment.origin);
    }
}

Vec3f radiance_along(const Scene& scene, const RenderOptions& options, const Ray& ray, const Hit& hit, RayCounts* counts,
                     RayTree* tree) {
    const Integrator integrator = make_integrator(scene, options);
    RayCounts local_counts;
    uint32_t budget = kMaxRaysPerSample;
    Sampler sampler(0, 0);
    TraceContext context;
    context.sampler = &sampler;
    context.counts = counts ? counts : &local_counts;
    context.rays_left = &budget;
    if (tree) {
        RayRecord record;
        record.origin = ray.origin;
        record.direction = ray.direction;
        record.t_max = INFINITY;
        context.tree = tree;
        context.record = tree->add(std::move(record));
    }
    return integrator.radiance(integrator, ray, hit, context);
}

namespace {

// A packet's hits in shade_camera_hits_locally, one array per component (LaneVectors): each
// step of shading is then one loop over the hits, which the compiler makes SIMD instructions of,
// 4 hits an instruction, each lane doing the scalar functions' operations in their order (the
// same bits: -ffp-contract=off, and no operation that SIMD rounds otherwise).
struct HitLanes {
    int count = 0;
    int lane[kMaxPacketLanes];  // the hit's place in the packet
    // surface_at's point, its normal made the shading normal by shading_frames (turned towards
    // the viewer on back faces with shade_back)
    SurfaceLanes surface;
    const Material* material[kMaxPacketLanes];
    // The rest of the shading frame (ShadingFrame): the unit vector to the viewer, and whether the
    // hit is on a back face.
    LaneVectors to_viewer;
    bool back_face[kMaxPacketLanes];
    LaneVectors diffuse, specular, color;  // local shading's
    float shininess[kMaxPacketLanes];
};

// shading_frame for every lane, from its surface point and its to_viewer (set to the ray's
// reversed direction): to_viewer made unit, and the surface normal made the shading normal; with
// either back-face rule, back_face (without, it is not set: nothing asks).
[[gnu::always_inline]] inline void shading_frames(HitLanes& hits, const Conventions& conventions) {
    const int n = hits.count;
    float length[kMaxPacketLanes];
    normalize_lanes(hits.to_viewer, length, n);
    if (!conventions.shade_back_faces && !conventions.black_back_faces) return;
    LaneVectors& normal = hits.surface.normal;
    const LaneVectors& to_viewer = hits.to_viewer;
    for (int j = 0; j < n; ++j)
        hits.back_face[j] = normal.x[j] * to_viewer.x[j] + normal.y[j] * to_viewer.y[j] + normal.z[j] * to_viewer.z[j] < 0;
    if (!conventions.shade_back_faces) return;
    // −v is v times −1, bit for bit; a loop that multiplies on a condition would not vectorise.
    for (int j = 0; j < n; ++j) {
        const float sign = hits.back_face[j] ? -1.0f : 1.0f;
        normal.x[j] = normal.x[j] * sign;
        normal.y[j] = normal.y[j] * sign;
        normal.z[j] = normal.z[j] * sign;
    }
}

// What illuminate() finds for every lane's point: the unit direction to the light, the colour
// arriving and (for a point light) the distance.
// Forced inline: local shading and the shadows traced ahead both call it, and with two callers
// GCC made it a call, in the loop over the lights of every packet.
[[gnu::always_inline]] inline void illuminate_lanes(const Light& light, const HitLanes& hits, LaneVectors& to_light,
                                                    LaneVectors& arriving, float* distance) {
    const int n = hits.count;
    if (light.kind == Light::Kind::Directional) {
        for (int j = 0; j < n; ++j) {
            to_light.set(j, -light.direction);
            arriving.set(j, light.color);
            distance[j] = std::numeric_limits<float>::infinity();
        }
        return;
    }
    const Vec3f& a = light.attenuation;
    for (int j = 0; j < n; ++j) {
        to_light.x[j] = light.position.x - hits.surface.position.x[j];
        to_light.y[j] = light.position.y - hits.surface.position.y[j];
        to_light.z[j] = light.position.z - hits.surface.position.z[j];
    }
    normalize_lanes(to_light, distance, n);
    float falloff[kMaxPacketLanes];
    for (int j = 0; j < n; ++j) {
        const float d = distance[j];
        const float f = a.x + a.y * d + a.z * d * d;
        falloff[j] = f > 0 ? f : 1.0f;  // a colour divided by 1 is the colour itself
    }
    for (int j = 0; j < n; ++j) {
        arriving.x[j] = light.color.x / falloff[j];
        arriving.y[j] = light.color.y / falloff[j];
        arriving.z[j] = light.color.z / falloff[j];
    }
}

// The base of reflect_light_terms' specular power for every lane (before the power), and N·L.
RAYCAST_SIMD_CLONES
void specular_bases(SpecularModel model, const HitLanes& hits, const LaneVectors& to_light, float* n_dot_l,
                    float* base) {
    using shade_detail::positive_part;
    const int n = hits.count;
    const LaneVectors& normal = hits.surface.normal;
    const LaneVectors& to_viewer = hits.to_viewer;
    for (int j = 0; j < n; ++j)
        n_dot_l[j] = normal.x[j] * to_light.x[j] + normal.y[j] * to_light.y[j] + normal.z[j] * to_light.z[j];
    if (model == SpecularModel::Phong) {
        for (int j = 0; j < n; ++j) {  // R = 2(L·N)N − L, base max(0, V·R)
            const float twice = 2 * n_dot_l[j];
            const float rx = twice * normal.x[j] - to_light.x[j];
            const float ry = twice * normal.y[j] - to_light.y[j];
            const float rz = twice * normal.z[j] - to_light.z[j];
            base[j] = positive_part(to_viewer.x[j] * rx + to_viewer.y[j] * ry + to_viewer.z[j] * rz);
        }
        return;
    }
    LaneVectors half;  // Blinn: H = normalize(L + V), base max(0, N·H)
    float length[kMaxPacketLanes];
    for (int j = 0; j < n; ++j) {
        half.x[j] = to_light.x[j] + to_viewer.x[j];
        half.y[j] = to_light.y[j] + to_viewer.y[j];
        half.z[j] = to_light.z[j] + to_viewer.z[j];
    }
    normalize_lanes(half, length, n);
    for (int j = 0; j < n; ++j)
        base[j] = positive_part(normal.x[j] * half.x[j] + normal.y[j] * half.y[j] + normal.z[j] * half.z[j]);
}

// needs_shadow_ray for every lane, from specular_bases' N·L and base: where reflect_light_terms
// is exactly zero no shadow ray is traced. reflects_no_light's conditions, which for the course's
// Phong are N·L <= 0, a positive shininess and V·R <= 0 (the base is 0 exactly then), and for
// MIT's clamped Blinn N·L <= 0; the arriving colour must be finite (inf·0 is NaN). MIT's Blinn
// times N·L asks the scalar function lane by lane.
RAYCAST_SIMD_CLONES
void shadow_ray_needs(const Scene& scene, const HitLanes& hits, const LaneVectors& to_light,
                      const LaneVectors& arriving, const float* distance, const float* n_dot_l, const float* base,
                      bool* needs) {
    const int n = hits.count;
    constexpr float kLargest = std::numeric_limits<float>::max();
    switch (scene.conventions.specular) {
        case SpecularModel::Phong:
            for (int j = 0; j < n; ++j) {
                const bool finite = std::fabs(arriving.x[j]) <= kLargest && std::fabs(arriving.y[j]) <= kLargest &&
                                    std::fabs(arriving.z[j]) <= kLargest;
                needs[j] = !(finite && !(n_dot_l[j] > 0) && hits.shininess[j] > 0 && base[j] == 0);
            }
            return;
        case SpecularModel::BlinnClampedByNdotL:
            for (int j = 0; j < n; ++j) {
                const bool finite = std::fabs(arriving.x[j]) <= kLargest && std::fabs(arriving.y[j]) <= kLargest &&
                                    std::fabs(arriving.z[j]) <= kLargest;
                needs[j] = !(finite && !(n_dot_l[j] > 0));
            }
            return;
        case SpecularModel::BlinnTimesNdotL:
            for (int j = 0; j < n; ++j)
                needs[j] = needs_shadow_ray(scene, *hits.material[j], hits.surface.normal.at(j), hits.to_viewer.at(j),
                                            {to_light.at(j), arriving.at(j), distance[j]});
            return;
    }
}

// Adds a light's share to every lane (where lit[j], when `lit` is given): reflect_light_terms'
// diffuse and specular terms (the power found per lane in `power`) times the arriving colour, as
// local shading adds it.
RAYCAST_SIMD_CLONES
void add_light_lanes(SpecularModel model, HitLanes& hits, const LaneVectors& arriving, const float* n_dot_l,
                     const float* power, const bool* lit) {
    using shade_detail::positive_part;
    const int n = hits.count;
    float cosine[kMaxPacketLanes], specular[kMaxPacketLanes];
    for (int j = 0; j < n; ++j) cosine[j] = positive_part(n_dot_l[j]);
    switch (model) {
        case SpecularModel::Phong:
            for (int j = 0; j < n; ++j) specular[j] = power[j];
            break;
        case SpecularModel::BlinnClampedByNdotL:
            for (int j = 0; j < n; ++j) {
                const float lit_power = power[j];  // read on every path, for the select to vectorise
                specular[j] = n_dot_l[j] > 0 ? lit_power : 0.0f;
            }
            break;
        case SpecularModel::BlinnTimesNdotL:
            for (int j = 0; j < n; ++j) specular[j] = power[j] * cosine[j];
            break;
    }
    LaneVectors contribution;
    for (int j = 0; j < n; ++j) {
        const float r = arriving.x[j] * (hits.diffuse.x[j] * cosine[j] + hits.specular.x[j] * specular[j]);
        const float g = arriving.y[j] * (hits.diffuse.y[j] * cosine[j] + hits.specular.y[j] * specular[j]);
        const float b = arriving.z[j] * (hits.diffuse.z[j] * cosine[j] + hits.specular.z[j] * specular[j]);
        contribution.set(j, {r, g, b});
    }
    // Only an addition made on no condition vectorises (GCC moves the addition under the
    // condition, and there it might trap where the scalar code would not add), so the lanes of
    // a light some shadow ray blocked are added one by one.
    LaneVectors& color = hits.color;
    if (!lit) {
        for (int j = 0; j < n; ++j) {
            color.x[j] = color.x[j] + contribution.x[j];
            color.y[j] = color.y[j] + contribution.y[j];
            color.z[j] = color.z[j] + contribution.z[j];
        }
        return;
    }
    for (int j = 0; j < n; ++j)
        if (lit[j]) color.set(j, color.at(j) + contribution.at(j));
}

// Whether whitted_hit_radiance shades a hit on `material` with local shading alone (and records
// nothing): MIT's black back faces are off and the surface neither reflects nor transmits; its
// only rays are then shadow rays.
bool shades_locally(const Scene& scene, const Material& material) {
    return !blackens_back_faces(scene.conventions) && material.reflective == Vec3f{0, 0, 0} &&
           material.transparent == Vec3f{0, 0, 0};
}

// Local shading's first term for every lane (the material's colours gathered): the ambient.
RAYCAST_SIMD_CLONES
void begin_local_shading(const Scene& scene, HitLanes& hits) {
    // Neighbouring hits are mostly on one material: its colours are then spread over the lanes in
    // SIMD. Written lane by lane, the colours were read back at once as vectors, which waited for
    // the single stores to leave the store buffer (most of this function's time in perf).
    bool one_material = true;
    for (int j = 1; j < hits.count; ++j) one_material = one_material && hits.material[j] == hits.material[0];
    if (one_material) {
        const Vec3f diffuse = hits.material[0]->diffuse, specular = hits.material[0]->specular;
        for (int j = 0; j < hits.count; ++j) {
            hits.diffuse.x[j] = diffuse.x;
            hits.diffuse.y[j] = diffuse.y;
            hits.diffuse.z[j] = diffuse.z;
            hits.specular.x[j] = specular.x;
            hits.specular.y[j] = specular.y;
            hits.specular.z[j] = specular.z;
        }
    } else {
        for (int j = 0; j < hits.count; ++j) {
            const Material& material = *hits.material[j];
            hits.diffuse.set(j, material.diffuse);
            hits.specular.set(j, material.specular);
        }
    }
    const Vec3f ambient = scene.ambient;
    for (int j = 0; j < hits.count; ++j) {
        hits.color.x[j] = ambient.x * hits.diffuse.x[j];
        hits.color.y[j] = ambient.y * hits.diffuse.y[j];
        hits.color.z[j] = ambient.z * hits.diffuse.z[j];
    }
}

// One light's share added to the lanes' colours where lit[j] (every lane when `lit` is null), and
// where wanted[j] (every lane when null): its specular power lane by lane (powf: a vector power
// would round otherwise), then the terms in SIMD.
RAYCAST_SIMD_CLONES
void add_light_share(SpecularModel model, HitLanes& hits, const LaneVectors& arriving, const float* n_dot_l,
                     const float* base, const bool* lit, const bool* wanted) {
    float power[kMaxPacketLanes];
    for (int j = 0; j < hits.count; ++j)
        power[j] = (!lit || lit[j]) && (!wanted || wanted[j]) ? shade_detail::specular_power(base[j], hits.shininess[j])
                                                               : 0.0f;
    add_light_lanes(model, hits, arriving, n_dot_l, power, lit);
}

// The bits set in x. __builtin_popcountll is a call into libgcc on the base instruction set (no
// POPCNT), 1% of a render with shadows at 1k triangles; these few operations are not.
uint64_t count_bits(uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555u);
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return (x * 0x0101010101010101u) >> 56;
}

}  // namespace

RAYCAST_SIMD_CLONES
void shade_camera_hits_locally(const Integrator& integrator, const Ray* rays, const Hit* hits, int count,
                               const CameraShadows* shadows, RayCounts& counts, Vec3f* colors, bool* shaded) {
    const Scene& scene = integrator.scene;
    const bool shadow_rays = integrator.options.shadows;
    // With shadow rays, a hit can be shaded here only when they were traced ahead, and then
    // trace_camera_shadows shaded it with them.
    const bool local = integrator.radiance == &whitted_radiance && (!shadow_rays || shadows);
    HitLanes lanes;
    // Neighbouring hits are mostly on one object: its material, and whether that shades
    // locally, are looked up once per run of hits on it.
    uint32_t last_object = kNoObject;
    const Material* material = nullptr;
    bool material_shades_locally = false;
    for (int k = 0; k < count; ++k) {
        shaded[k] = false;
        if (!local) continue;
        if (!hits[k].is_hit()) {
            colors[k] = scene.background;
            shaded[k] = true;
        } else if (shadow_rays) {
            if (!shadows[k].shaded) continue;
            // The colour with its shadow rays, counted here as local_shading counts them. The
            // sample's ray budget is left alone: 64 rays cannot spend it, and no later ray would.
            colors[k] = shadows[k].color;
            counts.shadow += count_bits(shadows[k].known);
            shaded[k] = true;
        } else {
            if (hits[k].object != last_object) {
                last_object = hits[k].object;
                material = &scene.materials[scene.instances[last_object].material];
                material_shades_locally = shades_locally(scene, *material);
            }
            if (!material_shades_locally) continue;
            const int j = lanes.count++;
            lanes.lane[j] = k;
            lanes.material[j] = material;
            lanes.to_viewer.set(j, -rays[k].direction);
            lanes.shininess[j] = material->shininess;
        }
    }
    const int n = lanes.count;
    if (n == 0) return;
    surface_points(scene, rays, hits, lanes.lane, n, lanes.surface);
    shading_frames(lanes, scene.conventions);
    begin_local_shading(scene, lanes);
    for (const Light& light : integrator.lights) {
        LaneVectors to_light, arriving;
        float distance[kMaxPacketLanes], n_dot_l[kMaxPacketLanes], base[kMaxPacketLanes];
        illuminate_lanes(light, lanes, to_light, arriving, distance);
        specular_bases(scene.conventions.specular, lanes, to_light, n_dot_l, base);
        add_light_share(scene.conventions.specular, lanes, arriving, n_dot_l, base, nullptr, nullptr);
    }
    for (int j = 0; j < n; ++j) {
        colors[lanes.lane[j]] = lanes.color.at(j);
        shaded[lanes.lane[j]] = true;
    }
}

bool traces_camera_shadows(const Integrator& integrator) {
    return integrator.radiance == &whitted_radiance && integrator.options.shadows &&
           !integrator.options.transparent_shadows && !integrator.lights.empty();
}

namespace {

// Up to a packet's worth of camera hits, prepared for their shadow rays (trace_camera_shadows):
// each hit as local shading sees it (whitted_hit_radiance and local_shading above), found for the
// hits together, a step at a time (HitLanes), and the current light's terms between making its
// rays and adding its share.
struct ShadowPart {
    CameraShadows* shadows = nullptr;  // the part's pixels' answers
    const Ray* rays = nullptr;         // their camera rays
    HitLanes lanes;
    LaneVectors surface_normal;  // for shadows[k], as surface_at gives it
    // Every shadow ray of a hit leaves its point by the same distance; a black back face is unlit
    // and has none (offset < 0).
    float offset[kMaxPacketLanes];
    // The hits whose colour is local shading alone are shaded here too, each light's share added
    // once its shadow rays are answered (shade_camera_hits_locally takes the colour).
    bool local[kMaxPacketLanes];
    bool any_local = false;
    LaneVectors arriving;
    float n_dot_l[kMaxPacketLanes], base[kMaxPacketLanes];
    int first_ray = 0, ray_count = 0;  // the current light's rays, in the shared array
};

// Fills a part from rays[0..count) (count <= kMaxPacketLanes) up to the lights.
RAYCAST_SIMD_CLONES
void prepare_shadow_part(const Scene& scene, bool shading, const Ray* rays, const Hit* hits, int count,
                         CameraShadows* shadows, ShadowPart& part) {
    part.shadows = shadows;
    part.rays = rays;
    part.any_local = false;
    HitLanes& lanes = part.lanes;
    lanes.count = 0;  // the caller reuses a part that had no hits
    for (int k = 0; k < count; ++k) {
        // Only the flags: `surface` and `color` are read only where they say so, and writing
        // every answer whole (80 bytes) took a share of a render with shadows.
        CameraShadows& answers = shadows[k];
        answers.known = 0;
        answers.blocked = 0;
        answers.surface_found = false;
        answers.shaded = false;
        if (!hits[k].is_hit()) continue;
        const int j = lanes.count++;
        lanes.lane[j] = k;
        lanes.to_viewer.set(j, -rays[k].direction);
    }
    const int n = lanes.count;
    if (n == 0) return;
    surface_points(scene, rays, hits, lanes.lane, n, lanes.surface);
    part.surface_normal = lanes.surface.normal;
    shading_frames(lanes, scene.conventions);
    const bool black_back_faces = blackens_back_faces(scene.conventions);
    for (int j = 0; j < n; ++j) {
        const int k = lanes.lane[j];
        lanes.material[j] = &scene.materials[lanes.surface.material[j]];
        lanes.shininess[j] = lanes.material[j]->shininess;
        part.local[j] = shading && shades_locally(scene, *lanes.material[j]);
        part.any_local = part.any_local || part.local[j];
        part.offset[j] = black_back_faces && lanes.back_face[j]
                             ? -1.0f
                             : ray_offset_distance(lanes.surface.position.at(j),
                                                   hit_travel_scale(rays[k].origin, rays[k].direction, hits[k].t,
                                                                    lanes.surface.geometry_scale[j]));
    }
    if (part.any_local) begin_local_shading(scene, lanes);
}

}  // namespace

RAYCAST_SIMD_CLONES
void trace_camera_shadows(const Integrator& integrator, const PacketTracer& tracer, const Ray* rays, const Hit* hits,
                          int count, CameraShadows* shadows) {
    RAYCAST_DCHECK(count <= kMaxCameraShadowHits);
    const Scene& scene = integrator.scene;
    const bool shading = integrator.radiance == &whitted_radiance && integrator.lights.size() <= kMaxCameraShadowLights;
    constexpr int kMaxParts = kMaxCameraShadowHits / kMaxPacketLanes;
    ShadowPart parts[kMaxParts];
    int part_count = 0;
    for (int first = 0; first < count; first += kMaxPacketLanes) {
        ShadowPart& part = parts[part_count++];
        prepare_shadow_part(scene, shading, rays + first, hits + first, std::min(kMaxPacketLanes, count - first),
                            shadows + first, part);
        if (part.lanes.count == 0) --part_count;  // nothing to trace or shade
    }
    if (part_count == 0) return;
    const size_t lights = std::min(integrator.lights.size(), kMaxCameraShadowLights);
    for (size_t i = 0; i < lights; ++i) {
        // The light's shadow rays from every part, traced in as few packets as hold them: a
        // block's hits that face the light are often a third of it, and a packet costs its walk
        // however few of its lanes hold rays.
        Ray shadow_rays[kMaxCameraShadowHits];
        float t_max[kMaxCameraShadowHits];
        int traced_lane[kMaxCameraShadowHits];  // the hit of each ray, in its part
        // Which rays may pass over back faces: camera_shadow_may_skip, ray by ray.
        const SkippableBackFaces* skippable = skippable_for(integrator, i);
        bool may_skip[kMaxCameraShadowHits];
        int ray_count = 0;
        for (int p = 0; p < part_count; ++p) {
            ShadowPart& part = parts[p];
            HitLanes& lanes = part.lanes;
            LaneVectors to_light;
            float distance[kMaxPacketLanes];
            bool needs[kMaxPacketLanes];
            illuminate_lanes(integrator.lights[i], lanes, to_light, part.arriving, distance);
            specular_bases(scene.conventions.specular, lanes, to_light, part.n_dot_l, part.base);
            shadow_ray_needs(scene, lanes, to_light, part.arriving, distance, part.n_dot_l, part.base, needs);
            part.first_ray = ray_count;
            for (int j = 0; j < lanes.count; ++j) {
                if (part.offset[j] < 0 || !needs[j]) continue;
                shadow_rays[ray_count] = {offset_ray_origin_by(lanes.surface.position.at(j),
                                                               lanes.surface.geometric_normal.at(j), to_light.at(j),
                                                               part.offset[j]),
                                          to_light.at(j)};
                if (skippable)
                    may_skip[ray_count] = camera_shadow_may_skip(integrator, *skippable, part.rays[lanes.lane[j]],
                                                                 lanes.surface.geometric_normal.at(j), to_light.at(j),
                                                                 part.offset[j], distance[j]);
                t_max[ray_count] = distance[j];
                traced_lane[ray_count++] = j;
            }
            part.ray_count = ray_count - part.first_ray;
        }
        bool blocked[kMaxCameraShadowHits];
        for (int first = 0; first < ray_count; first += tracer.lanes())
            tracer.occluded(shadow_rays + first, std::min(tracer.lanes(), ray_count - first), 0, t_max + first,
                            blocked + first, {skippable ? skippable->instances.data() : nullptr, may_skip + first});
        for (int p = 0; p < part_count; ++p) {
            ShadowPart& part = parts[p];
            bool lit[kMaxPacketLanes];  // a lane is lit unless its shadow ray was blocked
            for (int j = 0; j < part.lanes.count; ++j) lit[j] = true;
            bool all_lit = true;
            for (int r = part.first_ray; r < part.first_ray + part.ray_count; ++r) {
                CameraShadows& answers = part.shadows[part.lanes.lane[traced_lane[r]]];
                answers.known |= uint64_t{1} << i;
                answers.blocked |= uint64_t{blocked[r]} << i;
                lit[traced_lane[r]] = !blocked[r];
                all_lit = all_lit && !blocked[r];
            }
            if (part.any_local)
                add_light_share(scene.conventions.specular, part.lanes, part.arriving, part.n_dot_l, part.base,
                                all_lit ? nullptr : lit, part.local);
        }
    }
    for (int p = 0; p < part_count; ++p) {
        ShadowPart& part = parts[p];
        part.lanes.surface.normal = part.surface_normal;
        for (int j = 0; j < part.lanes.count; ++j) {
            CameraShadows& answers = part.shadows[part.lanes.lane[j]];
            answers.shaded = part.local[j];
            if (part.local[j]) {  // the colour is all the render loop takes
                answers.color = part.lanes.color.at(j);
            } else {  // for the radiance function, which would find the point again
                answers.surface = part.lanes.surface.at(j);
                answers.surface_found = true;
            }
        }
    }
}

}  // namespace raycast
