// Fuzz target: the whole pipeline on scenes built from the input's bytes, so that the scene
// builder, the BVHs, the packet kernels and the shading are fuzzed, not only the parsers. The
// bytes are choices, not text (tests/random_scene.h): every camera, light (attenuation included),
// material field (mirrors and glass), object kind and transform item, groups and transforms
// nested up to 100 levels more than usual, meshes from in-memory OBJ files in every index form,
// and now and then numbers at the edges of the float range. The scene goes through
// load_scene_text, build_scene and render_image at 8x6 pixels with settings the bytes pick too:
// packet ISA, samples, shadows, transparent shadows, bounces, weight, lens, every mode including
// ao and cost, crop, conventions, one or two threads.
// Anything but these outcomes is a finding (a crash, a sanitizer report, a failed RAYCAST_DCHECK,
// a hang, an exception other than InputError):
//  - the parser accepts every generated scene (they are valid by construction);
//  - build_scene refuses a scene only when it has extreme numbers (the extent limit, a product
//    of transforms that cannot be inverted);
//  - every pixel is finite when every number is moderate (RandomScene::moderate), and no camera
//    sample reaches the ray budget (kMaxRaysPerSample): with at most 4 bounces, 3 lights, 4
//    occlusion rays and a few dozen surfaces, a sample needs a few thousand rays at most;
//  - for a scene of moderate numbers, the image is bit for bit the brute-force reference's
//    (tests/reference_render.h: no BVH, no packets), crop or not, except in cost mode, which
//    counts BVH nodes, and at pixels the reference marks uncertain: where a hit rounded to
//    before its BVH leaf's box is moved up to that leaf's floor (bvh.h), as brute force cannot;
//    there the image must be the single-ray render's. Not with extreme numbers: the box test's
//    stand-in for 1/0 (1e30, bvh.h) lets a box thinner than t/1e30 along an axis the ray does not
//    move in be missed (an object of 1e-30 seen from 1e6 away), which brute force still hits;
//    docs/reliability.md;
//  - render_frame_rgb8's depth and normals images equal those modes' renders, and its colour
//    image is the quantized float image (render.h);
//  - explain_pixel gives a pixel the colour the render gave it (render.h);
//  - the render with every ray traced (RenderOptions::skip_empty_windows off) is bit for bit the
//    same, with the same counts of rays and hits, extreme numbers included (and of surface of
//    revolution tests, with moderate numbers): a window found to see nothing
//    (scene/camera_window.h) really sees nothing. About one input in eight (every input whose
//    bytes run out before the choice) also renders the same view at 40x24 in tiles of 32 or 64,
//    where tiles hold several of the 16x16 parts checked for it, both ways.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "base/error.h"
#include "random_scene.h"
#include "reference_render.h"
#include "render/render.h"
#include "sceneio/load_scene.h"

namespace {

using namespace raycast;
using namespace raycast::test;

constexpr int kWidth = 8, kHeight = 6;

std::string scene_files(const RandomScene& random) {
    std::string text = "--- fuzz.txt\n" + random.text;
    for (const auto& [path, obj] : random.meshes) text += "--- " + path + "\n" + obj;
    return text;
}

[[noreturn]] void finding(const char* what, const std::string& detail, const RandomScene& random) {
    std::fprintf(stderr, "fuzz_render_pipeline: FINDING: %s%s%s\n%s", what, detail.empty() ? "" : ": ", detail.c_str(),
                 scene_files(random).c_str());
    std::abort();
}

bool same_float(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }
bool same_pixel(Vec3f a, Vec3f b) { return same_float(a.x, b.x) && same_float(a.y, b.y) && same_float(a.z, b.z); }

std::string pixel_text(Vec3f p) {
    return string_printf("(%.9g, %.9g, %.9g)", double(p.x), double(p.y), double(p.z));
}

// The packet ISAs this build and CPU run, None (one ray at a time) included.
std::vector<PacketIsa> available_isas() {
    std::vector<PacketIsa> isas;
    for (PacketIsa isa : {PacketIsa::None, PacketIsa::Portable, PacketIsa::Sse2, PacketIsa::Avx2, PacketIsa::Avx512})
        if (packet_isa_available(isa)) isas.push_back(isa);
    return isas;
}

void check_against_reference(const Scene& scene, const RenderOptions& options, const Image& image,
                             const RandomScene& random) {
    std::vector<uint8_t> uncertain;
    const Image expected = reference_render(ReferenceScene(scene), options, &uncertain);
    // Output pixel (x, y) is camera pixel (x + x0, y + height - y1) of a crop (rows counted from the top).
    const int x0 = options.has_crop ? options.crop.x0 : 0;
    const int y0 = options.has_crop ? kHeight - options.crop.y1 : 0;
    // Where the reference is uncertain (a hit moved up to its BVH leaf's floor), every path must
    // still agree with the single-ray one.
    Image single_ray;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const bool doubt = uncertain[static_cast<size_t>(y + y0) * kWidth + static_cast<size_t>(x + x0)] != 0;
            if (doubt && single_ray.pixels.empty()) {
                RenderOptions single = options;
                single.packet_isa = PacketIsa::None;
                single_ray = render_image(scene, single);
            }
            const Vec3f wanted = doubt ? single_ray.at(x, y) : expected.at(x + x0, y + y0);
            if (!same_pixel(image.at(x, y), wanted))
                finding(doubt ? "where the reference is uncertain, the render differs from the single-ray render"
                              : "the render differs from the brute-force reference",
                        string_printf("%s, mode %s, pixel (%d, %d) from the bottom of the frame: ",
                                      packet_isa_name(options.packet_isa), render_mode_name(options.mode), x + x0,
                                      y + y0) +
                            pixel_text(image.at(x, y)) + " vs " + pixel_text(wanted),
                        random);
        }
}

void check_frame_images(const Scene& scene, RenderOptions options, const Image& image, const RandomScene& random) {
    FrameRequest request;
    request.depth = request.normals = true;
    const FrameImages frame = render_frame_rgb8(scene, options, request);
    if (frame.color.rgb != quantize(image).rgb) finding("render_frame_rgb8's colour is not the quantized image", "", random);
    options.mode = RenderMode::Normals;
    if (frame.normals.rgb != render_image_rgb8(scene, options).rgb)
        finding("render_frame_rgb8's normals differ from a normals render", "", random);
    options.mode = RenderMode::Depth;
    if (frame.depth.rgb != render_image_rgb8(scene, options).rgb)
        finding("render_frame_rgb8's depth differs from a depth render", "", random);
}

// The render with every ray traced (RenderOptions::skip_empty_windows off) must be `image`, bit
// for bit, with the same counts.
void check_skipped_windows(const Scene& scene, const RenderOptions& options, const Image& image, const RenderStats& stats,
                           const RandomScene& random) {
    RenderOptions traced = options;
    traced.skip_empty_windows = false;
    RenderStats traced_stats;
    const Image every_ray = render_image(scene, traced, &traced_stats);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const Vec3f p = image.at(x, y), q = every_ray.at(x, y);
            if (std::memcmp(&p, &q, sizeof p) != 0)
                finding("skipping windows that see nothing changed a pixel",
                        string_printf("mode %s, pixel (%d, %d): ", render_mode_name(options.mode), x, y) +
                            pixel_text(p) + " vs " + pixel_text(q) + " traced",
                        random);
        }
    // With extreme numbers the tracer's box test can let a ray into a box it cannot reach (a
    // camera 1e18 away: the stand-in for 1/0 times the distance overflows), and a surface of
    // revolution there is tested, in vain: its counters may then differ, never the image.
    const bool same_rev_counts = traced_stats.rev_surface.tests == stats.rev_surface.tests &&
                                 traced_stats.rev_surface.newton_iterations == stats.rev_surface.newton_iterations;
    if (traced_stats.rays != stats.rays || traced_stats.hits != stats.hits || (random.moderate && !same_rev_counts))
        finding("skipping windows that see nothing changed the counts",
                string_printf("rays %llu / %llu, hits %llu / %llu, surface of revolution tests %llu / %llu, "
                              "Newton steps %llu / %llu (skipping / tracing every ray)",
                              static_cast<unsigned long long>(stats.rays),
                              static_cast<unsigned long long>(traced_stats.rays),
                              static_cast<unsigned long long>(stats.hits),
                              static_cast<unsigned long long>(traced_stats.hits),
                              static_cast<unsigned long long>(stats.rev_surface.tests),
                              static_cast<unsigned long long>(traced_stats.rev_surface.tests),
                              static_cast<unsigned long long>(stats.rev_surface.newton_iterations),
                              static_cast<unsigned long long>(traced_stats.rev_surface.newton_iterations)),
                random);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Choices choices(data, size);
    SceneLimits limits;
    limits.max_objects = 12;
    limits.max_depth = 4;
    limits.max_mesh_vertices = 24;
    limits.max_deep_nesting = 100;
    limits.extreme_numbers = true;
    const RandomScene random = random_scene(choices, limits);
    RandomRender settings =
        random_render(choices, kWidth, kHeight,
                      {RenderMode::Shaded, RenderMode::Normals, RenderMode::Depth, RenderMode::Material,
                       RenderMode::Cost, RenderMode::AmbientOcclusion});
    RenderOptions& options = settings.render;
    options.packet_isa = choices.pick(available_isas());
    // A second thread costs ~3 ms to start under ASan: now and then.
    if (choices.one_in(8)) options.threads = 2;
    if (choices.one_in(4)) {
        options.has_crop = true;
        options.crop.x0 = static_cast<int>(choices.below(kWidth));
        options.crop.x1 = options.crop.x0 + 1 + static_cast<int>(choices.below(static_cast<uint32_t>(kWidth - options.crop.x0)));
        options.crop.y0 = static_cast<int>(choices.below(kHeight));
        options.crop.y1 = options.crop.y0 + 1 + static_cast<int>(choices.below(static_cast<uint32_t>(kHeight - options.crop.y0)));
        // A depth image's grey scale must not depend on the window (raycast insists on a range).
        if (options.mode == RenderMode::Depth && options.depth_near == 0 && options.depth_far == 0) options.depth_far = 20;
    }
    const bool check_frame = !options.has_crop && choices.one_in(4);
    const bool check_explain = !options.has_crop && choices.one_in(4);

    SceneLoadOptions load;
    load.in_memory_meshes = &random.meshes;
    SceneDesc desc;
    try {
        desc = load_scene_text(random.text, "fuzz.txt", load);
    } catch (const InputError& error) {
        finding("the parser refused a generated scene", error.what(), random);
    }
    Scene scene;
    try {
        scene = build_scene(std::move(desc), settings.build);
    } catch (const InputError& error) {
        if (random.moderate) finding("build_scene refused a scene of moderate numbers", error.what(), random);
        return 0;
    }
    apply_lens(settings, scene);

    RenderStats stats;
    const Image image = render_image(scene, options, &stats);
    // RAYCAST_FUZZ_SHOW=1 prints what an input makes (to look at a slow or surprising one).
    if (std::getenv("RAYCAST_FUZZ_SHOW"))
        std::fprintf(stderr, "%smode %s, %d samples, %d bounces, shadows %d, packets %s: %llu rays, %llu surface of "
                             "revolution tests, %llu Newton steps\n",
                     scene_files(random).c_str(), render_mode_name(options.mode), options.samples_per_pixel,
                     options.bounces, options.shadows ? 1 : 0, packet_isa_name(options.packet_isa),
                     static_cast<unsigned long long>(stats.rays), static_cast<unsigned long long>(stats.rev_surface.tests),
                     static_cast<unsigned long long>(stats.rev_surface.newton_iterations));
    if (random.moderate && stats.truncated_samples > 0)
        finding("a camera sample reached the ray budget in a scene of moderate numbers",
                string_printf("%llu samples, %llu rays", static_cast<unsigned long long>(stats.truncated_samples),
                              static_cast<unsigned long long>(stats.rays)),
                random);
    const int width = options.has_crop ? options.crop.x1 - options.crop.x0 : kWidth;
    const int height = options.has_crop ? options.crop.y1 - options.crop.y0 : kHeight;
    if (image.width != width || image.height != height) finding("an image of the wrong size", "", random);
    if (random.moderate)
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                if (!is_finite(image.at(x, y)))
                    finding("a pixel that is not finite in a scene of moderate numbers",
                            string_printf("mode %s, pixel (%d, %d): ", render_mode_name(options.mode), x, y) +
                                pixel_text(image.at(x, y)),
                            random);
    if (random.moderate && options.mode != RenderMode::Cost) check_against_reference(scene, options, image, random);
    if (stats.window_missed_rays > 0) check_skipped_windows(scene, options, image, stats, random);
    if (check_frame) check_frame_images(scene, options, image, random);
    if (check_explain) {
        const int x = static_cast<int>(choices.below(kWidth)), y = static_cast<int>(choices.below(kHeight));
        const PixelExplanation explanation = explain_pixel(scene, options, x, y);
        // explain counts rows from the top, the image from the bottom.
        if (!same_pixel(explanation.color, image.at(x, kHeight - 1 - y)))
            finding("explain_pixel differs from the render",
                    string_printf("pixel (%d, %d) from the top: ", x, y) + pixel_text(explanation.color) + " vs " +
                        pixel_text(image.at(x, kHeight - 1 - y)),
                    random);
    }
    // Now and then the same view on a frame five times as wide and four times as tall (40x24),
    // in tiles of 32 or 64, so that tiles hold several of the 16x16 parts that are checked for
    // windows that see nothing, and some parts see something while others do not. (An input
    // whose bytes have run out gets the first choice: 32.)
    if (!options.has_crop && choices.one_in(8)) {
        Camera wide = scene.camera;
        wide.width *= 5;
        wide.height *= 4;
        wide.cx *= 5;
        wide.cy *= 4;
        wide.fx *= 5;
        wide.fy *= 4;
        RenderOptions larger = options;
        larger.camera = &wide;
        larger.tile_size = choices.pick(std::vector<int>{32, 64});
        RenderStats larger_stats;
        const Image larger_image = render_image(scene, larger, &larger_stats);
        if (larger_stats.window_missed_rays > 0) check_skipped_windows(scene, larger, larger_image, larger_stats, random);
    }
    return 0;
}
