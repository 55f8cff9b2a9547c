#include "render/ray_tree.h"

#include "base/json_writer.h"

#include <cmath>
#include <cstdio>

namespace raycast {

const char* ray_kind_name(RayKind kind) {
    switch (kind) {
        case RayKind::Camera: return "camera";
        case RayKind::Shadow: return "shadow";
        case RayKind::Reflected: return "reflected";
        case RayKind::Transmitted: return "transmitted";
        case RayKind::Occlusion: return "occlusion";
    }
    return "camera";
}

namespace {

void vec_field(JsonWriter& json, const char* name, Vec3f v) { json.numbers_field(name, {v.x, v.y, v.z}); }

void write_ray(JsonWriter& json, const RayTree& tree, const std::vector<std::vector<int>>& children, int index) {
    const RayRecord& ray = tree.rays[static_cast<size_t>(index)];
    json.open('{');
    json.field("kind", std::string(ray_kind_name(ray.kind)));
    json.integer_field("depth", ray.depth);
    vec_field(json, "origin", ray.origin);
    vec_field(json, "direction", ray.direction);
    json.field("t_min", ray.t_min);
    json.field("t_max", ray.t_max);
    const bool any_hit = ray.kind == RayKind::Shadow || ray.kind == RayKind::Occlusion;
    if (ray.kind == RayKind::Reflected || ray.kind == RayKind::Transmitted) {
        vec_field(json, "multiplier", ray.multiplier);
        json.field("weight", ray.weight);
        json.field("index_of_refraction", ray.index_of_refraction);
    }
    if (ray.hit) {
        json.key("hit");
        json.open('{');
        json.field("t", ray.t);
        json.integer_field("object", ray.object);
        json.integer_field("material", ray.material);
        vec_field(json, "point", ray.point);
        vec_field(json, "normal", ray.normal);
        if (!any_hit) {
            vec_field(json, "shading_normal", ray.shading_normal);
            json.field("side", std::string(ray.back_face ? "back" : "front"));
        }
        json.close('}');
    } else {
        json.key("hit");
        json.null();
    }
    if (any_hit) {
        vec_field(json, "transmittance", ray.transmittance);
        json.field("blocked", ray.transmittance == Vec3f{0, 0, 0});
    } else if (ray.hit && (!ray.lights.empty() || ray.local != Vec3f{})) {
        json.key("shading");
        json.open('{');
        vec_field(json, "ambient", ray.ambient);
        json.key("lights");
        json.open('[');
        for (const LightTerm& light : ray.lights) {
            json.item();
            json.open('{');
            json.integer_field("light", light.light);
            vec_field(json, "to_light", light.to_light);
            json.field("distance", light.distance);
            vec_field(json, "arriving", light.arriving);
            vec_field(json, "transmittance", light.transmittance);
            vec_field(json, "diffuse", light.diffuse);
            vec_field(json, "specular", light.specular);
            vec_field(json, "contribution", light.contribution);
            json.field("shadow_ray", light.shadow_ray);
            json.close('}');
        }
        json.close(']');
        vec_field(json, "local", ray.local);
        vec_field(json, "reflected", ray.reflected);
        vec_field(json, "transmitted", ray.transmitted);
        json.field("total_internal_reflection", ray.total_internal_reflection);
        json.close('}');
    }
    if (!ray.note.empty()) json.field("note", ray.note);
    vec_field(json, "color", ray.color);
    json.key("children");
    json.open('[');
    for (const int child : children[static_cast<size_t>(index)]) {
        json.item();
        write_ray(json, tree, children, child);
    }
    json.close(']');
    json.close('}');
}

}  // namespace

std::string explanation_json(const PixelExplanation& e) {
    JsonWriter json;
    json.open('{');
    json.field("scene", e.scene);
    json.integer_field("x", e.x);
    json.integer_field("y", e.y);
    json.key("image_size");
    json.inline_numbers({double(e.width), double(e.height)});
    json.key("camera");
    json.open('{');
    const Camera& c = e.camera;
    json.field("projection", std::string(c.projection == Camera::Projection::Perspective ? "perspective" : "orthographic"));
    vec_field(json, "center", c.center);
    vec_field(json, "direction", c.direction);
    vec_field(json, "horizontal", c.horizontal);
    vec_field(json, "up", c.up);
    json.field("fx", c.fx);
    json.field("fy", c.fy);
    json.field("cx", c.cx);
    json.field("cy", c.cy);
    json.field("pixel_offset", c.pixel_offset);
    json.field("lens_radius", c.lens_radius);
    json.close('}');
    json.field("mode", e.mode);
    json.integer_field("samples_per_pixel", e.samples_per_pixel);
    json.integer_field("bounces", e.bounces);
    json.field("weight_cutoff", e.weight_cutoff);
    json.field("shadows", e.shadows);
    json.field("transparent_shadows", e.transparent_shadows);
    vec_field(json, "color", e.color);
    json.key("rgb8");
    json.inline_numbers({double(e.rgb8[0]), double(e.rgb8[1]), double(e.rgb8[2])});
    json.key("samples");
    json.open('[');
    for (size_t s = 0; s < e.samples.size(); ++s) {
        const RayTree& tree = e.samples[s];
        std::vector<std::vector<int>> children(tree.rays.size());
        for (size_t i = 1; i < tree.rays.size(); ++i)
            children[static_cast<size_t>(tree.rays[i].parent)].push_back(static_cast<int>(i));
        json.item();
        json.open('{');
        json.key("offset");
        json.inline_numbers({e.sample_offsets[s].x, e.sample_offsets[s].y});
        json.key("ray");
        if (tree.rays.empty())
            json.null();
        else
            write_ray(json, tree, children, 0);
        json.integer_field("unrecorded_rays", static_cast<long long>(tree.unrecorded));
        json.close('}');
    }
    json.close(']');
    json.close('}');
    std::string text = json.take();
    text += '\n';
    return text;
}

}  // namespace raycast
