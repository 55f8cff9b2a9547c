#include "render/ray_tree.h"

#include <cmath>
#include <cstdio>
#include <initializer_list>

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

// Writes JSON with two-space indentation; numbers as the shortest decimal that reads back as the
// same float (%.9g always does), and infinity or NaN, which JSON cannot hold, as null.
class JsonWriter {
public:
    std::string take() { return std::move(out_); }

    void open(char bracket) {
        out_ += bracket;
        first_.push_back(true);
    }
    void close(char bracket) {
        const bool empty = first_.back();
        first_.pop_back();
        if (!empty) newline();
        out_ += bracket;
    }
    void key(const char* name) {
        item();
        out_ += '"';
        out_ += name;
        out_ += "\": ";
    }
    // Before a value in an array.
    void item() {
        if (!first_.back()) out_ += ',';
        first_.back() = false;
        newline();
    }

    void number(double x) {
        if (!std::isfinite(x)) {
            out_ += "null";
            return;
        }
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", x);
        out_ += text;
    }
    void integer(long long x) { out_ += std::to_string(x); }
    void null() { out_ += "null"; }
    // A short array on one line.
    void inline_numbers(std::initializer_list<double> values) {
        out_ += '[';
        bool first = true;
        for (const double v : values) {
            if (!first) out_ += ", ";
            first = false;
            number(v);
        }
        out_ += ']';
    }
    void boolean(bool b) { out_ += b ? "true" : "false"; }
    void vec(Vec3f v) { inline_numbers({v.x, v.y, v.z}); }
    void string(const std::string& s) {
        out_ += '"';
        for (const char c : s) {
            if (c == '"' || c == '\\') out_ += '\\';
            if (static_cast<unsigned char>(c) < 0x20) {
                char escaped[8];
                std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
                out_ += escaped;
                continue;
            }
            out_ += c;
        }
        out_ += '"';
    }

    void field(const char* name, double x) { key(name), number(x); }
    void field(const char* name, Vec3f v) { key(name), vec(v); }
    void field(const char* name, bool b) { key(name), boolean(b); }
    void field(const char* name, const std::string& s) { key(name), string(s); }
    void integer_field(const char* name, long long x) { key(name), integer(x); }

private:
    void newline() {
        out_ += '\n';
        out_.append(2 * first_.size(), ' ');
    }

    std::string out_;
    std::vector<bool> first_;  // per open bracket: nothing written in it yet
};

void write_ray(JsonWriter& json, const RayTree& tree, const std::vector<std::vector<int>>& children, int index) {
    const RayRecord& ray = tree.rays[static_cast<size_t>(index)];
    json.open('{');
    json.field("kind", std::string(ray_kind_name(ray.kind)));
    json.integer_field("depth", ray.depth);
    json.field("origin", ray.origin);
    json.field("direction", ray.direction);
    json.field("t_min", ray.t_min);
    json.field("t_max", ray.t_max);
    const bool any_hit = ray.kind == RayKind::Shadow || ray.kind == RayKind::Occlusion;
    if (ray.kind == RayKind::Reflected || ray.kind == RayKind::Transmitted) {
        json.field("multiplier", ray.multiplier);
        json.field("weight", ray.weight);
        json.field("index_of_refraction", ray.index_of_refraction);
    }
    if (ray.hit) {
        json.key("hit");
        json.open('{');
        json.field("t", ray.t);
        json.integer_field("object", ray.object);
        json.integer_field("material", ray.material);
        json.field("point", ray.point);
        json.field("normal", ray.normal);
        if (!any_hit) {
            json.field("shading_normal", ray.shading_normal);
            json.field("side", std::string(ray.back_face ? "back" : "front"));
        }
        json.close('}');
    } else {
        json.key("hit");
        json.null();
    }
    if (any_hit) {
        json.field("transmittance", ray.transmittance);
        json.field("blocked", ray.transmittance == Vec3f{0, 0, 0});
    } else if (ray.hit && (!ray.lights.empty() || ray.local != Vec3f{})) {
        json.key("shading");
        json.open('{');
        json.field("ambient", ray.ambient);
        json.key("lights");
        json.open('[');
        for (const LightTerm& light : ray.lights) {
            json.item();
            json.open('{');
            json.integer_field("light", light.light);
            json.field("to_light", light.to_light);
            json.field("distance", light.distance);
            json.field("arriving", light.arriving);
            json.field("transmittance", light.transmittance);
            json.field("diffuse", light.diffuse);
            json.field("specular", light.specular);
            json.field("contribution", light.contribution);
            json.close('}');
        }
        json.close(']');
        json.field("local", ray.local);
        json.field("reflected", ray.reflected);
        json.field("transmitted", ray.transmitted);
        json.field("total_internal_reflection", ray.total_internal_reflection);
        json.close('}');
    }
    if (!ray.note.empty()) json.field("note", ray.note);
    json.field("color", ray.color);
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
    json.field("mode", e.mode);
    json.integer_field("samples_per_pixel", e.samples_per_pixel);
    json.integer_field("bounces", e.bounces);
    json.field("weight_cutoff", e.weight_cutoff);
    json.field("shadows", e.shadows);
    json.field("transparent_shadows", e.transparent_shadows);
    json.field("color", e.color);
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
        json.close('}');
    }
    json.close(']');
    json.close('}');
    std::string text = json.take();
    text += '\n';
    return text;
}

}  // namespace raycast
