#include "random_scene.h"

#include <cmath>
#include <initializer_list>

#include "base/error.h"
#include "math/mat4.h"
#include "scene_builders.h"
#include "sceneio/write_obj.h"

namespace raycast::test {

uint32_t Choices::next_bits(int bytes) {
    if (!from_bytes_) {
        // splitmix64 (Steele, Lea and Flood 2014): every seed gives a good stream.
        uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return static_cast<uint32_t>((z ^ (z >> 31)) >> 32);
    }
    uint32_t bits = 0;
    for (int i = 0; i < bytes; ++i) bits = bits << 8 | (position_ < size_ ? data_[position_++] : 0u);
    return bits;
}

uint32_t Choices::below(uint32_t n) {
    if (n <= 1) return 0;
    return next_bits(n <= 256 ? 1 : (n <= 65536 ? 2 : 4)) % n;
}

float Choices::between(float lo, float hi) {
    constexpr uint32_t kSteps = 256;
    return lo + (hi - lo) * static_cast<float>(below(kSteps + 1)) / static_cast<float>(kSteps);
}

namespace {

// Numbers at the edges of what a float holds, and what raycast accepts: the smallest subnormal,
// the smallest normal, values whose squares overflow, the extent limit (1e18) and beyond it.
const std::vector<float> kExtremeNumbers = {0.0f,    -0.0f, 1.4e-45f, 1.17549435e-38f, 1e-30f, 1e-20f, 1e-7f,
                                            1e7f,    1e18f, 1e19f,    1e30f,           3.4e38f, -1e-30f, -1e18f,
                                            -3.4e38f};
const std::vector<float> kExtremePositive = {1.4e-45f, 1e-30f, 1e-20f, 1e-7f, 1e7f, 1e18f, 1e20f, 3.4e38f};

std::string number_text(float value) { return string_printf("%.9g", static_cast<double>(value)); }

// The pieces joined by spaces. Every choice is made inside a braced list, whose elements C++
// evaluates in order: in `a() + " " + b()` the compiler picks the order, and GCC and clang pick
// differently, so a seed or a fuzzer's input would make another scene with each compiler.
std::string words(std::initializer_list<std::string> pieces) {
    std::string text;
    for (const std::string& piece : pieces) text += (text.empty() ? "" : " ") + piece;
    return text;
}

class Generator {
public:
    Generator(Choices& choices, const SceneLimits& limits) : c_(choices), limits_(limits) {}

    RandomScene run() {
        objects_left_ = 1 + static_cast<int>(c_.below(static_cast<uint32_t>(std::max(1, limits_.max_objects))));
        materials_ = 1 + static_cast<int>(c_.below(4));
        // Blocks in the file's usual order, but a camera or background now and then comes last.
        const bool camera_last = c_.one_in(8);
        if (!camera_last) camera();
        if (c_.one_in(4)) background();
        if (!c_.one_in(8)) lights();
        materials();
        out_.text += "Group {\n";
        std::vector<std::string> objects;
        objects.push_back("MaterialIndex " + std::to_string(c_.below(static_cast<uint32_t>(materials_))) + "\n");
        int count = 0;
        while (objects_left_ > 0) {
            objects.push_back(object(1));
            ++count;
            if (c_.one_in(3))
                objects.push_back("MaterialIndex " + std::to_string(c_.below(static_cast<uint32_t>(materials_))) + "\n");
        }
        out_.text += "numObjects " + std::to_string(count) + "\n";
        for (const std::string& o : objects) out_.text += o;
        out_.text += "}\n";
        if (camera_last) camera();
        return std::move(out_);
    }

private:
    // ---- numbers -------------------------------------------------------------------------------

    // A number in [lo, hi], or now and then (when the limits allow) one at the edge of the float
    // range, taken from `extremes`.
    float value(float lo, float hi, const std::vector<float>& extremes = kExtremeNumbers) {
        if (limits_.extreme_numbers && c_.one_in(24)) {
            out_.moderate = false;
            return c_.pick(extremes);
        }
        return c_.between(lo, hi);
    }
    std::string num(float lo, float hi) { return number_text(value(lo, hi)); }
    // Positive (for a radius, an index of refraction, a size), also when extreme.
    std::string positive(float lo, float hi) { return number_text(value(lo, hi, kExtremePositive)); }
    std::string vec3(float lo, float hi) { return words({num(lo, hi), num(lo, hi), num(lo, hi)}); }
    std::string colour() { return words({positive_or_zero(), positive_or_zero(), positive_or_zero()}); }
    std::string positive_or_zero() { return c_.one_in(6) ? std::string("0") : positive(0.05f, 1.0f); }
    // A vector that is not zero (the parser refuses zero directions, normals and axes).
    std::string nonzero_vec3(float lo, float hi) {
        Vec3f v{value(lo, hi), value(lo, hi), value(lo, hi)};
        if (v.x == 0 && v.y == 0 && v.z == 0) v.z = 1;
        return exact(v);
    }

    // ---- blocks --------------------------------------------------------------------------------

    void camera() {
        const bool perspective = !c_.one_in(4);
        // From 4 to 8 units away in any direction, looking at a point near the origin, where
        // the objects are; the up vector is never parallel to the direction.
        Vec3f away{c_.between(-1, 1), c_.between(-1, 1), c_.between(-1, 1)};
        if (dot(away, away) < 0.01f) away = {0, 0, 1};
        const Vec3f center = away * (c_.between(4, 8) / std::sqrt(dot(away, away)));
        const Vec3f direction = Vec3f{c_.between(-1, 1), c_.between(-1, 1), c_.between(-1, 1)} - center;
        const float along_y = std::fabs(direction.y) / std::sqrt(dot(direction, direction) + 1e-20f);
        const char* up = along_y > 0.9f ? "1 0 0" : (c_.one_in(4) ? "0 -1 0" : "0 1 0");
        std::string text = perspective ? "PerspectiveCamera {\n" : "OrthographicCamera {\n";
        text += "  center " + exact(center) + "\n  direction " + exact(direction) + "\n  up " + up + "\n";
        if (perspective)
            text += "  angle " + number_text(c_.between(30, 75)) + "\n";
        else
            text += "  size " + positive(3, 10) + "\n";
        if (!c_.one_in(3)) text += "  width 8\n  height 6\n";  // the build gives the size anyway
        if (limits_.extreme_numbers && c_.one_in(32)) {
            out_.moderate = false;
            text = perspective ? "PerspectiveCamera {\n" : "OrthographicCamera {\n";
            text += "  center " + vec3(-10, 10) + "\n  direction 0 0 -1\n  up 0 1 0\n";
            text += perspective ? "  angle 179.9\n" : "  size " + positive(1, 10) + "\n";
        }
        out_.text += text + "}\n";
    }

    void background() {
        out_.text += "Background {\n  color " + colour() + "\n";
        if (c_.one_in(2)) out_.text += "  ambientLight " + colour() + "\n";
        out_.text += "}\n";
    }

    void lights() {
        const int count = static_cast<int>(c_.below(4));
        out_.text += "Lights {\n  numLights " + std::to_string(count) + "\n";
        for (int i = 0; i < count; ++i) {
            if (c_.one_in(2)) {
                out_.text += words({"  DirectionalLight { direction", nonzero_vec3(-1, 1), "color", colour(), "}\n"});
            } else {
                out_.text += words({"  PointLight { position", vec3(-10, 10), "color", colour()});
                // Attenuation: none negative, not all zero.
                if (c_.one_in(2))
                    out_.text += words({" attenuation", positive(0.5f, 2), positive_or_zero(), positive_or_zero()});
                out_.text += " }\n";
            }
        }
        out_.text += "}\n";
    }

    void materials() {
        out_.text += "Materials {\n  numMaterials " + std::to_string(materials_) + "\n";
        for (int i = 0; i < materials_; ++i) {
            out_.text += c_.one_in(2) ? "  PhongMaterial {" : "  Material {";
            // Fields in any order: each is offered in a shuffled-by-choice sequence.
            if (!c_.one_in(4)) out_.text += " diffuseColor " + colour();
            if (c_.one_in(2)) out_.text += " specularColor " + colour();
            if (c_.one_in(2)) out_.text += words({c_.one_in(2) ? " shininess" : " exponent", positive(1, 64)});
            if (c_.one_in(3)) out_.text += " reflectiveColor " + colour();
            if (c_.one_in(3)) out_.text += " transparentColor " + colour();
            if (c_.one_in(3)) out_.text += " indexOfRefraction " + positive(1, 2.5f);
            if (c_.one_in(16)) out_.text += " texture \"textures/none.ppm\"";
            out_.text += " }\n";
        }
        out_.text += "}\n";
    }

    // ---- objects -------------------------------------------------------------------------------

    // One object (and what it holds), which spends at least one of the objects left.
    std::string object(int depth) {
        std::string text;
        const bool may_nest = depth <= limits_.max_depth && objects_left_ > 1;
        const uint32_t kinds = may_nest ? 9 : 6;
        switch (c_.below(kinds)) {
            case 0: text = sphere(); break;
            case 1: text = c_.one_in(2) ? plane() : sphere(); break;  // planes fill much of the picture: fewer
            case 2: text = triangle(); break;
            case 3:
            case 4: text = triangle_mesh(); break;
            case 5: text = c_.one_in(8) ? curve() : rev_surface(); break;
            case 6: text = group(depth); break;
            default: text = transform(depth); break;  // 7 and 8: transforms are where most can go wrong
        }
        if (limits_.max_deep_nesting > 0 && c_.one_in(32)) text = deep_nesting(text);
        return text;
    }

    std::string sphere() {
        --objects_left_;
        return words({"Sphere { center", vec3(-2, 2), "radius", positive(0.4f, 1.6f), "}\n"});
    }

    std::string plane() {
        --objects_left_;
        return words({"Plane { normal", nonzero_vec3(-1, 1), "offset", num(-4, 4), "}\n"});
    }

    std::string triangle() {
        --objects_left_;
        // Now and then a degenerate one (a warning, never seen).
        if (c_.one_in(16)) return "Triangle { vertex0 0 0 0 vertex1 1 1 1 vertex2 2 2 2 }\n";
        return words({"Triangle { vertex0", vec3(-2.5f, 2.5f), "vertex1", vec3(-2.5f, 2.5f), "vertex2",
                      vec3(-2.5f, 2.5f), "}\n"});
    }

    // The control points of a profile in the z = 0 plane (as RevSurface requires): x > 0 mostly,
    // now and then crossing the axis, which the surface must take too.
    std::string controls(bool bezier) {
        // A Bezier curve takes 3k + 1 points (the course's rule); a B-spline at least 4.
        const int points = bezier ? (c_.one_in(4) ? 7 : 4) : 4 + static_cast<int>(c_.below(4));
        const float x_low = c_.one_in(6) ? -0.6f : 0.05f;
        std::string text = bezier ? "BezierCurve { controls" : "BsplineCurve { controls";
        // Never numbers at the edges of the float range here: the exact surface test costs tens of
        // microseconds a ray in the fuzz build, and a profile a billion billion wide lets a ray
        // tree spend its whole budget (65,536 rays a sample, minutes a scene) meeting it again. The
        // curve grammar's edges are fuzzed as text by fuzz_scene_parser.
        for (int i = 0; i < points; ++i)
            text += words({" [", number_text(c_.between(x_low, 1.6f)), number_text(c_.between(-1.8f, 1.8f)), "0 ]"});
        return text + " }";
    }

    std::string rev_surface() {
        --objects_left_;
        return "RevSurface { profile " + controls(c_.one_in(2)) + " }\n";
    }

    // A curve alone draws nothing (a warning), but takes an object's place.
    std::string curve() {
        --objects_left_;
        return controls(c_.one_in(2)) + "\n";
    }

    std::string triangle_mesh() {
        --objects_left_;
        // A mesh used twice is loaded once: reuse an earlier file now and then.
        std::string path;
        if (!out_.meshes.empty() && c_.one_in(3)) {
            auto it = out_.meshes.begin();
            std::advance(it, c_.below(static_cast<uint32_t>(out_.meshes.size())));
            path = it->first;
        } else {
            path = "mesh" + std::to_string(out_.meshes.size()) + ".obj";
            out_.meshes[path] = limits_.closed_meshes && c_.one_in(2) ? closed_obj_file() : obj_file();
        }
        const std::string quoted = c_.one_in(4) ? "\"" + path + "\"" : path;
        return "TriangleMesh { obj_file " + quoted + " }\n";
    }

    // An OBJ file with every index form: v, v/t, v//n, v/t/n, negative indices, polygons.
    std::string obj_file() {
        const std::string eol = c_.one_in(8) ? "\r\n" : "\n";
        const int vertices = 3 + static_cast<int>(c_.below(static_cast<uint32_t>(std::max(1, limits_.max_mesh_vertices - 2))));
        const int normals = c_.one_in(2) ? 0 : 1 + static_cast<int>(c_.below(3));
        const int texcoords = 1 + static_cast<int>(c_.below(2));
        std::string text = c_.one_in(4) ? "# a random mesh" + eol + "o thing" + eol : "";
        // A box around the origin, with a random size and place, so that meshes overlap and nest.
        const float scale = c_.between(1, 2.5f), dx = c_.between(-1.5f, 1.5f), dy = c_.between(-1.5f, 1.5f),
                    dz = c_.between(-1.5f, 1.5f);
        for (int i = 0; i < vertices; ++i)
            text += words({"v", number_text(dx + scale * c_.between(-1, 1)), number_text(dy + scale * c_.between(-1, 1)),
                           number_text(dz + scale * c_.between(-1, 1))}) +
                    eol;
        for (int i = 0; i < normals; ++i) text += "vn " + nonzero_vec3(-1, 1) + eol;
        for (int i = 0; i < texcoords; ++i) text += words({"vt", num(0, 1), num(0, 1)}) + eol;
        // A mesh without faces now and then: a warning, and nothing drawn.
        const int faces = c_.one_in(16) ? 0 : vertices + static_cast<int>(c_.below(static_cast<uint32_t>(vertices)));
        for (int f = 0; f < faces; ++f) {
            const int corners = c_.one_in(4) ? 4 + static_cast<int>(c_.below(2)) : 3;
            const uint32_t form = c_.below(normals > 0 ? 4 : 2);  // 0: v, 1: v/t, 2: v//n, 3: v/t/n
            text += "f";
            for (int k = 0; k < corners; ++k) {
                const int v = 1 + static_cast<int>(c_.below(static_cast<uint32_t>(vertices)));
                // Negative indices count back from the last vertex (all come before the faces).
                text += " " + (c_.one_in(4) ? std::to_string(v - vertices - 1) : std::to_string(v));
                const int t = 1 + static_cast<int>(c_.below(static_cast<uint32_t>(texcoords)));
                const int n = normals > 0 ? 1 + static_cast<int>(c_.below(static_cast<uint32_t>(normals))) : 0;
                if (form == 1) text += "/" + std::to_string(t);
                if (form == 2) text += "//" + std::to_string(n);
                if (form == 3) text += "/" + std::to_string(t) + "/" + std::to_string(n);
            }
            text += eol;
        }
        return text;
    }

    // A closed mesh: a UV sphere of 2 to 5 rings and 3 to 8 segments, its poles and ring vertices
    // moved along their radii, or one time in three anywhere in its box (it may then pass through
    // itself), wound outwards or, one time in three, inwards.
    std::string closed_obj_file() {
        const int rings = 2 + static_cast<int>(c_.below(4)), segments = 3 + static_cast<int>(c_.below(6));
        const float scale = c_.between(1, 2.5f), dx = c_.between(-1.5f, 1.5f), dy = c_.between(-1.5f, 1.5f),
                    dz = c_.between(-1.5f, 1.5f);
        const bool anywhere = c_.one_in(3), inwards = c_.one_in(3);
        TriangleMesh mesh = sphere_mesh({0, 0, 0}, 1, rings, segments);  // tests/scene_builders.h
        for (Vec3f& p : mesh.positions) {
            const float r = anywhere ? 1.0f : c_.between(0.3f, 1);
            if (anywhere) {
                p.x = c_.between(-1, 1);
                p.y = c_.between(-1, 1);
                p.z = c_.between(-1, 1);
            }
            p = {dx + scale * r * p.x, dy + scale * r * p.y, dz + scale * r * p.z};
        }
        return "# a closed mesh\n" + obj_text(inwards ? inside_out(std::move(mesh)) : mesh);
    }

    std::string group(int depth) {
        std::vector<std::string> children;
        const int wanted = 1 + static_cast<int>(c_.below(3));
        for (int i = 0; i < wanted && objects_left_ > 0; ++i) {
            if (c_.one_in(3))
                children.push_back("MaterialIndex " + std::to_string(c_.below(static_cast<uint32_t>(materials_))) + "\n");
            children.push_back(object(depth + 1));
        }
        int count = 0;
        for (const std::string& child : children) count += child.rfind("MaterialIndex", 0) == 0 ? 0 : 1;
        std::string text = "Group {\nnumObjects " + std::to_string(count) + "\n";
        for (const std::string& child : children) text += child;
        return text + "}\n";
    }

    std::string transform(int depth) {
        std::string text = "Transform {\n";
        const int items = static_cast<int>(c_.below(4));
        for (int i = 0; i < items; ++i) text += transform_item();
        return text + object(depth + 1) + "}\n";
    }

    std::string transform_item() {
        switch (c_.below(9)) {
            case 0: return words({"  Scale", scale_factor(), scale_factor(), scale_factor()}) + "\n";
            case 1: return "  UniformScale " + scale_factor() + "\n";
            case 2: return "  Translate " + vec3(-1.5f, 1.5f) + "\n";
            case 3: return "  XRotate " + num(-180, 180) + "\n";
            case 4: return "  YRotate " + num(-180, 180) + "\n";
            case 5: return "  ZRotate " + num(-180, 180) + "\n";
            case 6: return words({"  Rotate {", nonzero_vec3(-1, 1), num(-180, 180), "}\n"});
            default: return matrix_item();
        }
    }

    // A factor that is never 0 (the parser refuses a zero scale): 0.3 to 2 in magnitude, now and
    // then negative (a mirror image: the winding and the normals flip).
    std::string scale_factor() {
        if (limits_.extreme_numbers && c_.one_in(24)) {
            out_.moderate = false;
            const float magnitude = c_.pick(kExtremePositive);
            return number_text(c_.one_in(2) ? -magnitude : magnitude);
        }
        const float magnitude = c_.between(0.3f, 2);
        return number_text(c_.one_in(4) ? -magnitude : magnitude);
    }

    // Matrix4f (the course's, column by column) or Matrix (MIT's, row by row) holding a
    // well-conditioned affine map, made here from rotations, a scale and a translation.
    std::string matrix_item() {
        const Vec3f offset{c_.between(-2, 2), c_.between(-2, 2), c_.between(-2, 2)};
        const Vec3f axis{c_.between(-1, 1), c_.between(-1, 1), 1};
        const float degrees = c_.between(-180, 180);
        const Vec3f scale{c_.between(0.5f, 2), c_.between(0.5f, 2), c_.between(0.5f, 2)};
        const Mat4 m = Mat4::translate(offset) * Mat4::rotate(axis, degrees) * Mat4::scale(scale);
        const bool columns = c_.one_in(2);
        std::string text = columns ? "  Matrix4f {" : "  Matrix {";
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) text += " " + number_text(columns ? m.m[j][i] : m.m[i][j]);
        return text + " }\n";
    }

    // The object inside many groups or identity transforms: the recursion of the parser and
    // the builder, and (for transforms) the product of many matrices.
    std::string deep_nesting(const std::string& inner) {
        const int levels = 1 + static_cast<int>(c_.below(static_cast<uint32_t>(limits_.max_deep_nesting)));
        const bool groups = c_.one_in(2);
        std::string text;
        for (int i = 0; i < levels; ++i) text += groups ? "Group { numObjects 1\n" : "Transform { Translate 0 0 0\n";
        text += inner;
        for (int i = 0; i < levels; ++i) text += "}\n";
        return text;
    }

    // A vector written so that the parser reads exactly it back.
    static std::string exact(Vec3f v) { return number_text(v.x) + " " + number_text(v.y) + " " + number_text(v.z); }

    Choices& c_;
    const SceneLimits& limits_;
    RandomScene out_;
    int objects_left_ = 0;
    int materials_ = 1;
};

}  // namespace

RandomScene random_scene(Choices& choices, const SceneLimits& limits) { return Generator(choices, limits).run(); }

RandomRender random_render(Choices& choices, int width, int height, const std::vector<RenderMode>& modes) {
    RandomRender settings;
    SceneBuildOptions& build = settings.build;
    build.width = width;
    build.height = height;
    build.threads = 1;
    build.conventions = choices.one_in(2) ? Conventions::course() : Conventions::mit6837();
    if (choices.one_in(4)) build.conventions.fov_axis = choices.one_in(2) ? FovAxis::Both : FovAxis::Vertical;
    if (choices.one_in(3)) build.conventions.shade_back_faces = true;
    if (choices.one_in(4)) build.conventions.specular = SpecularModel::BlinnTimesNdotL;

    RenderOptions& render = settings.render;
    render.threads = 1;
    render.mode = choices.pick(modes);
    render.samples_per_pixel = choices.one_in(3) ? 1 + static_cast<int>(choices.below(4)) : 1;
    render.shadows = choices.one_in(2);
    render.transparent_shadows = choices.one_in(3);
    render.bounces = choices.one_in(2) ? static_cast<int>(choices.below(5)) : 0;
    render.weight_cutoff = choices.one_in(4) ? choices.between(0, 0.5f) : 0.001f;
    render.ao_samples = 1 + static_cast<int>(choices.below(4));
    if (choices.one_in(4)) render.ao_distance = choices.between(0.1f, 4);
    if (choices.one_in(4)) {
        render.depth_near = choices.between(0, 5);
        render.depth_far = render.depth_near + choices.between(0.5f, 10);
    }
    if (choices.one_in(6)) {
        settings.lens_radius = choices.between(0.01f, 0.3f);
        settings.focus_distance = choices.between(1, 15);
    }
    return settings;
}

void apply_lens(const RandomRender& settings, Scene& scene) {
    if (settings.lens_radius <= 0) return;
    scene.camera.lens_radius = settings.lens_radius;
    scene.camera.focus_distance = settings.focus_distance;
}

}  // namespace raycast::test
