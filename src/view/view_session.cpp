#include "view/view_session.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <utility>

#include "base/check.h"
#include "base/json_writer.h"
#include "base/limits.h"
#include "base/parallel.h"
#include "base/parse_number.h"
#include "image/image_io.h"
#include "render/render.h"
#include "scene/build_scene.h"

namespace raycast {

namespace {

// The most a request may ask for: enough for any screen, and a bound on memory and time.
constexpr int kMaxViewSide = 4096;
constexpr int kMaxViewSamples = 256;
constexpr int kDefaultViewSide = 400;  // for a camera that gives no size (MIT's scenes)

ViewResponse text_response(int status, std::string body) {
    if (body.empty() || body.back() != '\n') body += '\n';
    return {status, "text/plain; charset=utf-8", std::move(body)};
}

ViewResponse json_response(std::string body) { return {200, "application/json", std::move(body)}; }

bool parse_whole_float(const std::string& text, float& value) {
    const char* first = text.c_str();
    const char* last = first + text.size();
    const NumberResult result = parse_float(first, last, value);
    return result.status == NumberStatus::Ok && result.end == last && std::isfinite(value);
}

bool parse_whole_int(const std::string& text, int64_t& value) {
    const char* first = text.c_str();
    const char* last = first + text.size();
    const NumberResult result = parse_int(first, last, value);
    return result.status == NumberStatus::Ok && result.end == last;
}

// "x,y,z" with three finite numbers.
bool parse_vec3(const std::string& text, Vec3f& v) {
    const size_t a = text.find(','), b = a == std::string::npos ? a : text.find(',', a + 1);
    if (b == std::string::npos || text.find(',', b + 1) != std::string::npos) return false;
    return parse_whole_float(text.substr(0, a), v.x) && parse_whole_float(text.substr(a + 1, b - a - 1), v.y) &&
           parse_whole_float(text.substr(b + 1), v.z);
}

// "lightN", N a light's number written as a whole number is (no sign, no leading zero); a
// number too large for `index` is SIZE_MAX, which names no light.
bool light_index(const std::string& name, size_t& index) {
    if (name.compare(0, 5, "light") != 0 || name.size() == 5) return false;
    if (name[5] == '0' && name.size() > 6) return false;
    index = 0;
    for (size_t i = 5; i < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9') return false;
        const size_t digit = static_cast<size_t>(name[i] - '0');
        index = index > (SIZE_MAX - digit) / 10 ? SIZE_MAX : index * 10 + digit;
    }
    return true;
}

bool parse_switch(const std::string& text, bool& value) {
    if (text == "1" || text == "true") return value = true, true;
    if (text == "0" || text == "false") return value = false, true;
    return false;
}

// The refusal of a parameter that puts `what` (the camera, a point light) at `p`, beyond the
// coordinate limit that the scene file's own positions keep (NaN included); empty within it.
std::string beyond_coordinate_limit(const std::string& parameter, const char* what, Vec3f p) {
    if (max_abs(p) <= kMaxCoordinate) return {};
    return string_printf("parameter '%s' puts %s at coordinates of %g, beyond raycast's limit of %g", parameter.c_str(),
                         what, double(max_abs(p)), double(kMaxCoordinate));
}

// A query value as it may be shown in a message: short, printable ASCII (the answer is UTF-8
// text, and a decoded %FF is no character).
std::string shown(const std::string& value) {
    std::string out;
    for (const char c : value.substr(0, 40)) out += static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f ? '?' : c;
    return "'" + out + (value.size() > 40 ? "...'" : "'");
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// Percent-decoding of one name or value; false for a '%' not followed by two hex digits.
bool decode_query_text(const std::string& text, std::string& out) {
    out.clear();
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '+') {
            out += ' ';
        } else if (text[i] != '%') {
            out += text[i];
        } else {
            const int high = i + 2 < text.size() ? hex_digit(text[i + 1]) : -1;
            const int low = high >= 0 ? hex_digit(text[i + 2]) : -1;
            if (low < 0) return false;
            out += static_cast<char>(high * 16 + low);
            i += 2;
        }
    }
    return true;
}

// Everything of the conventions that the scene or its shading reads, as a cache key.
std::string conventions_key(const Conventions& c) {
    return string_printf("%g/%d/%d/%g/%d/%d/%d/%d", double(c.pixel_offset), int(c.fov_axis), int(c.specular),
                         double(c.default_shininess), int(c.ambient_without_lights), int(c.orthographic_sees_behind),
                         int(c.black_back_faces), int(c.shade_back_faces));
}

void write_diagnostics(JsonWriter& json, const char* name, const std::vector<Diagnostic>& diagnostics) {
    json.key(name);
    json.open('[');
    for (const Diagnostic& d : diagnostics) {
        json.item();
        json.open('{');
        json.field("severity", std::string(d.severity == Severity::Error     ? "error"
                                           : d.severity == Severity::Warning ? "warning"
                                                                             : "note"));
        json.field("file", d.location.file);
        json.integer_field("line", d.location.line);
        json.integer_field("column", d.location.column);
        json.field("message", d.message);
        json.field("source_line", d.source_line);
        json.field("text", format_diagnostic(d));
        json.close('}');
    }
    json.close(']');
}

}  // namespace

bool parse_query(const std::string& target, QueryParameters& parameters, std::string& error) {
    parameters.clear();
    const size_t question = target.find('?');
    if (question == std::string::npos) return true;
    const std::string query = target.substr(question + 1);
    for (size_t start = 0; start <= query.size();) {
        size_t end = query.find('&', start);
        if (end == std::string::npos) end = query.size();
        const std::string part = query.substr(start, end - start);
        start = end + 1;
        if (part.empty()) continue;  // "a=1&&b=2", or a '&' last
        const size_t equals = part.find('=');
        std::string name, value;
        if (equals == std::string::npos || part.find('=', equals + 1) != std::string::npos || equals == 0) {
            error = "a query parameter must be NAME=VALUE, got " + shown(part);
            return false;
        }
        if (!decode_query_text(part.substr(0, equals), name) || !decode_query_text(part.substr(equals + 1), value)) {
            error = "a '%' in the query must be followed by two hex digits, got " + shown(part);
            return false;
        }
        parameters.emplace(std::move(name), std::move(value));
    }
    return true;
}

// A request's render options, conventions and camera, and the pixel for /explain.
struct ViewSession::Request {
    RenderOptions options;
    Conventions conventions;
    CameraDesc camera;
    struct LightMove {
        std::string name;  // lightN
        size_t index;      // N (SIZE_MAX if past it)
        Vec3f to;          // the position of a point light, the direction of a directional one
        std::string text;  // the value as the query wrote it
    };
    std::vector<LightMove> light_moves;
    // The description the camera and the lights were checked against, and the one the request
    // renders: read once, so that a reload in between cannot pair a light's number with a scene
    // that has fewer lights (that wrote past the end of the lights).
    std::shared_ptr<const SceneDesc> desc;
    int width = 0, height = 0;
    int x = -1, y = -1;
};

struct ViewSession::Prepared {
    Request request;                     // request.desc is the description it renders
    std::shared_ptr<const Scene> scene;  // built from request.desc
    Camera camera;              // request.options.camera points here
    std::vector<Light> lights;  // request.options.lights points here when the query moved one
};

ViewSession::ViewSession(ViewSettings settings) : settings_(std::move(settings)) {
    settings_.render.progress = nullptr;
    settings_.render.has_crop = false;  // the viewer always shows the whole frame
}

ViewSession::FileStamp ViewSession::stamp(const std::string& path) { return {path, current_version(path)}; }

// Each mesh as the loader opened it (MeshDesc::version): a second look by name, after the load,
// could see a version saved while the old one was read, and then that save would never reload.
std::vector<ViewSession::FileStamp> ViewSession::stamps_of(const SceneDesc* desc) const {
    std::vector<FileStamp> stamps{stamp(settings_.scene_path)};
    if (desc)
        for (const MeshDesc& mesh : desc->meshes) stamps.push_back({mesh.path, mesh.version});
    return stamps;
}

uint64_t ViewSession::version() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return loaded_.version;
}

std::vector<std::string> ViewSession::watched_files() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> files;
    for (const FileStamp& s : stamps_) files.push_back(s.path);
    return files;
}

std::vector<Diagnostic> ViewSession::diagnostics() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Diagnostic> all = loaded_.errors;
    if (all.empty()) all = loaded_.warnings;
    return all;
}

bool ViewSession::reload_if_changed(const std::function<bool(bool)>& changed_during_load,
                                    const std::function<bool()>& change_heard) {
    // The files as they are before this load reads them: a file written again while the load
    // reads it must not be recorded as loaded (a mesh saved twice 30 ms apart left the viewer
    // showing the first version, with no error).
    std::vector<FileStamp> before{stamp(settings_.scene_path)};
    bool first = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        first = loaded_.version == 0;
        bool changed = first;
        for (const FileStamp& old : stamps_) {
            before.push_back(stamp(old.path));
            changed |= !(before.back() == old);
        }
        if (!changed) return false;
    }
    // A change the watcher has not heard of may be a save whose writer has emptied the file and
    // not yet queued the event: read now, the empty file was shown as a version of its own.
    if (!first && change_heard && !change_heard()) return false;
    // Load and build outside the lock: requests go on with the last scene meanwhile.
    std::shared_ptr<SceneDesc> desc;
    std::shared_ptr<const Scene> scene;
    std::vector<Diagnostic> errors;
    std::vector<FileStamp> stamps;
    // Asked once the files are read, before the scene is built: a save that began meanwhile
    // drops the load unbuilt. A save's event is queued a moment after the file changed, so one
    // whose first call has not yet returned is found by the files' times and sizes instead. A
    // save during the build changes nothing read: the stamps below have the next look load it.
    const auto save_began = [&] {
        if (!changed_during_load) return false;
        bool files_changed = false;
        for (const FileStamp& earlier : before) files_changed |= !(stamp(earlier.path) == earlier);
        return changed_during_load(files_changed);
    };
    try {
        desc = std::make_shared<SceneDesc>(load_scene_file(settings_.scene_path, settings_.load));
        if (save_began()) return false;
        stamps = stamps_of(desc.get());
        SceneBuildOptions build;
        build.width = settings_.width > 0 ? settings_.width : (desc->camera && desc->camera->width > 0 ? 0 : kDefaultViewSide);
        build.height = settings_.height > 0 ? settings_.height : (desc->camera && desc->camera->height > 0 ? 0 : kDefaultViewSide);
        build.conventions = settings_.conventions;
        build.threads = settings_.render.threads;
        scene = std::make_shared<const Scene>(build_scene(*desc, build));
    } catch (const InputError& error) {
        if (!desc && save_began()) return false;  // the read failed, perhaps on a half-written file
        errors = error.diagnostics();
        if (stamps.empty()) stamps = stamps_of(nullptr);
    } catch (const std::bad_alloc&) {
        if (!desc && save_began()) return false;
        Diagnostic out_of_memory;
        out_of_memory.location.file = settings_.scene_path;
        out_of_memory.message = "out of memory while loading the scene";
        errors.push_back(std::move(out_of_memory));
        if (stamps.empty()) stamps = stamps_of(nullptr);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    // Keep watching the meshes of the last good scene too, so that fixing one reloads.
    if (errors.empty()) {
        loaded_.desc = std::move(desc);
        loaded_.warnings = loaded_.desc->warnings;
        scenes_.clear();
        scenes_[conventions_key(settings_.conventions)] = std::move(scene);
    } else {
        for (const FileStamp& old : stamps_)
            if (std::none_of(stamps.begin(), stamps.end(), [&](const FileStamp& s) { return s.path == old.path; }))
                stamps.push_back(stamp(old.path));
    }
    loaded_.errors = std::move(errors);
    // A file that changed while it was read keeps the stamp from before, so that the next look
    // finds it changed and loads it again.
    for (FileStamp& after : stamps)
        for (const FileStamp& earlier : before)
            if (earlier.path == after.path && !(earlier == after)) after = earlier;
    stamps_ = std::move(stamps);
    ++loaded_.version;
    return true;
}

std::shared_ptr<const Scene> ViewSession::scene_for(const std::shared_ptr<const SceneDesc>& desc,
                                                    const Conventions& conventions, std::string& error) {
    const std::string key = conventions_key(conventions);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (desc != loaded_.desc) {
            error = "the scene changed while the request waited: ask again";
            return nullptr;
        }
        auto found = scenes_.find(key);
        if (found != scenes_.end()) return found->second;
    }
    std::lock_guard<std::mutex> building(build_mutex_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto found = scenes_.find(key);
        if (desc == loaded_.desc && found != scenes_.end()) return found->second;
    }
    SceneBuildOptions build;
    build.width = desc->camera && desc->camera->width > 0 ? 0 : kDefaultViewSide;
    build.height = desc->camera && desc->camera->height > 0 ? 0 : kDefaultViewSide;
    build.conventions = conventions;
    build.threads = settings_.render.threads;
    std::shared_ptr<const Scene> scene;
    try {
        scene = std::make_shared<const Scene>(build_scene(*desc, build));
    } catch (const InputError& e) {
        error = e.what();
        return nullptr;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (desc == loaded_.desc) scenes_[key] = scene;
    return scene;
}

bool ViewSession::parse_request(const QueryParameters& query, bool explaining, Request& request,
                                std::string& error) const {
    request.options = settings_.render;
    request.conventions = settings_.conventions;
    bool mit = settings_.mit_conventions;
    bool fov_given = false, shade_back_given = false;
    FovAxis fov = settings_.conventions.fov_axis;
    bool shade_back = settings_.conventions.shade_back_faces;
    std::set<std::string> seen;
    Vec3f eye, direction, up;
    bool has_eye = false, has_direction = false, has_up = false;
    float angle = 0, size = 0;
    for (const auto& parameter : query) {
        // Named references, not a structured binding: lambdas may capture those only from C++20.
        const std::string& name = parameter.first;
        const std::string& value = parameter.second;
        if (!seen.insert(name).second) return error = "parameter '" + name + "' is given twice", false;
        const auto fail = [&](const std::string& expected) {
            error = "parameter '" + name + "' " + expected + ", got " + shown(value);
            return false;
        };
        int64_t whole = 0;
        float number = 0;
        bool flag = false;
        RenderOptions& o = request.options;
        if (name == "mode") {
            const std::pair<const char*, RenderMode> modes[] = {
                {"shaded", RenderMode::Shaded}, {"normals", RenderMode::Normals}, {"depth", RenderMode::Depth},
                {"material", RenderMode::Material}, {"cost", RenderMode::Cost}, {"ao", RenderMode::AmbientOcclusion}};
            bool known = false;
            for (const auto& [mode_name, mode] : modes)
                if (value == mode_name) o.mode = mode, known = true;
            if (!known) return fail("must be shaded, normals, depth, material, cost or ao");
        } else if (name == "shadows" || name == "transparent_shadows" || name == "shade_back") {
            if (!parse_switch(value, flag)) return fail("must be 0 or 1");
            if (name == "shadows") o.shadows = flag;
            if (name == "transparent_shadows") o.transparent_shadows = flag;
            if (name == "shade_back") shade_back = flag, shade_back_given = true;
        } else if (name == "bounces") {
            if (!parse_whole_int(value, whole) || whole < 0 || whole > kMaxBounces)
                return fail(string_printf("must be a whole number from 0 to %d", kMaxBounces));
            o.bounces = static_cast<int>(whole);
        } else if (name == "weight") {
            if (!parse_whole_float(value, number) || number < 0 || number > 1) return fail("must be a number from 0 to 1");
            o.weight_cutoff = number;
        } else if (name == "spp") {
            if (!parse_whole_int(value, whole) || whole < 1 || whole > kMaxViewSamples)
                return fail(string_printf("must be a whole number from 1 to %d", kMaxViewSamples));
            o.samples_per_pixel = static_cast<int>(whole);
        } else if (name == "ao_samples") {
            if (!parse_whole_int(value, whole) || whole < 1 || whole > 4096)
                return fail("must be a whole number from 1 to 4096");
            o.ao_samples = static_cast<int>(whole);
        } else if (name == "ao_distance") {
            if (!parse_whole_float(value, number) || !(number > 0)) return fail("must be a positive number");
            o.ao_distance = number;
        } else if (name == "conventions") {
            if (value != "course" && value != "mit6837") return fail("must be course or mit6837");
            mit = value == "mit6837";
        } else if (name == "fov") {
            if (value != "both" && value != "vertical") return fail("must be both or vertical");
            fov = value == "both" ? FovAxis::Both : FovAxis::Vertical;
            fov_given = true;
        } else if (name == "width" || name == "height") {
            if (!parse_whole_int(value, whole) || whole < 1 || whole > kMaxViewSide)
                return fail(string_printf("must be a whole number from 1 to %d", kMaxViewSide));
            (name == "width" ? request.width : request.height) = static_cast<int>(whole);
        } else if (name == "eye" || name == "dir" || name == "up") {
            Vec3f v;
            if (!parse_vec3(value, v)) return fail("must be three numbers x,y,z");
            if (name == "eye") eye = v, has_eye = true;
            if (name == "dir") direction = v, has_direction = true;
            if (name == "up") up = v, has_up = true;
        } else if (name == "angle") {
            if (!parse_whole_float(value, number) || !(number > 0 && number < 180))
                return fail("must be more than 0 and less than 180 degrees");
            angle = number;
        } else if (name == "size") {
            if (!parse_whole_float(value, number) || !(number > 0)) return fail("must be a positive number");
            size = number;
        } else if (size_t index = 0; light_index(name, index)) {
            Vec3f v;
            if (!parse_vec3(value, v)) return fail("must be three numbers x,y,z");
            request.light_moves.push_back({name, index, v, value});
        } else if (explaining && (name == "x" || name == "y")) {
            if (!parse_whole_int(value, whole) || whole < 0 || whole >= kMaxViewSide)
                return fail("must be a pixel's column (x) or row from the top (y)");
            (name == "x" ? request.x : request.y) = static_cast<int>(whole);
        } else {
            error = "unknown parameter " + shown(name);
            return false;
        }
    }
    if (explaining && (request.x < 0 || request.y < 0)) return error = "explain needs the pixel: x= and y=", false;
    // The conventions: the chosen base, with the command line's adjustments unless the query
    // makes its own.
    if (mit != settings_.mit_conventions) {
        const Conventions given = request.conventions;
        request.conventions = mit ? Conventions::mit6837() : Conventions::course();
        request.conventions.shade_back_faces = given.shade_back_faces;
        request.conventions.specular = given.specular == SpecularModel::BlinnTimesNdotL && mit ? given.specular
                                                                                               : request.conventions.specular;
        if (!fov_given) fov = request.conventions.fov_axis;
    }
    request.conventions.fov_axis = fov;
    if (shade_back_given) request.conventions.shade_back_faces = shade_back;
    // The camera as the file has it, moved where the query says.
    std::lock_guard<std::mutex> lock(mutex_);
    if (!loaded_.desc || !loaded_.desc->camera) return error = "the scene has not loaded", false;
    request.desc = loaded_.desc;
    request.camera = *loaded_.desc->camera;
    CameraDesc& camera = request.camera;
    if (has_eye && !(error = beyond_coordinate_limit("eye", "the camera", eye)).empty()) return false;
    if (has_eye) camera.center = eye;
    if (has_direction) camera.direction = direction;
    if (has_up) camera.up = up;
    if (angle > 0) {
        if (camera.kind != CameraDesc::Kind::Perspective) return error = "angle is for a perspective camera", false;
        camera.angle_degrees = angle;
    }
    if (size > 0) {
        if (camera.kind != CameraDesc::Kind::Orthographic) return error = "size is for an orthographic camera", false;
        camera.size = size;
    }
    // The lights the query moves: a point light's position, a directional light's direction.
    const std::vector<LightDesc>& lights = loaded_.desc->lights;
    for (const Request::LightMove& move : request.light_moves) {
        const std::string name = "parameter '" + move.name + "'";
        if (move.index >= lights.size())
            return error = name + (lights.empty() ? ": the scene has no lights"
                                                  : lights.size() == 1 ? ": the scene has one light, light0"
                                                                       : string_printf(": the scene has %zu lights, light0 to light%zu",
                                                                                       lights.size(), lights.size() - 1)),
                   false;
        if (lights[move.index].kind == LightDesc::Kind::Directional && is_zero(move.to))
            return error = name + " must not be the zero vector (light" + std::to_string(move.index) +
                           " is a directional light), got " + shown(move.text),
                   false;
        if (lights[move.index].kind == LightDesc::Kind::Point &&
            !(error = beyond_coordinate_limit(move.name, "a point light", move.to)).empty())
            return false;
    }
    if (is_zero(camera.direction)) return error = "the camera direction must not be the zero vector", false;
    if (is_zero(camera.up)) return error = "the camera up must not be the zero vector", false;
    if (length(cross(normalize_any_length(camera.direction), normalize_any_length(camera.up))) < 1e-6f)
        return error = "the camera up must not be parallel to its direction", false;
    const int width = settings_.width > 0 ? settings_.width : (camera.width > 0 ? camera.width : kDefaultViewSide);
    const int height = settings_.height > 0 ? settings_.height : (camera.height > 0 ? camera.height : kDefaultViewSide);
    if (request.width == 0) request.width = width;
    if (request.height == 0) request.height = height;
    if (explaining && (request.x >= request.width || request.y >= request.height))
        return error = string_printf("pixel %d %d is outside the %dx%d image", request.x, request.y, request.width,
                                     request.height),
               false;
    return true;
}

bool ViewSession::prepare(const QueryParameters& query, bool explaining, Prepared& prepared, ViewResponse& refusal) {
    std::string error;
    if (!parse_request(query, explaining, prepared.request, error)) return refusal = text_response(400, error), false;
    const Request& request = prepared.request;
    prepared.scene = scene_for(request.desc, request.conventions, error);
    if (!prepared.scene) return refusal = text_response(503, error), false;
    Camera& camera = prepared.camera;
    camera = make_camera(request.camera, request.width, request.height, request.conventions);
    if (settings_.aperture > 0) {
        camera.lens_radius = settings_.aperture / 2;
        camera.focus_distance =
            settings_.focus_distance > 0 ? settings_.focus_distance : auto_focus_distance(*prepared.scene, camera);
    }
    prepared.request.options.camera = &camera;
    if (!request.light_moves.empty()) {
        // As build_scene makes them from the file's lights, moved.
        // scene_for built (or found) the scene of request.desc, whose lights were checked.
        prepared.lights = prepared.scene->lights;
        RAYCAST_CHECK(prepared.lights.size() == request.desc->lights.size());
        for (const Request::LightMove& move : request.light_moves) {
            Light& light = prepared.lights[move.index];
            if (light.kind == Light::Kind::Directional) light.direction = normalize_any_length(move.to);
            else light.position = move.to;
        }
        prepared.request.options.lights = &prepared.lights;
    }
    return true;
}

ViewResponse ViewSession::image(const QueryParameters& query) {
    // Requests are numbered as they arrive, and the newest one that is valid cancels the older
    // renders; a refused request (a bad parameter, the scene reloading) cancels nothing.
    const uint64_t id = ++image_tickets_;
    Prepared prepared;
    ViewResponse refusal;
    if (!prepare(query, false, prepared, refusal)) return refusal;
    uint64_t latest = latest_image_.load();
    while (latest < id && !latest_image_.compare_exchange_weak(latest, id)) {
    }
    if (latest > id) return text_response(409, "cancelled: a newer image was asked for");
    const std::shared_ptr<const Scene>& scene = prepared.scene;
    RenderOptions& options = prepared.request.options;
    options.cancelled = [this, id] { return latest_image_.load(std::memory_order_relaxed) != id; };
    RenderStats stats;
    FrameImages images = render_frame_rgb8(*scene, options, FrameRequest{}, &stats);
    if (stats.cancelled) return text_response(409, "cancelled: a newer image was asked for");
    const ImageFormat format = png_supported() ? ImageFormat::Png : ImageFormat::Bmp;
    const std::vector<uint8_t> bytes = encode_image(images.color, format);
    return {200, png_supported() ? "image/png" : "image/bmp", std::string(bytes.begin(), bytes.end())};
}

ViewResponse ViewSession::explain(const QueryParameters& query) {
    Prepared prepared;
    ViewResponse refusal;
    if (!prepare(query, true, prepared, refusal)) return refusal;
    const Request& request = prepared.request;
    PixelExplanation explanation = explain_pixel(*prepared.scene, request.options, request.x, request.y);
    explanation.scene = request.desc->file;
    return json_response(explanation_json(explanation));
}

ViewResponse ViewSession::status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    JsonWriter json;
    const auto vec = [&](const char* name, Vec3f v) { json.numbers_field(name, {v.x, v.y, v.z}); };
    json.open('{');
    json.integer_field("version", static_cast<long long>(loaded_.version));
    json.field("scene", settings_.scene_path);
    json.field("loaded", loaded_.desc != nullptr);
    write_diagnostics(json, "errors", loaded_.errors);
    write_diagnostics(json, "warnings", loaded_.warnings);
    json.field("png", png_supported());
    // The defaults every request starts from (the command line's options).
    const RenderOptions& o = settings_.render;
    json.key("defaults");
    json.open('{');
    json.field("mode", std::string(render_mode_name(o.mode)));
    json.field("shadows", o.shadows);
    json.field("transparent_shadows", o.transparent_shadows);
    json.integer_field("bounces", o.bounces);
    json.field("weight", o.weight_cutoff);
    json.integer_field("spp", o.samples_per_pixel);
    json.integer_field("ao_samples", o.ao_samples);
    json.field("ao_distance", o.ao_distance);
    json.field("conventions", std::string(settings_.mit_conventions ? "mit6837" : "course"));
    json.field("fov", std::string(settings_.conventions.fov_axis == FovAxis::Both ? "both" : "vertical"));
    json.field("shade_back", settings_.conventions.shade_back_faces);
    json.close('}');
    // The camera as the scene file writes it, for moving it and for copying the block back.
    json.key("camera");
    if (loaded_.desc && loaded_.desc->camera) {
        const CameraDesc& c = *loaded_.desc->camera;
        json.open('{');
        json.field("kind", std::string(c.kind == CameraDesc::Kind::Perspective ? "PerspectiveCamera" : "OrthographicCamera"));
        vec("center", c.center);
        vec("direction", c.direction);
        vec("up", c.up);
        json.field("angle", c.angle_degrees);
        json.field("size", c.size);
        json.integer_field("file_width", c.width);
        json.integer_field("file_height", c.height);
        json.integer_field("width", settings_.width > 0 ? settings_.width : (c.width > 0 ? c.width : kDefaultViewSide));
        json.integer_field("height",
                           settings_.height > 0 ? settings_.height : (c.height > 0 ? c.height : kDefaultViewSide));
        json.close('}');
        const auto found = scenes_.find(conventions_key(settings_.conventions));
        json.key("bounds");
        if (found != scenes_.end() && !found->second->bounds.is_empty()) {
            json.open('{');
            vec("lower", found->second->bounds.lower);
            vec("upper", found->second->bounds.upper);
            json.close('}');
        } else {
            json.null();
        }
    } else {
        json.null();
        json.key("bounds");
        json.null();
    }
    // The lights as the scene file writes them, for moving them (lightN=) and copying the block
    // back: a point light's position, a directional light's direction as written (not unit).
    json.key("lights");
    if (loaded_.desc) {
        json.open('[');
        for (const LightDesc& light : loaded_.desc->lights) {
            json.item();
            json.open('{');
            const bool point = light.kind == LightDesc::Kind::Point;
            json.field("kind", std::string(point ? "PointLight" : "DirectionalLight"));
            vec(point ? "position" : "direction", point ? light.position : light.direction);
            vec("color", light.color);
            if (point) vec("attenuation", light.attenuation);
            json.close('}');
        }
        json.close(']');
    } else {
        json.null();
    }
    json.close('}');
    std::string body = json.take();
    body += '\n';
    return json_response(std::move(body));
}

}  // namespace raycast
