// raycast's command-line program: the only place that reads argv, prints, and picks exit codes
// (0 success, 1 input or output error, 2 usage error).
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/write_file.h"
#include "base/parallel.h"
#include "base/timer.h"
#include "cli/cli_options.h"
#include "image/compare_images.h"
#include "image/crop_pieces.h"
#include "image/image_io.h"
#include "render/integrator.h"
#include "render/render.h"
#include "scene/build_scene.h"
#include "scene/intersect_packet.h"
#include "sceneio/load_scene.h"
#ifdef RAYCAST_VIEW_PROGRAM
#include "view/view_server.h"
#endif

#ifndef RAYCAST_VERSION
#define RAYCAST_VERSION "dev"
#endif

namespace raycast {
namespace {

constexpr int kExitInputError = 1;
constexpr int kExitUsageError = 2;
constexpr int kExitImagesDiffer = 1;  // compare beyond its --max-diff/--max-fraction tolerance

void print_diagnostics(const std::vector<Diagnostic>& diagnostics) {
    for (const Diagnostic& d : diagnostics) std::fputs(format_diagnostic(d).c_str(), stderr);
}

bool same_file(const std::string& a, const std::string& b) {
    struct stat sa, sb;
    return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

// Checks an output path before any work is done, so a long render never ends in "cannot write".
// The output must not be one of `inputs`; `input_what` names them in the message, e.g. "the scene file".
// Its format is `format` (--format's) or, when that is nullopt, its name's; `format_option` says
// whether --format could have named one, as it can for the course's OUTPUT, and the message then says so.
void check_output_path(const std::string& path, const std::vector<std::string>& inputs, const char* input_what,
                       std::optional<ImageFormat> format = std::nullopt, bool format_option = false) {
    if (path.empty()) return;
    if (!format) format = image_format_for_path(path);
    if (!format) {
        const std::string hint = format_option ? ", or give --format" : "";
        const size_t dot = path.find_last_of('.');
        const size_t slash = path.find_last_of('/');
        if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
            throw UsageError("cannot tell the image format of '" + path + "': name it .bmp, .ppm, .tga or .png" + hint);
        throw UsageError("unknown image format '" + path.substr(dot) + "' for '" + path +
                         "': use .bmp, .ppm, .tga or .png" + hint);
    }
    for (const std::string& input : inputs)
        if (path == input || same_file(path, input))
            throw UsageError("the output '" + path + "' is " + input_what + " itself: choose another name");
    if (*format == ImageFormat::Png && !png_supported())
        throw InputError(path, "PNG images need libpng: rebuild raycast with libpng-dev installed, or use .bmp, .ppm or .tga");
    struct stat existing;
    const bool found = ::stat(path.c_str(), &existing) == 0;
    if (found && S_ISDIR(existing.st_mode)) throw InputError(path, "cannot write image: it is a directory");
    const WriteTarget destination = write_target(path);
    // A pipe, a device or /dev/stdout is written into: no rename, no folder to check.
    if (destination.in_place) {
        if (::access(path.c_str(), W_OK) != 0)
            throw InputError(path, std::string("cannot write image: ") + std::strerror(errno));
        return;
    }
    // A link is written through: the rename replaces what it leads to, in that file's folder,
    // whose entry's owner is the one a sticky folder asks about.
    if (destination.error == EACCES)
        throw InputError(path, "cannot write image: it is another user's link in a sticky folder (as /tmp is), which "
                               "is not followed, as the system follows none: choose another name");
    if (destination.error != 0)
        throw InputError(path, std::string("cannot write image: ") + std::strerror(destination.error));
    const std::string& target = destination.file;
    struct stat entry;
    const bool exists = ::lstat(target.c_str(), &entry) == 0;
    const std::string folder = folder_of(target);
    struct stat folder_info;
    if (::stat(folder.c_str(), &folder_info) != 0 || !S_ISDIR(folder_info.st_mode))
        throw InputError(path, "cannot write image: the folder '" + folder + "' does not exist");
    if (::access(folder.c_str(), W_OK) != 0)
        throw InputError(path, "cannot write image: the folder '" + folder + "' is not writable: " + std::strerror(errno));
    // The image replaces the file by a rename, which these refuse only at the end of the render.
    const std::string name = target.substr(target.find_last_of('/') + 1);
    const long name_max = ::pathconf(folder.c_str(), _PC_NAME_MAX);
    if (name_max > 0 && static_cast<long>(name.size()) > name_max)
        throw InputError(path, string_printf("cannot write image: its name is %zu bytes long, and the folder takes at "
                                             "most %ld",
                                             name.size(), name_max));
    const uid_t me = ::geteuid();
    if (exists && (folder_info.st_mode & S_ISVTX) && me != 0 && entry.st_uid != me && folder_info.st_uid != me)
        throw InputError(path, "cannot write image: the file belongs to another user, and its folder (sticky, as /tmp "
                               "is) lets only the owner replace it: choose another name");
}

// The same file named twice, even differently spelt ("out.bmp" and "./out.bmp") or through a link
// (written through, write_target): the same string, the same existing file, or the same name in
// the same folder.
bool same_output(const std::string& given_a, const std::string& given_b) {
    if (given_a == given_b || same_file(given_a, given_b)) return true;
    const std::string a = write_target(given_a).file, b = write_target(given_b).file;
    if (a == b) return true;
    auto name_of = [](const std::string& path) { return path.substr(path.find_last_of('/') + 1); };
    if (name_of(a) != name_of(b)) return false;
    struct stat fa, fb;
    return ::stat(folder_of(a).c_str(), &fa) == 0 && ::stat(folder_of(b).c_str(), &fb) == 0 && fa.st_dev == fb.st_dev &&
           fa.st_ino == fb.st_ino;
}

// Each output once: with the image and --depth (or --normals) the same file, the last written
// won and the other was lost in silence.
void check_outputs_differ(const std::vector<std::pair<const char*, std::string>>& outputs) {
    for (size_t i = 0; i < outputs.size(); ++i)
        for (size_t j = i + 1; j < outputs.size(); ++j)
            if (!outputs[i].second.empty() && !outputs[j].second.empty() &&
                same_output(outputs[i].second, outputs[j].second))
                throw UsageError(std::string(outputs[i].first) + " and " + outputs[j].first + " are both '" +
                                 outputs[j].second + "': give each its own name");
}

// A progress bar on stderr, shown only on a terminal and only for renders that last.
class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled && ::isatty(2)) {}
    ~ProgressBar() { finish(); }
    /// A line for the user while the bar may be showing: the bar's line is cleared first, and
    /// the bar goes on below.
    void note(const std::string& text) {
        std::fprintf(stderr, "%s%s\n", shown_.load() ? "\r\033[K" : "", text.c_str());
        std::fflush(stderr);
    }
    /// Clears the bar's line, so that what is printed next starts a line of its own.
    void finish() {
        if (shown_.exchange(false)) std::fputs("\r\033[K", stderr);
        enabled_ = false;
    }
    void update(double fraction) {
        if (!enabled_ || timer_.elapsed_ms() < 1000) return;
        const int percent = static_cast<int>(fraction * 100);
        int last = last_percent_.load();
        if (percent <= last || !last_percent_.compare_exchange_strong(last, percent)) return;
        constexpr int kWidth = 40;
        const int filled = percent * kWidth / 100;
        std::fprintf(stderr, "\rrendering [%.*s%*s] %3d%%", filled, "========================================",
                     kWidth - filled, "", percent);
        std::fflush(stderr);
        shown_ = true;
    }

private:
    bool enabled_;
    Timer timer_;
    std::atomic<int> last_percent_{-1};
    std::atomic<bool> shown_{false};
};

// A scene loaded and built as the options say, with the notes and warnings a user should see.
struct LoadedScene {
    Scene scene;
    std::string file;
    double load_ms = 0, build_ms = 0;
};

// Whether any object's material reflects or refracts.
bool uses_mirrors_or_glass(const Scene& scene) {
    for (const Instance& instance : scene.instances) {
        const Material& m = scene.materials[instance.material];
        if (m.reflective != Vec3f{0, 0, 0} || m.transparent != Vec3f{0, 0, 0}) return true;
    }
    return false;
}

LoadedScene load_and_build(const CliOptions& options, int threads) {
    if (!options.quiet)
        for (const std::string& note : options.notes) std::fprintf(stderr, "raycast: note: %s\n", note.c_str());
    LoadedScene loaded;
    Timer load_timer;
    SceneLoadOptions load_options;
    load_options.threads = threads;
    load_options.allow_missing_meshes = options.allow_missing_meshes;
    SceneDesc desc = load_scene_file(options.scene_path, load_options);
    loaded.load_ms = load_timer.elapsed_ms();
    if (!options.quiet) print_diagnostics(desc.warnings);

    Timer build_timer;
    SceneBuildOptions build_options;
    build_options.width = options.width;
    build_options.height = options.height;
    build_options.conventions = options.conventions;
    build_options.threads = threads;
    loaded.file = desc.file;
    loaded.scene = build_scene(std::move(desc), build_options);
    loaded.build_ms = build_timer.elapsed_ms();
    Scene& scene = loaded.scene;
    if (options.aperture > 0) {
        scene.camera.lens_radius = options.aperture / 2;
        scene.camera.focus_distance =
            options.has_focus_distance ? options.focus_distance : auto_focus_distance(scene, scene.camera);
    }
    if (options.quiet) return loaded;
    const Camera& camera = scene.camera;
    if (!options.fov_given && options.conventions.fov_axis == FovAxis::Both && camera.width != camera.height)
        std::fprintf(stderr,
                     "raycast: note: the image is %dx%d and the camera's %s spans both its width and its height, so "
                     "pixels are stretched as the course's handout defines them; --fov vertical gives square pixels\n",
                     camera.width, camera.height,
                     camera.projection == Camera::Projection::Perspective ? "angle" : "size");
    if (options.render.packet_isa != PacketIsa::None && scene.worst_transform_condition > kMaxPacketCondition)
        std::fprintf(stderr,
                     "raycast: note: a transform in the scene is nearly singular (its condition is %.3g): every ray "
                     "is traced alone, without SIMD packets, so that the image is the same on every path\n",
                     double(scene.worst_transform_condition));
    if (options.aperture > 0 && camera.projection != Camera::Projection::Perspective)
        std::fprintf(stderr, "raycast: note: --aperture makes a thin lens of a perspective camera; the scene's "
                             "orthographic camera has none, and the image is as sharp as without it\n");
    const RenderMode mode = options.render.mode;
    if (scene.lights.empty() && scene.ambient == Vec3f{0, 0, 0} && mode == RenderMode::Shaded)
        std::fprintf(stderr, "%s: warning: the scene has no lights and no ambient light: every object will be black\n",
                     loaded.file.c_str());
    if (mode == RenderMode::Shaded && options.render.bounces == 0 && uses_mirrors_or_glass(scene))
        std::fprintf(stderr,
                     "raycast: note: the scene has reflective or transparent materials, but no reflected or "
                     "transmitted rays are traced: add %s N (e.g. %s 5) to see mirrors and glass\n",
                     options.mit_form ? "-bounces" : "--bounces", options.mit_form ? "-bounces" : "--bounces");
    return loaded;
}

int run_render(const CliOptions& options) {
    const int threads = options.threads > 0 ? options.threads : hardware_threads();
    check_output_path(options.output_path, {options.scene_path}, "the scene file", options.output_format,
                      !options.mit_form);
    for (const std::string& path : {options.depth_path, options.normals_path})
        check_output_path(path, {options.scene_path}, "the scene file");
    check_outputs_differ({{"the image", options.output_path},
                          {options.mit_form ? "-depth" : "--depth", options.depth_path},
                          {options.mit_form ? "-normals" : "--normals", options.normals_path}});
    const LoadedScene loaded = load_and_build(options, threads);
    const Scene& scene = loaded.scene;

    RenderOptions render = options.render;
    render.threads = threads;
    if (render.has_crop) {
        const CropWindow& c = render.crop;
        if (c.x1 > scene.camera.width || c.y1 > scene.camera.height)
            throw UsageError(string_printf("--crop %d,%d,%d,%d reaches outside the %dx%d image", c.x0, c.y0, c.x1, c.y1,
                                           scene.camera.width, scene.camera.height));
        // Grey levels from the visible range would differ from piece to piece.
        const bool depth_image = render.mode == RenderMode::Depth || !options.depth_path.empty();
        if (depth_image && render.depth_near == 0 && render.depth_far == 0)
            throw UsageError("--crop with a depth image needs --depth-range NEAR,FAR, so that every piece uses the same "
                             "grey scale");
    }
    ProgressBar progress(!options.quiet);
    render.progress = [&progress](double fraction) { progress.update(fraction); };
    if (!options.quiet) {
        // Said at once: such a render can take hours, and the count of samples cut short comes
        // only at the end.
        const char* bounces = options.mit_form ? "-bounces" : "--bounces";
        const char* weight = options.mit_form ? "-weight" : "--weight";
        render.reaching_ray_limit = [&progress, bounces, weight, limit = render.bounces] {
            progress.note(string_printf("raycast: note: camera samples are reaching their limit of %u rays (mirror and "
                                        "glass rays %d bounces deep), so this render may take long: lower %s, or "
                                        "raise %s",
                                        kMaxRaysPerSample, limit, bounces, weight));
        };
    }

    // One pass traces the camera rays once for every image asked for.
    FrameRequest request;
    request.color = !options.output_path.empty();
    request.depth = !options.depth_path.empty();
    request.normals = !options.normals_path.empty();
    RenderStats stats;
    const FrameImages images = render_frame_rgb8(scene, render, request, &stats);
    // Written together: a failure (a full disk) before the last rename leaves every output as it was.
    // --format names the image's format; each file's name, checked before the render, gives the rest.
    struct Output {
        const std::string& path;
        const ImageRgb8& image;
        std::optional<ImageFormat> format;
    };
    std::vector<std::pair<std::string, std::vector<uint8_t>>> files;
    for (const Output& output : {Output{options.output_path, images.color, options.output_format},
                                 Output{options.depth_path, images.depth, std::nullopt},
                                 Output{options.normals_path, images.normals, std::nullopt}}) {
        if (output.path.empty()) continue;
        const ImageFormat format = output.format ? *output.format : *image_format_for_path(output.path);
        if (render.has_crop && format == ImageFormat::Ppm) {
            const CropWindow& c = render.crop;
            files.emplace_back(output.path, encode_crop_piece(output.image, CropPlacement{c.x0, c.y0, c.x1, c.y1,
                                                                                          scene.camera.width,
                                                                                          scene.camera.height}));
        } else {
            files.emplace_back(output.path, encode_image(output.image, format));
        }
    }
    progress.finish();  // the bar's line cleared before any warning
    write_files_atomically(files, "image");
    if (stats.truncated_samples > 0 && !options.quiet)
        std::fprintf(stderr,
                     "raycast: warning: %llu camera samples reached the limit of %u rays each, so their mirror and glass "
                     "rays were cut short: lower %s or raise %s\n",
                     static_cast<unsigned long long>(stats.truncated_samples), kMaxRaysPerSample,
                     options.mit_form ? "-bounces" : "--bounces", options.mit_form ? "-weight" : "--weight");
    if (options.stats) {
        const double mrays = stats.milliseconds > 0 ? static_cast<double>(stats.rays) / (stats.milliseconds * 1000) : 0;
        // Not into the image: with the image on standard output (/dev/stdout, "-", or a name for
        // the same file) the line goes to standard error.
        FILE* stats_stream = same_file(options.output_path, "/dev/stdout") ? stderr : stdout;
        std::fprintf(stats_stream, "raycast-stats load_ms=%.3f build_ms=%.3f render_ms=%.3f rays=%llu mrays_per_s=%.3f "
                    "triangles=%zu threads=%d hit_fraction=%.4f traversal=%s primary_rays=%llu window_missed_rays=%llu "
                    "shadow_rays=%llu "
                    "secondary_rays=%llu occlusion_rays=%llu rev_surfaces=%zu rev_surface_tests=%llu "
                    "newton_iterations=%llu newton_failures=%llu\n",
                    loaded.load_ms, loaded.build_ms, stats.milliseconds, static_cast<unsigned long long>(stats.rays),
                    mrays, scene.triangle_count(), threads,
                    stats.primary_rays ? static_cast<double>(stats.hits) / static_cast<double>(stats.primary_rays) : 0.0,
                    stats.traversal.c_str(), static_cast<unsigned long long>(stats.primary_rays),
                    static_cast<unsigned long long>(stats.window_missed_rays),
                    static_cast<unsigned long long>(stats.shadow_rays),
                    static_cast<unsigned long long>(stats.secondary_rays),
                    static_cast<unsigned long long>(stats.occlusion_rays), scene.rev_surfaces.size(),
                    static_cast<unsigned long long>(stats.rev_surface.tests),
                    static_cast<unsigned long long>(stats.rev_surface.newton_iterations),
                    static_cast<unsigned long long>(stats.rev_surface.newton_failures));
    }
    return 0;
}

int run_explain(const CliOptions& options) {
    const int threads = options.threads > 0 ? options.threads : hardware_threads();
    const LoadedScene loaded = load_and_build(options, threads);
    const Camera& camera = loaded.scene.camera;
    if (options.explain_x >= camera.width || options.explain_y >= camera.height)
        throw UsageError(string_printf("pixel %d %d is outside the %dx%d image (columns 0 to %d, rows 0 to %d)",
                                       options.explain_x, options.explain_y, camera.width, camera.height,
                                       camera.width - 1, camera.height - 1));
    RenderOptions render = options.render;
    render.threads = threads;
    PixelExplanation explanation = explain_pixel(loaded.scene, render, options.explain_x, options.explain_y);
    explanation.scene = loaded.file;
    std::fputs(explanation_json(explanation).c_str(), stdout);
    return 0;
}

#ifdef RAYCAST_VIEW_PROGRAM
bool is_loopback(const std::string& host) {
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

int run_view(const CliOptions& options) {
    if (!view_server_available())
        throw InputError("raycast view",
                         "this raycast was built without cpp-httplib, which the viewer needs: install it "
                         "(Debian/Ubuntu: sudo apt-get install libcpp-httplib-dev pkg-config) and rebuild");
    const int threads = options.threads > 0 ? options.threads : hardware_threads();
    ViewSettings settings;
    settings.scene_path = options.scene_path;
    settings.load.threads = threads;
    settings.load.allow_missing_meshes = options.allow_missing_meshes;
    settings.mit_conventions = options.mit_conventions;
    settings.conventions = options.conventions;
    settings.width = options.width;
    settings.height = options.height;
    settings.render = options.render;
    settings.render.threads = threads;
    settings.aperture = options.aperture;
    settings.focus_distance = options.has_focus_distance ? options.focus_distance : 0;
    ViewSession session(settings);
    // Watched from before the first load: a save that begins during it (or before the server's
    // loop has started) is seen, and that load dropped as the loop's are.
    FileWatcher files;
    files.watch({settings.scene_path});
    session.reload_if_changed([&](bool files_changed) { return files.changed_since_wait(files_changed); });
    if (!options.quiet) {
        for (const std::string& note : options.notes) std::fprintf(stderr, "raycast: note: %s\n", note.c_str());
        print_diagnostics(session.diagnostics());
        if (!is_loopback(options.view_host))
            std::fprintf(stderr,
                         "raycast: warning: listening on %s, not only on this machine: anyone who can reach it can see "
                         "the scene and make it render\n",
                         options.view_host.c_str());
    }
    ViewServerOptions server;
    server.host = options.view_host;
    server.port = options.view_port;
    run_view_server(session, files, server, [&](const std::string& url) {
        // The URL alone on stdout, for scripts; the rest for people, on stderr.
        std::printf("%s\n", url.c_str());
        std::fflush(stdout);
        if (!options.quiet)
            std::fprintf(stderr, "raycast: viewing %s at %s (Ctrl-C to stop)\n", options.scene_path.c_str(), url.c_str());
    });
    return 0;
}

#else
// The viewer is its own program, raycast-view, built beside raycast: cpp-httplib comes as a shared
// library linked with OpenSSL, zlib and brotli, whose loading would add milliseconds and megabytes
// to every render. `raycast view ...` runs it with the same words.
[[noreturn]] void exec_view_program(char** argv) {
    char self[4096];
    const ssize_t length = readlink("/proc/self/exe", self, sizeof self - 1);
    std::string program = length > 0 ? std::string(self, static_cast<size_t>(length)) : std::string(argv[0]);
    const size_t slash = program.rfind('/');
    program = (slash == std::string::npos ? std::string(".") : program.substr(0, slash)) + "/raycast-view";
    if (access(program.c_str(), X_OK) != 0)
        throw InputError("raycast view", "the viewer is the program " + program +
                                             ", which is not there: it is built with raycast (cmake --build)");
    argv[0] = program.data();
    execv(program.c_str(), argv);
    throw InputError("raycast view", "cannot run " + program + ": " + std::strerror(errno));
}
#endif

int run_compare(const CliOptions& options) {
    const ImageRgb8 a = read_image(options.inputs[0]);
    const ImageRgb8 b = read_image(options.inputs[1]);
    if (a.width != b.width || a.height != b.height)
        throw InputError(options.inputs[1], string_printf("cannot compare: it is %dx%d but '%s' is %dx%d", b.width, b.height,
                                                          options.inputs[0].c_str(), a.width, a.height));
    ImageRgb8 mask;
    std::vector<std::string> inputs = options.inputs;
    if (!options.mask_path.empty()) {
        mask = read_image(options.mask_path);
        if (mask.width != a.width || mask.height != a.height)
            throw InputError(options.mask_path, string_printf("cannot use it as a mask: it is %dx%d but the images are %dx%d",
                                                              mask.width, mask.height, a.width, a.height));
        inputs.push_back(options.mask_path);
    }
    const ImageRgb8* ignore = options.mask_path.empty() ? nullptr : &mask;
    check_output_path(options.diff_path, inputs, "an image being compared");
    const ImageComparison c = compare_images(a, b, ignore);
    std::printf("compared %s and %s (%dx%d)\n", options.inputs[0].c_str(), options.inputs[1].c_str(), a.width, a.height);
    if (ignore) std::printf("ignored pixels (black in %s): %zu\n", options.mask_path.c_str(), c.ignored_pixels);
    std::printf("differing pixels: %zu of %zu (%.4f%%)\n", c.differing_pixels, c.pixel_count,
                c.pixel_count ? 100.0 * static_cast<double>(c.differing_pixels) / static_cast<double>(c.pixel_count) : 0.0);
    std::printf("pixels off by more than 1 level: %zu\n", c.pixels_beyond(1));
    std::printf("max error: %d levels\nmean error: %.6f levels\n", c.max_error, c.mean_error);
    if (std::isinf(c.psnr))
        std::printf("PSNR: inf (identical)\n");
    else
        std::printf("PSNR: %.2f dB\n", c.psnr);
    if (!options.diff_path.empty()) write_image(options.diff_path, difference_heat_map(a, b, ignore));
    if (options.grade) {
        std::string why;
        if (!within_tolerance(c, options.tolerance, &why)) {
            std::fflush(stdout);  // the report first, also when both go to one pipe
            std::fprintf(stderr, "raycast: images differ: %s\n", why.c_str());
            return kExitImagesDiffer;
        }
        std::printf("within tolerance: %s\n", why.c_str());
    }
    return 0;
}

int run_merge(const CliOptions& options) {
    check_output_path(options.merge_output, options.inputs, "a piece");
    std::vector<CropPiece> pieces;
    for (const std::string& input : options.inputs) pieces.push_back(read_crop_piece(input));
    write_image(options.merge_output, merge_crop_pieces(pieces));
    if (!options.quiet)
        std::fprintf(stderr, "raycast: merged %zu pieces into %s\n", pieces.size(), options.merge_output.c_str());
    return 0;
}

int run(int argc, char** argv) {
    CliOptions options;
    try {
        options = parse_command_line(argc, argv);
    } catch (const UsageError& error) {
        std::fprintf(stderr, "raycast: usage error: %s\nTry 'raycast --help' for more information.\n", error.what());
        return kExitUsageError;
    }
    try {
        switch (options.command) {
            case CliOptions::Command::Help:
                std::fputs(usage_text().c_str(), stdout);
                return 0;
            case CliOptions::Command::Version:
                std::printf("raycast %s (SIMD packets: %s; PNG: %s)\n", RAYCAST_VERSION,
                            packet_isa_name(best_packet_isa()), png_supported() ? "yes" : "no");
                return 0;
            case CliOptions::Command::Compare:
                return run_compare(options);
            case CliOptions::Command::Merge:
                return run_merge(options);
            case CliOptions::Command::Render:
                return run_render(options);
            case CliOptions::Command::Explain:
                return run_explain(options);
            case CliOptions::Command::View:
#ifdef RAYCAST_VIEW_PROGRAM
                return run_view(options);
#else
                exec_view_program(argv);
#endif
        }
    } catch (const UsageError& error) {
        std::fprintf(stderr, "raycast: usage error: %s\nTry 'raycast --help' for more information.\n", error.what());
        return kExitUsageError;
    } catch (const InputError& error) {
        print_diagnostics(error.diagnostics());
        return kExitInputError;
    } catch (const std::bad_alloc&) {
        std::fputs("raycast: error: out of memory\n", stderr);
        return kExitInputError;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "raycast: error: %s\n", error.what());
        return kExitInputError;
    }
    return 0;
}

}  // namespace
}  // namespace raycast

int main(int argc, char** argv) { return raycast::run(argc, argv); }
