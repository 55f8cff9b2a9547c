#include "cli/cli_options.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "base/command_line.h"
#include "base/error.h"
#include "base/limits.h"
#include "base/parse_number.h"

namespace raycast {

std::string usage_text() {
    return R"(usage: raycast [options] SCENE OUTPUT
       raycast -input SCENE -size W H -output FILE [-depth NEAR FAR FILE] [-normals FILE]
               [-shade_back] [-specular_fix] [-shadows] [-bounces N] [-weight W]
               [-transparent_shadows]
       raycast explain SCENE X Y [options]
       raycast view SCENE [options] [--port N] [--host ADDR]
       raycast compare A B [--diff DIFF] [--max-diff L] [--max-fraction F] [--mask MASK]
       raycast merge -o OUTPUT PIECE...

Renders SCENE (the course's scene format, or MIT 6.837's) into OUTPUT. The image format follows
OUTPUT's extension: .bmp, .ppm, .tga, or .png (when built with libpng); --format overrides it.

Options:
  -h, --help                 show this help and exit
      --version              show the version and exit
  -j, --threads N            render on N threads (default: all hardware threads); -j4 and
                             --threads=4 work too, as does --name=VALUE for every option below
      --size WxH             image size, replacing the camera's width and height
      --stats                print one line of timings and counts: load, build and render
                             milliseconds, rays, Mrays/s, triangles, threads
  -q, --quiet                no warnings, no progress bar
      --conventions NAME     course (default with this form) or mit6837 (default with -input)
      --fov both|vertical    for width != height: angle spans both axes, pixels stretched as the
                             course's handout defines them (both, the default of the course's
                             conventions), or only the height, with square pixels (vertical,
                             MIT 6.837's default)
      --allow-missing-meshes render without a TriangleMesh whose OBJ file cannot be found (a
                             warning, not an error), as the course's starter does
      --mode MODE            shaded (default), normals, depth, material, cost or ao (ambient
                             occlusion: the share of rays from each hit that escape, as grey)
      --ao-samples N         ambient occlusion: rays per hit (default 16)
      --ao-distance D        ambient occlusion: how far they look (default: a tenth of the
                             diagonal of the scene's bounding box)
      --format FMT           write OUTPUT as FMT (bmp, ppm, tga or png) whatever its name says,
                             even another image extension: for a pipe or a device, as in
                             raycast SCENE - --format ppm | display -  ('-' is standard
                             output; --stats then goes to standard error)
                             (--depth and --normals files still follow their own names)
      --depth FILE           also write a depth image (grey: near white, far black)
      --normals FILE         also write a normals image (|n| per channel)
      --depth-range NEAR,FAR distances mapped to white and black in depth images
                             (default: the nearest and farthest visible hits)
      --spp N                N samples per pixel, stratified (default 1: the course's image)
      --shadows              cast shadow rays towards every light
      --bounces N            trace reflected and transmitted rays up to N deep (default 0:
                             local shading only, the course's ray caster)
      --weight W             stop a path once its weight (the product of the reflective and
                             transparent colours' magnitudes along it) falls below W, 0..1
                             (default 0.001)
      --transparent-shadows  shadow rays pass through transparent surfaces, filtered by their
                             transparentColor (default: any surface blocks the light)
      --aperture D           thin-lens camera with a lens D wide (depth of field)
      --focus-distance F     distance that stays sharp (default: what the image centre sees)
      --crop X0,Y0,X1,Y1     render only columns X0..X1-1 and rows Y0..Y1-1 (row 0 at the top);
                             a PPM output (.ppm, or --format ppm) records the window, for
                             'raycast merge'
      --shade-back           light back faces as front faces (MIT: -shade_back)
      --specular-fix         MIT: multiply the specular term by N.L (MIT: -specular_fix)
      --tile N               tile size in pixels (default 64, down to 16 for small images:
                             16 tiles or more per thread)
      --simd ISA             trace primary rays in SIMD packets of avx512, avx2, sse2 or
                             portable, or none (one ray at a time); default auto, the
                             widest this CPU runs. The image is the same with every choice.
      --no-packets           the same as --simd none
      --test-every-face      shadow rays test every face of closed meshes; by default a
                             camera hit's shadow rays pass over the faces that face away from
                             them, which can let light in only where another surface lies
                             nearer the hit than the rays' start offset (about 1e-5 of the
                             coordinates: where objects touch)

view serves a live viewer on http://127.0.0.1:PORT/ (--port 0, the default, picks a free port;
--host another address, to be reachable from elsewhere): the render, refined while nothing
changes and redone when the scene file or a mesh changes; a movable camera; the ray tree of any
pixel (docs/viewer.md). It runs until Ctrl-C.
explain prints, as JSON, the tree of rays behind pixel (X, Y) (row 0 at the top, as --crop):
every camera, shadow, reflected and transmitted ray, what it hit and the shading terms, with the
same options as a render (docs/explain.md).
compare prints how A and B differ (pixels, max and mean error, PSNR); --diff writes a heat map.
With --max-diff L and/or --max-fraction F it grades: exit 1, with one line saying why, when more
than a fraction F (default 0) of the pixels differ by more than L levels (default 0) in some
channel. The course's tolerance: raycast compare ref.bmp out.bmp --max-diff 1 --max-fraction 0.001
--mask MASK ignores the pixels that are black in MASK, an image of the same size.
merge assembles the PPM pieces written with --crop into the full image, byte-identical to one render.

Exit status: 0 success, 1 input or output error, 2 usage error.
)";
}

namespace {

[[noreturn]] void usage_error(const std::string& message) { throw UsageError(message); }

// A whole number from `lowest` (0 or 1) to `limit`.
int parse_whole_number(const std::string& text, const std::string& what, int64_t lowest, int64_t limit) {
    int64_t value = 0;
    const char* first = text.c_str();
    const char* last = first + text.size();
    const NumberResult result = parse_int(first, last, value);
    if (result.status != NumberStatus::Ok || result.end != last)
        usage_error(what + " needs a whole number, got '" + text + "'");
    if (value < lowest)
        usage_error(what + (lowest == 0 ? std::string(" must not be negative") : " must be at least " + std::to_string(lowest)) +
                    ", got " + text);
    if (value > limit) usage_error(what + " must be at most " + std::to_string(limit) + ", got " + text);
    return static_cast<int>(value);
}

int parse_positive_int(const std::string& text, const std::string& what, int64_t limit) {
    return parse_whole_number(text, what, 1, limit);
}

// A whole number from 0 to `limit`.
int parse_count(const std::string& text, const std::string& what, int64_t limit) {
    return parse_whole_number(text, what, 0, limit);
}

float parse_number(const std::string& text, const std::string& what) {
    float value = 0;
    const char* first = text.c_str();
    const char* last = first + text.size();
    const NumberResult result = parse_float(first, last, value);
    if (result.status != NumberStatus::Ok || result.end != last)
        usage_error(what + " needs a number, got '" + text + "'");
    return value;
}

// A number from 0 to 1, read as a double: a pixel count is a fraction of millions, and a float's
// rounding (0.7 is 0.699999988) would move the limit by a pixel.
double parse_fraction(const std::string& text, const std::string& what) {
    const char* first = text.c_str();
    char* end = nullptr;
    const bool plain = !text.empty() && text.find_first_not_of("0123456789.eE+-") == std::string::npos;
    const double value = plain ? std::strtod(first, &end) : 0.0;
    if (!plain || end != first + text.size() || !std::isfinite(value))
        usage_error(what + " needs a number from 0 to 1, got '" + text + "'");
    if (!(value >= 0 && value <= 1)) usage_error(what + " must be from 0 to 1, got " + text);
    return value;
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (;;) {
        const size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end - start));
        if (end == std::string::npos) return parts;
        start = end + 1;
    }
}

// Each side is checked on its own as it is read; the total keeps the image's memory sane too.
void check_pixel_count(const std::string& what, const CliOptions& options) {
    const int64_t pixels = int64_t{options.width} * options.height;
    if (pixels > kMaxImagePixels)
        usage_error(string_printf("%s %dx%d has %lld pixels, more than raycast's limit of %lld (8192x8192)", what.c_str(),
                                  options.width, options.height, static_cast<long long>(pixels),
                                  static_cast<long long>(kMaxImagePixels)));
}

void parse_size(const std::string& text, const std::string& what, CliOptions& options) {
    const size_t x = text.find_first_of("xX");
    if (x == std::string::npos) usage_error(what + " needs WIDTHxHEIGHT, e.g. 640x480, got '" + text + "'");
    options.width = parse_positive_int(text.substr(0, x), what + " width", kMaxImageSide);
    options.height = parse_positive_int(text.substr(x + 1), what + " height", kMaxImageSide);
    check_pixel_count(what, options);
}

// Walks argv with the current position, for options that take values. A value may also be
// attached, as GNU tools take it: "--threads=4" and "-j4" read as "--threads 4" and "-j 4". An
// attached value that its option does not take ("--stats=1") is refused at the next argument.
class Arguments {
public:
    Arguments(int argc, const char* const* argv, int first) : argc_(argc), argv_(argv), index_(first) {}
    bool done() const {
        check_attached_value_taken();
        return index_ >= argc_;
    }
    std::string next() {
        check_attached_value_taken();
        std::string arg = argv_[index_++];
        std::string name, value;
        if (split_long_option(arg, name, value)) {
            attached_value_ = value;
            attached_to_ = name;
            return name;
        }
        if (arg.size() > 2 && arg.rfind("-j", 0) == 0) {
            attached_value_ = arg.substr(2);
            arg.resize(2);
            attached_to_ = arg;
        }
        return arg;
    }
    /// A file name: like value_for, and not empty ("" is what an unset shell variable gives, and
    /// a render would write nothing).
    std::string file_name_for(const std::string& option, const std::string& missing_message = "") {
        std::string name = value_for(option, missing_message);
        if (name.empty()) usage_error(option + " needs a file name, got an empty one");
        return name;
    }
    std::string value_for(const std::string& option, const std::string& missing_message = "") {
        if (!attached_to_.empty()) {
            attached_to_.clear();
            return attached_value_;
        }
        if (index_ >= argc_) usage_error(missing_message.empty() ? option + " needs a value" : missing_message);
        return argv_[index_++];
    }

private:
    void check_attached_value_taken() const {
        if (!attached_to_.empty()) usage_error(attached_to_ + " takes no value, got '" + attached_value_ + "'");
    }

    int argc_;
    const char* const* argv_;
    int index_;
    std::string attached_to_;  ///< the option whose attached value is not yet read; empty: none
    std::string attached_value_;
};

// The switches that adjust a course's conventions, kept apart until the command line is read, so
// that they apply whichever conventions are chosen and in whatever order they were given.
struct ConventionChoices {
    const char* name = nullptr;  ///< "course" or "mit6837" from --conventions; null: by the form
    bool fov_given = false;
    FovAxis fov_axis = FovAxis::Both;
    bool shade_back = false;
    bool specular_fix = false;
};

Conventions chosen_conventions(const ConventionChoices& choices, bool mit_form) {
    const bool mit = choices.name ? std::strcmp(choices.name, "mit6837") == 0 : mit_form;
    Conventions conventions = mit ? Conventions::mit6837() : Conventions::course();
    if (choices.fov_given) conventions.fov_axis = choices.fov_axis;
    if (choices.shade_back) conventions.shade_back_faces = true;
    if (choices.specular_fix) conventions.specular = SpecularModel::BlinnTimesNdotL;
    return conventions;
}

void check_render_options(CliOptions& options, const std::vector<std::string>& positional) {
    if (options.mit_form) {
        if (!positional.empty()) usage_error("unexpected argument '" + positional[0] + "' (with -input, name files with -output)");
        if (options.scene_path.empty()) usage_error("-input SCENE is missing");
        if (options.output_path.empty() && options.depth_path.empty() && options.normals_path.empty())
            usage_error("nothing to write: give -output FILE (or -depth NEAR FAR FILE, or -normals FILE)");
        if (options.output_format)
            usage_error("--format is for raycast SCENE OUTPUT: with -input, -output FILE takes its format from its "
                        "name (.bmp, .ppm, .tga or .png)");
    } else {
        if (positional.size() < 2)
            usage_error(positional.empty() ? "missing SCENE and OUTPUT" : "missing OUTPUT (the image to write)");
        if (positional.size() > 2) usage_error("unexpected argument '" + positional[2] + "'");
        options.scene_path = positional[0];
        // "-" is standard output, as for most tools (its format must come from --format).
        options.output_path = positional[1] == "-" ? "/dev/stdout" : positional[1];
        // An unset shell variable ("$OUT") gives an empty argument: the render would write nothing.
        if (options.scene_path.empty()) usage_error("SCENE is an empty name");
        if (options.output_path.empty()) usage_error("OUTPUT is an empty name: name the image to write");
    }
    if (options.render.has_crop) {
        const CropWindow& c = options.render.crop;
        if (c.x0 < 0 || c.y0 < 0 || c.x1 <= c.x0 || c.y1 <= c.y0)
            usage_error("--crop needs X0 < X1 and Y0 < Y1, all at least 0");
    }
}

bool looks_like_integer(const std::string& text) {
    size_t i = text.size() > 1 && (text[0] == '-' || text[0] == '+') ? 1 : 0;
    if (i == text.size()) return false;
    for (; i < text.size(); ++i)
        if (text[i] < '0' || text[i] > '9') return false;
    return true;
}

// explain SCENE X Y, or X Y with MIT's -input SCENE; no images to write.
void check_explain_options(CliOptions& options, const std::vector<std::string>& positional) {
    if (!options.output_path.empty() || !options.depth_path.empty() || !options.normals_path.empty())
        usage_error("explain prints the ray tree of one pixel and writes no image: drop -output, -depth and -normals");
    // X and Y are pixels of the whole image; a window would only suggest otherwise.
    if (options.render.has_crop) usage_error("explain takes X and Y in the whole image: drop --crop");
    const size_t wanted = options.mit_form ? 2 : 3;
    if (positional.size() != wanted)
        usage_error(options.mit_form ? "explain needs the pixel: raycast explain -input SCENE X Y"
                                     : "explain needs a scene and a pixel: raycast explain SCENE X Y");
    if (!options.mit_form) options.scene_path = positional[0];
    const size_t first = wanted - 2;
    options.explain_x = parse_count(positional[first], "explain X", kMaxImageSide);
    options.explain_y = parse_count(positional[first + 1], "explain Y", kMaxImageSide);
}

// view SCENE, or MIT's -input SCENE; the page shows the image, so nothing is written.
void check_view_options(CliOptions& options, const std::vector<std::string>& positional) {
    if (!options.output_path.empty() || !options.depth_path.empty() || !options.normals_path.empty())
        usage_error("view shows the image in a browser and writes none: drop -output, -depth and -normals");
    if (options.render.has_crop) usage_error("view shows the whole image: drop --crop");
    const size_t wanted = options.mit_form ? 0 : 1;
    if (positional.size() != wanted)
        usage_error(options.mit_form ? "unexpected argument '" + positional[0] + "'"
                                     : "view needs one scene: raycast view SCENE [options]");
    if (!options.mit_form) options.scene_path = positional[0];
}

CropWindow parse_crop(const std::string& text) {
    const std::vector<std::string> parts = split(text, ',');
    if (parts.size() != 4) usage_error("--crop needs X0,Y0,X1,Y1, got '" + text + "'");
    int values[4];
    for (int i = 0; i < 4; ++i) {
        int64_t v = 0;
        const char* first = parts[static_cast<size_t>(i)].c_str();
        const char* last = first + parts[static_cast<size_t>(i)].size();
        const NumberResult r = parse_int(first, last, v);
        if (r.status != NumberStatus::Ok || r.end != last || v < 0 || v > kMaxImageSide)
            usage_error("--crop needs four whole numbers from 0 to " + std::to_string(kMaxImageSide) + ", got '" + text + "'");
        values[i] = static_cast<int>(v);
    }
    return {values[0], values[1], values[2], values[3]};
}

}  // namespace

CliOptions parse_command_line(int argc, const char* const* argv) {
    CliOptions options;
    if (argc >= 2 && (std::strcmp(argv[1], "compare") == 0 || std::strcmp(argv[1], "merge") == 0)) {
        const bool compare = std::strcmp(argv[1], "compare") == 0;
        options.command = compare ? CliOptions::Command::Compare : CliOptions::Command::Merge;
        Arguments args(argc, argv, 2);
        while (!args.done()) {
            const std::string arg = args.next();
            if (arg == "-h" || arg == "--help") {
                options.command = CliOptions::Command::Help;
                return options;
            }
            if (arg == "-q" || arg == "--quiet") {
                options.quiet = true;
            } else if (compare && arg == "--diff") {
                options.diff_path = args.file_name_for(arg, "--diff needs a file name");
            } else if (compare && arg == "--mask") {
                options.mask_path = args.file_name_for(arg, "--mask needs a file name");
            } else if (compare && arg == "--max-diff") {
                options.tolerance.max_diff =
                    parse_count(args.value_for(arg, "--max-diff needs a number of levels, 0 to 255"), "--max-diff", 255);
                options.grade = true;
            } else if (compare && arg == "--max-fraction") {
                options.tolerance.max_fraction = parse_fraction(
                    args.value_for(arg, "--max-fraction needs a fraction of the pixels, 0 to 1"), "--max-fraction");
                options.grade = true;
            } else if (!compare && (arg == "-o" || arg == "--output")) {
                options.merge_output = args.file_name_for(arg, arg + " needs a file name");
            } else if (arg.size() > 1 && arg[0] == '-') {
                usage_error("unknown option '" + arg + "' for " + argv[1]);
            } else {
                options.inputs.push_back(arg);
            }
        }
        if (compare && options.inputs.size() != 2) usage_error("compare needs two images: raycast compare A B");
        if (!compare && options.merge_output.empty()) usage_error("merge needs -o OUTPUT");
        if (!compare && options.inputs.empty()) usage_error("merge needs at least one piece");
        return options;
    }

    const bool explain = argc >= 2 && std::strcmp(argv[1], "explain") == 0;
    const bool view = argc >= 2 && std::strcmp(argv[1], "view") == 0;
    if (explain) options.command = CliOptions::Command::Explain;
    if (view) options.command = CliOptions::Command::View;
    Arguments args(argc, argv, explain || view ? 2 : 1);
    std::vector<std::string> positional;
    ConventionChoices choices;
    while (!args.done()) {
        const std::string arg = args.next();
        // explain's pixel coordinates are positional, even when negative (then refused below).
        if (explain && looks_like_integer(arg)) {
            positional.push_back(arg);
            continue;
        }
        if (arg == "-h" || arg == "--help") {
            options.command = CliOptions::Command::Help;
            return options;
        }
        if (arg == "--version") {
            options.command = CliOptions::Command::Version;
            return options;
        }
        // MIT 6.837's flags.
        if (arg == "-input") {
            options.mit_form = true;
            options.scene_path = args.file_name_for(arg);
        } else if (arg == "-size") {
            options.mit_form = true;
            options.width = parse_positive_int(args.value_for(arg), "-size width", kMaxImageSide);
            options.height = parse_positive_int(args.value_for(arg), "-size height", kMaxImageSide);
            check_pixel_count("-size", options);
        } else if (arg == "-output") {
            options.mit_form = true;
            options.output_path = args.file_name_for(arg);
        } else if (arg == "-depth") {
            options.mit_form = true;
            options.render.depth_near = parse_number(args.value_for("-depth NEAR FAR FILE"), "-depth NEAR");
            options.render.depth_far = parse_number(args.value_for("-depth NEAR FAR FILE"), "-depth FAR");
            options.depth_path = args.file_name_for("-depth NEAR FAR FILE");
            // As --depth-range: NEAR 0 and FAR 0 would mean "the visible range", which MIT's
            // form does not have.
            if (!(options.render.depth_far > options.render.depth_near))
                usage_error(string_printf("-depth needs NEAR < FAR, got %g %g", double(options.render.depth_near),
                                          double(options.render.depth_far)));
        } else if (arg == "-normals") {
            options.mit_form = true;
            options.normals_path = args.file_name_for(arg);
        } else if (arg == "-shade_back" || arg == "--shade-back") {
            choices.shade_back = true;
        } else if (arg == "-specular_fix" || arg == "--specular-fix") {
            choices.specular_fix = true;
        } else if (arg == "-shadows" || arg == "--shadows") {
            options.render.shadows = true;
        } else if (arg == "-gui" || arg == "-gouraud") {
            options.notes.push_back(arg + " is ignored: raycast has no OpenGL preview");
        } else if (arg == "-tessellation") {
            args.value_for(arg);
            args.value_for(arg);
            options.notes.push_back("-tessellation is ignored: raycast has no OpenGL preview");
        } else if (arg == "-bounces" || arg == "--bounces") {
            options.render.bounces = parse_count(args.value_for(arg), arg, kMaxBounces);
        } else if (arg == "-weight" || arg == "--weight") {
            const std::string value = args.value_for(arg);
            options.render.weight_cutoff = parse_number(value, arg);
            if (!(options.render.weight_cutoff >= 0 && options.render.weight_cutoff <= 1))
                usage_error(arg + " must be from 0 to 1, got " + value);
        } else if (arg == "-transparent_shadows" || arg == "--transparent-shadows") {
            options.render.transparent_shadows = true;
        }
        // raycast's own options.
        else if (arg == "-j" || arg == "--threads") {
            options.threads = parse_positive_int(args.value_for(arg), arg, 4096);
        } else if (arg == "--size") {
            parse_size(args.value_for(arg), arg, options);
        } else if (arg == "--allow-missing-meshes") {
            options.allow_missing_meshes = true;
        } else if (arg == "--stats") {
            options.stats = true;
        } else if (arg == "-q" || arg == "--quiet") {
            options.quiet = true;
        } else if (arg == "--conventions") {
            const std::string name = args.value_for(arg);
            if (name == "course")
                choices.name = "course";
            else if (name == "mit6837")
                choices.name = "mit6837";
            else
                usage_error("--conventions must be course or mit6837, got '" + name + "'");
        } else if (arg == "--fov") {
            const std::string axis = args.value_for(arg);
            if (axis == "vertical")
                choices.fov_axis = FovAxis::Vertical;
            else if (axis == "both")
                choices.fov_axis = FovAxis::Both;
            else
                usage_error("--fov must be vertical or both, got '" + axis + "'");
            choices.fov_given = true;
        } else if (arg == "--mode") {
            const std::string mode = args.value_for(arg);
            if (mode == "shaded") options.render.mode = RenderMode::Shaded;
            else if (mode == "normals") options.render.mode = RenderMode::Normals;
            else if (mode == "depth") options.render.mode = RenderMode::Depth;
            else if (mode == "material") options.render.mode = RenderMode::Material;
            else if (mode == "cost") options.render.mode = RenderMode::Cost;
            else if (mode == "ao") options.render.mode = RenderMode::AmbientOcclusion;
            else usage_error("--mode must be shaded, normals, depth, material, cost or ao, got '" + mode + "'");
        } else if (arg == "--ao-samples") {
            options.render.ao_samples = parse_positive_int(args.value_for(arg), arg, 4096);
        } else if (arg == "--ao-distance") {
            const std::string value = args.value_for(arg);
            options.render.ao_distance = parse_number(value, arg);
            if (!(options.render.ao_distance > 0) || !std::isfinite(options.render.ao_distance))
                usage_error("--ao-distance must be a positive number, got " + value);
        } else if (!explain && !view && arg == "--format") {
            const std::string name = args.value_for(arg);
            options.output_format = image_format_named(name);
            if (!options.output_format) usage_error("--format must be bmp, ppm, tga or png, got '" + name + "'");
        } else if (arg == "--depth") {
            options.depth_path = args.file_name_for(arg);
        } else if (arg == "--normals") {
            options.normals_path = args.file_name_for(arg);
        } else if (arg == "--depth-range") {
            const std::string range = args.value_for(arg);
            const std::vector<std::string> parts = split(range, ',');
            if (parts.size() != 2) usage_error("--depth-range needs NEAR,FAR, got '" + range + "'");
            options.render.depth_near = parse_number(parts[0], "--depth-range NEAR");
            options.render.depth_far = parse_number(parts[1], "--depth-range FAR");
            if (!(options.render.depth_far > options.render.depth_near))
                usage_error("--depth-range needs NEAR < FAR, got '" + range + "'");
        } else if (arg == "--spp") {
            options.render.samples_per_pixel = parse_positive_int(args.value_for(arg), arg, 65536);
        } else if (arg == "--aperture") {
            options.aperture = parse_number(args.value_for(arg), arg);
            if (!(options.aperture >= 0)) usage_error("--aperture must not be negative");
            // The lens's rays start up to half of it from the camera: held to the camera's limit.
            if (!(options.aperture <= kMaxCoordinate))
                usage_error(string_printf("--aperture must be at most %g, raycast's coordinate limit, got %g",
                                          double(kMaxCoordinate), double(options.aperture)));
        } else if (arg == "--focus-distance") {
            options.focus_distance = parse_number(args.value_for(arg), arg);
            options.has_focus_distance = true;
            if (!(options.focus_distance > 0)) usage_error("--focus-distance must be positive");
            if (!(options.focus_distance <= kMaxCoordinate))
                usage_error(string_printf("--focus-distance must be at most %g, raycast's coordinate limit, got %g",
                                          double(kMaxCoordinate), double(options.focus_distance)));
        } else if (arg == "--crop") {
            options.render.crop = parse_crop(args.value_for(arg));
            options.render.has_crop = true;
        } else if (arg == "--tile") {
            options.render.tile_size = parse_positive_int(args.value_for(arg), arg, 4096);
        } else if (arg == "--no-packets") {
            options.render.packet_isa = PacketIsa::None;
        } else if (arg == "--test-every-face") {
            options.render.skip_back_faces = false;
        } else if (arg == "--simd") {
            const std::string name = args.value_for(arg);
            PacketIsa isa = PacketIsa::None;
            if (name == "auto")
                isa = best_packet_isa();
            else if (!packet_isa_from_name(name.c_str(), isa))
                usage_error("--simd must be auto, avx512, avx2, sse2, portable or none, got '" + name + "'");
            if (!packet_isa_available(isa))
                usage_error("--simd " + name + " is not available on this CPU or in this build");
            options.render.packet_isa = isa;
        } else if (view && arg == "--port") {
            options.view_port = parse_count(args.value_for(arg), arg, 65535);
        } else if (view && arg == "--host") {
            options.view_host = args.value_for(arg);
            if (options.view_host.empty()) usage_error("--host needs an address");
        } else if (arg.size() > 1 && arg[0] == '-' && arg != "-") {
            usage_error("unknown option '" + arg + "'");
        } else {
            positional.push_back(arg);
        }
    }
    if (explain)
        check_explain_options(options, positional);
    else if (view)
        check_view_options(options, positional);
    else
        check_render_options(options, positional);
    options.conventions = chosen_conventions(choices, options.mit_form);
    options.mit_conventions = choices.name ? std::strcmp(choices.name, "mit6837") == 0 : options.mit_form;
    options.fov_given = choices.fov_given;
    return options;
}

}  // namespace raycast
