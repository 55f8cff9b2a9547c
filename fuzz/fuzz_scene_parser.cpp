// Fuzz target: scene text -> parse_scene -> build_scene -> render_image, the whole pipeline on
// arbitrary bytes. An InputError from the parser or the builder is an expected outcome; anything
// else is a finding: a crash, a sanitizer report, a hang, another exception, or a broken promise
// that the headers make and that this target checks:
//  - an InputError holds 1..kMaxReportedErrors errors (plus the "too many errors" note), each
//    located inside the text (line and column count from 1, columns in bytes);
//  - parse_float and parse_int give what strtof and strtoll give (base/parse_number.h), checked
//    on the first token;
//  - the image does not depend on how primary rays are traced (render.h, intersect_packet.h):
//    one ray at a time, portable packets and the CPU's widest packets give the same floats;
//  - a crop window holds exactly the pixels of the full image (render.h);
//  - a scene whose numbers are all moderate (see Moderate below) renders no NaN or infinity.
// Meshes are not read from disk: every TriangleMesh gets a small built-in mesh, so the mesh
// instancing path of build_scene runs too. Images are 5x4, so one input renders in microseconds.
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "base/error.h"
#include "base/limits.h"
#include "base/parse_number.h"
#include "render/render.h"
#include "scene/build_scene.h"
#include "sceneio/parse_scene.h"
#include "sceneio/text_check.h"

namespace {

using namespace raycast;

constexpr int kWidth = 5, kHeight = 4;  // odd width: packets of 4, 8 and 16 lanes run part-full
// Crop rows count from the top: rows 1..2 from the top are rows 1..2 from the bottom of 4 rows.
constexpr CropWindow kCrop{1, 1, 4, 3};

[[noreturn]] void finding(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz_scene_parser: FINDING: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
    std::abort();
}

// ---- parse_float against strtof ----------------------------------------------------------------

void check_numbers(const uint8_t* data, size_t size) {
    size_t n = 0;
    while (n < size && n < 80 && data[n] != ' ' && data[n] != '\n' && data[n] != '\t' && data[n] != '\r') ++n;
    const char* first = reinterpret_cast<const char*>(data);
    float value = 0;
    const NumberResult result = parse_float(first, first + n, value);
    if (result.status == NumberStatus::Invalid) {
        if (result.end != first) finding("parse_float: Invalid but end moved");
        return;
    }
    if (result.end <= first || result.end > first + n) finding("parse_float: end outside the token");
    const std::string used(first, result.end);
    if (used.find('\0') != std::string::npos) finding("parse_float: read past a NUL byte", used);
    errno = 0;
    char* end = nullptr;
    const float expected = std::strtof(used.c_str(), &end);
    if (end != used.c_str() + used.size())
        finding("parse_float consumed more than strtof", used + " (strtof stops after " +
                                                              std::to_string(end - used.c_str()) + " bytes)");
    if (result.status == NumberStatus::OutOfRange) {
        if (!std::isinf(expected)) finding("parse_float: OutOfRange but strtof gives a finite float", used);
        return;
    }
    uint32_t a = 0, b = 0;
    std::memcpy(&a, &value, sizeof a);
    std::memcpy(&b, &expected, sizeof b);
    if (a != b)
        finding("parse_float differs from strtof",
                used + string_printf(": %.9g (0x%08x) vs %.9g (0x%08x)", double(value), a, double(expected), b));

    int64_t integer = 0;
    const NumberResult int_result = parse_int(first, first + n, integer);
    if (int_result.status != NumberStatus::Invalid) {
        // fuzz/regressions/fuzz_scene_parser-parse-int-wraparound: 2^64 + 1 was once parsed as 1.
        const std::string digits(first, int_result.end);
        errno = 0;
        const long long expected_integer = std::strtoll(digits.c_str(), nullptr, 10);
        if (int_result.status == NumberStatus::OutOfRange ? errno != ERANGE : expected_integer != integer)
            finding("parse_int differs from strtoll", digits);
    }
}

// ---- diagnostics -------------------------------------------------------------------------------

void check_diagnostics(const InputError& error, std::string_view file_text) {
    // Line starts, to check that every location lies inside the text, as the parser reads it
    // (classic Mac line breaks count as line breaks).
    std::string converted;
    const std::string_view text = as_unix_text(file_text, converted);
    std::vector<size_t> line_start{0};
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') line_start.push_back(i + 1);
    int errors = 0;
    for (const Diagnostic& d : error.diagnostics()) {
        if (d.severity == Severity::Error) ++errors;
        if (d.location.file != "fuzz.txt") finding("diagnostic names another file", d.location.file);
        const int line = d.location.line;
        if (line < 0 || d.location.column < 0) finding("negative line or column", format_diagnostic(d));
        if (line > 0) {
            if (static_cast<size_t>(line) > line_start.size()) finding("diagnostic past the last line", format_diagnostic(d));
            const size_t begin = line_start[static_cast<size_t>(line) - 1];
            const size_t end = static_cast<size_t>(line) < line_start.size() ? line_start[static_cast<size_t>(line)] - 1
                                                                              : text.size();
            if (d.location.column < 1 || static_cast<size_t>(d.location.column) > end - begin + 1)
                finding("diagnostic column outside its line", format_diagnostic(d));
        }
        if (d.message.empty()) finding("diagnostic without a message");
        (void)format_diagnostic(d);
    }
    if (errors < 1 || errors > kMaxReportedErrors + 1)
        finding("InputError with a wrong number of errors", std::to_string(errors));
    (void)error.what();
}

// ---- moderate scenes ---------------------------------------------------------------------------

// Numbers between 1e-3 and 1e3 in magnitude (or 0): nothing a renderer of such a scene computes
// should overflow or become NaN, so a non-finite pixel is a bug, not an extreme input.
struct Moderate {
    bool ok = true;
    void operator()(float v) {
        const float a = std::fabs(v);
        if (!(a == 0 || (a >= 1e-3f && a <= 1e3f))) ok = false;
    }
    void operator()(Vec3f v) {
        (*this)(v.x);
        (*this)(v.y);
        (*this)(v.z);
    }
};

// Gives every TriangleMesh the one built-in mesh and checks the numbers of the objects.
void prepare_objects(ObjectDesc& object, Moderate& moderate) {
    switch (object.kind) {
        case ObjectDesc::Kind::Sphere:
            moderate(object.sphere.center);
            moderate(object.sphere.radius);
            break;
        case ObjectDesc::Kind::Plane:
            moderate(object.plane.normal);
            moderate(object.plane.offset);
            break;
        case ObjectDesc::Kind::Triangle:
            for (const Vec3f& v : object.vertices) moderate(v);
            break;
        case ObjectDesc::Kind::TriangleMesh:
            object.mesh = 0;
            break;
        case ObjectDesc::Kind::Transform:
            for (const auto& row : object.world_from_object.m)
                for (float v : row) moderate(v);
            break;
        case ObjectDesc::Kind::Curve:
        case ObjectDesc::Kind::RevSurface:
            for (const Vec3f& v : object.curve.controls) moderate(v);
            break;
        case ObjectDesc::Kind::Group:
            break;
    }
    for (ObjectDesc& child : object.children) prepare_objects(child, moderate);
}

// A tetrahedron with one normal per corner on two faces, so both normal paths run.
TriangleMesh small_mesh() {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    mesh.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    mesh.normals = {{0, 0, -1}, {0, -1, 0}};
    mesh.normal_indices = {0, 0, 0, 1, 1, 1, kNoNormal, kNoNormal, kNoNormal, kNoNormal, kNoNormal, kNoNormal};
    return mesh;
}

// ---- rendering ---------------------------------------------------------------------------------

bool same_float(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }
bool same_pixel(Vec3f a, Vec3f b) { return same_float(a.x, b.x) && same_float(a.y, b.y) && same_float(a.z, b.z); }

std::string pixel_text(const char* label, Vec3f p) {
    return string_printf("%s (%.9g, %.9g, %.9g)", label, double(p.x), double(p.y), double(p.z));
}

void check_same_image(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height) finding(what, "different sizes");
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (!same_pixel(a.at(x, y), b.at(x, y)))
                finding(what, string_printf("pixel (%d, %d): ", x, y) + pixel_text("", a.at(x, y)) +
                                  pixel_text(" vs", b.at(x, y)));
}

void check_finite(const Image& image, const char* what) {
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (!is_finite(image.at(x, y)))
                finding(what, string_printf("pixel (%d, %d)", x, y) + pixel_text(" is", image.at(x, y)));
}

void render_and_check(const Scene& scene, bool moderate) {
    RenderOptions options;
    options.threads = 1;
    options.shadows = true;
    options.packet_isa = PacketIsa::None;
    const Image single = render_image(scene, options);
    if (single.width != kWidth || single.height != kHeight) finding("image of the wrong size");

    options.packet_isa = PacketIsa::Portable;
    check_same_image(single, render_image(scene, options), "portable packets differ from single rays");
    const PacketIsa best = best_packet_isa();
    if (best != PacketIsa::None && best != PacketIsa::Portable) {
        options.packet_isa = best;
        check_same_image(single, render_image(scene, options),
                         (std::string(packet_isa_name(best)) + " packets differ from single rays").c_str());
    }

    options.has_crop = true;
    options.crop = kCrop;
    const Image crop = render_image(scene, options);
    if (crop.width != kCrop.x1 - kCrop.x0 || crop.height != kCrop.y1 - kCrop.y0) finding("crop of the wrong size");
    for (int y = 0; y < crop.height; ++y)
        for (int x = 0; x < crop.width; ++x)
            if (!same_pixel(crop.at(x, y), single.at(x + kCrop.x0, y + kHeight - kCrop.y1)))
                finding("crop differs from the full image", string_printf("crop pixel (%d, %d)", x, y));
    options.has_crop = false;

    options.mode = RenderMode::Normals;
    const Image normals = render_image(scene, options);
    options.mode = RenderMode::Depth;
    const Image depth = render_image(scene, options);
    if (moderate) {
        check_finite(single, "non-finite pixel in a moderate scene (shaded)");
        check_finite(normals, "non-finite pixel in a moderate scene (normals)");
        check_finite(depth, "non-finite pixel in a moderate scene (depth)");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    check_numbers(data, size);

    // The view covers exactly the fuzzer's buffer, so ASan sees any read past its end.
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    SceneDesc desc;
    try {
        desc = parse_scene(text, "fuzz.txt");
    } catch (const InputError& error) {
        check_diagnostics(error, text);
        return 0;
    }
    if (!desc.camera || !desc.root) finding("parse_scene succeeded without a camera or a Group");

    Moderate moderate;
    const CameraDesc& camera = *desc.camera;
    moderate(camera.center);
    moderate(camera.direction);
    moderate(camera.up);
    moderate(camera.kind == CameraDesc::Kind::Perspective ? camera.angle_degrees : camera.size);
    moderate(desc.background);
    if (desc.ambient) moderate(*desc.ambient);
    for (const LightDesc& light : desc.lights) {
        moderate(light.direction);
        moderate(light.position);
        moderate(light.color);
        moderate(light.attenuation);
    }
    for (const MaterialDesc& material : desc.materials) {
        moderate(material.diffuse);
        moderate(material.specular);
        if (material.shininess) moderate(*material.shininess);
    }
    prepare_objects(*desc.root, moderate);
    desc.meshes.push_back(MeshDesc{"built-in.obj", small_mesh()});

    SceneBuildOptions build_options;
    build_options.width = kWidth;
    build_options.height = kHeight;
    // Both profiles, picked by the input's length so that each input always takes the same one.
    build_options.conventions = size % 2 == 0 ? Conventions::course() : Conventions::mit6837();
    if (size % 4 == 3) build_options.conventions.fov_axis = FovAxis::Both;
    Scene scene;
    try {
        scene = build_scene(std::move(desc), build_options);
    } catch (const InputError& error) {
        // Only a transform that cannot be inverted is refused here; the camera and size are known.
        if (error.diagnostics().empty()) finding("build_scene threw an InputError without diagnostics");
        return 0;
    }
    render_and_check(scene, moderate.ok);
    return 0;
}
