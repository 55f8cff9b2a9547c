// Fuzz target: the live viewer's requests. The input is the query string of a request
// ("mode=ao&eye=1,2,3&light0=..."), read as `raycast view` reads it (parse_query), then answered
// by a ViewSession on a small scene (two lights, a mirror sphere, a glass sphere, a plane, a
// transformed triangle mesh) as /image, /explain and /status would answer it. An input that
// starts with '~' is the rest of it asked of the same scene through an orthographic camera. The viewer is the
// part of raycast that takes input from a network, so every query must end in an answer.
// Anything but these outcomes is a finding (a crash, a sanitizer report, a failed
// RAYCAST_DCHECK, a hang, an exception):
//  - parse_query refuses a query only with a reason, and the session answers 200 or 400 (409
//    and 503 cannot happen here: one request at a time, the scene loaded once);
//  - a 400's body is one line saying why, ending in a newline;
//  - a 200 image is a PNG or BMP with its content type, and a 200 explanation is a JSON object;
//  - /status is a JSON object.
// Renders are kept small so that the fuzzer keeps its pace: a width or height, samples,
// ambient-occlusion rays or bounces beyond a small number, in a query that asks for them
// correctly, are lowered before the image is asked for (the refusals of values out of range are
// still fuzzed: those go through as written). /explain traces one pixel whatever the size, so it
// gets the width and height as written.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "base/parse_number.h"
#include "view/view_session.h"

namespace {

using namespace raycast;

const char* const kScene = R"(PerspectiveCamera {
    center 0 1 9  direction 0 -0.1 -1  up 0 1 0  angle 35  width 8  height 6
}
Lights {
    numLights 2
    PointLight { position 3 5 5 color 0.8 0.8 0.8 attenuation 1 0.1 0.01 }
    DirectionalLight { direction -0.3 -1 -0.5 color 0.4 0.4 0.4 }
}
Background { color 0.2 0.3 0.5 }
Materials {
    numMaterials 3
    Material { diffuseColor 0.05 0.05 0.05 specularColor 0.6 0.6 0.6 shininess 40 reflectiveColor 0.85 0.85 0.85 }
    Material { diffuseColor 0.1 0.1 0.1 transparentColor 0.9 0.9 0.9 indexOfRefraction 1.5 }
    Material { diffuseColor 0.6 0.6 0.55 }
}
Group {
    numObjects 5
    MaterialIndex 0
    Sphere { center -1 0 0 radius 1 }
    MaterialIndex 1
    Sphere { center 1.3 -0.3 0.8 radius 0.7 }
    MaterialIndex 2
    Plane { normal 0 1 0 offset -1 }
    Transform {
        Translate 0 0 -3  YRotate 30  Scale 2 1 1
        TriangleMesh { obj_file quad.obj }
    }
    Transform { UniformScale 0.5 Sphere { center 0 3 0 radius 1 } }
}
)";

[[noreturn]] void finding(const char* what, const std::string& query, const std::string& detail) {
    std::fprintf(stderr, "fuzz_view_query: FINDING: %s\nquery: %s\n%s\n", what, query.c_str(), detail.c_str());
    std::abort();
}

ViewSession* sessions[2] = {nullptr, nullptr};  // perspective, orthographic

ViewSession& the_session(bool orthographic) {
    ViewSession*& session = sessions[orthographic ? 1 : 0];
    if (session) return *session;
    char folder[] = "/tmp/raycast-fuzz-view-XXXXXX";
    if (!::mkdtemp(folder)) finding("no temporary folder", "", "");
    const std::string dir = folder;
    const auto write = [](const std::string& path, const char* text) {
        FILE* file = std::fopen(path.c_str(), "wb");
        if (!file || std::fputs(text, file) < 0 || std::fclose(file) != 0) finding("cannot write the scene", "", path);
    };
    std::string scene = kScene;
    if (orthographic) {
        const size_t camera_end = scene.find("}\n") + 2;
        scene.replace(0, camera_end, "OrthographicCamera {\n    center 0 1 9  direction 0 -0.1 -1  up 0 1 0  size 6  width 8  height 6\n}\n");
    }
    write(dir + "/s.txt", scene.c_str());
    write(dir + "/quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    ViewSettings settings;
    settings.scene_path = dir + "/s.txt";
    settings.render.threads = 1;
    session = new ViewSession(settings);
    if (!session->reload_if_changed() || !session->diagnostics().empty())
        finding("the fuzz target's own scene did not load", "", "");
    return *session;
}

// Lowers a well-formed value above `most` to `most` (a value out of range stays: its refusal is
// fuzzed too).
void lower(QueryParameters& query, const char* name, int64_t most) {
    const auto found = query.find(name);
    if (found == query.end() || query.count(name) != 1) return;
    int64_t value = 0;
    const std::string& text = found->second;
    const NumberResult result = parse_int(text.c_str(), text.c_str() + text.size(), value);
    if (result.status == NumberStatus::Ok && result.end == text.c_str() + text.size() && value > most)
        found->second = std::to_string(most);
}

void check_answer(const ViewResponse& answer, const std::string& query, const char* endpoint) {
    if (answer.status == 400) {
        const std::string& body = answer.body;
        if (body.empty() || body.back() != '\n' || body.find('\n') != body.size() - 1)
            finding("a 400 that is not one line", query, std::string(endpoint) + ": " + body);
        return;
    }
    if (answer.status != 200) finding("an answer other than 200 or 400", query, std::string(endpoint) + ": " + answer.body);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > 4096) return 0;
    std::string query(reinterpret_cast<const char*>(data), size);
    const bool orthographic = !query.empty() && query[0] == '~';
    if (orthographic) query.erase(0, 1);
    ViewSession& view = the_session(orthographic);
    QueryParameters parameters;
    std::string error;
    if (!parse_query("/image?" + query, parameters, error)) {
        if (error.empty()) finding("a query refused without a reason", query, "");
        return 0;
    }
    lower(parameters, "spp", 4);
    lower(parameters, "ao_samples", 8);
    lower(parameters, "bounces", 4);
    QueryParameters small = parameters;
    lower(small, "width", 12);
    lower(small, "height", 12);
    const ViewResponse image = view.image(small);
    check_answer(image, query, "/image");
    if (image.status == 200) {
        const std::string& body = image.body;
        const bool png = body.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0, bmp = body.compare(0, 2, "BM") == 0;
        if (!(png || bmp) || image.content_type != (png ? "image/png" : "image/bmp"))
            finding("a 200 image that is neither PNG nor BMP", query, image.content_type);
    }
    // The same query as /explain, for the pixel it names or, when it names none, the first one.
    QueryParameters explained = parameters;
    if (!explained.count("x") && !explained.count("y")) explained.insert({{"x", "0"}, {"y", "0"}});
    const ViewResponse explanation = view.explain(explained);
    check_answer(explanation, query, "/explain");
    if (explanation.status == 200 && (explanation.body.empty() || explanation.body[0] != '{'))
        finding("a 200 explanation that is not a JSON object", query, explanation.body.substr(0, 200));
    const ViewResponse status = view.status();
    if (status.status != 200 || status.body.empty() || status.body[0] != '{') finding("a bad /status", query, status.body);
    return 0;
}
