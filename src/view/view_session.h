// The live viewer's state, apart from HTTP: the scene file (reloaded when it or a mesh it names
// changes on disk, the last good scene kept when the new one has errors), and what the three
// endpoints answer: /image (a render as PNG or BMP), /explain (a pixel's ray tree as JSON) and
// /status (JSON: the version, the errors, the camera, the lights and the defaults). Query strings
// choose the render options and move the camera and the lights; every value is checked, and a bad
// one is a 400 that says why. view_server.cpp puts this behind cpp-httplib; tests drive it directly.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "base/file_version.h"
#include "render/render_options.h"
#include "scene/conventions.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"
#include "sceneio/load_scene.h"

namespace raycast {

/// What `raycast view` was started with: the scene and the render options every request starts
/// from (so that /image with no query is the image `raycast SCENE OUT [same options]` writes).
struct ViewSettings {
    std::string scene_path;
    SceneLoadOptions load;
    bool mit_conventions = false;  ///< the base conventions: MIT 6.837's, or the course's
    Conventions conventions;       ///< as the command line made them (fov, shade_back, specular_fix)
    int width = 0, height = 0;     ///< --size; 0: the camera's own (or 400 when it has none)
    RenderOptions render;
    float aperture = 0;            ///< thin lens, as the command line's --aperture
    float focus_distance = 0;      ///< 0: focus on what the image centre sees
};

/// An HTTP answer without the HTTP.
struct ViewResponse {
    int status = 200;
    std::string content_type;
    std::string body;
};

using QueryParameters = std::multimap<std::string, std::string>;

/// The parameters of a request target's query ("/image?spp=4&mode=ao"), read strictly: parts
/// separated by '&' alone, each NAME=VALUE with one '=' and a name, '%' followed by two hex
/// digits, '+' a space. False, with `error` saying why, otherwise: the HTTP library's own reader
/// dropped a repeated parameter given twice alike, read "spp=1=2" as 2, took ';' as a separator
/// and "%u0038" as "8", so that requests the viewer documents as refused were answered.
bool parse_query(const std::string& target, QueryParameters& parameters, std::string& error);

class ViewSession {
public:
    explicit ViewSession(ViewSettings settings);

    /// Loads the scene when a file it was read from has changed since the last load (or when it
    /// has never been loaded). Returns whether it loaded one: a new version, good or bad.
    /// `changed_during_load`, when given, is asked after the files were read and before the load
    /// is shown, with whether a file's time or size is no longer what it was before the read: if
    /// it says a file changed meanwhile (a save begun: the load may have read it empty or half
    /// written), the load is dropped, nothing changes and false is returned; the next call loads
    /// again. `change_heard`, when given, is asked when a file has changed since a load: if it
    /// says no (the change may be a save caught before its writer's first event), nothing is
    /// loaded yet and false is returned. Thread-safe.
    bool reload_if_changed(const std::function<bool(bool files_changed)>& changed_during_load = nullptr,
                           const std::function<bool()>& change_heard = nullptr);

    /// GET /status.
    ViewResponse status() const;
    /// GET /image: the render for the query, PNG when this build has libpng, else BMP. A request
    /// made while an older one renders cancels the older one (409).
    ViewResponse image(const QueryParameters& query);
    /// GET /explain?x=&y=: the JSON of `raycast explain` for that pixel and query.
    ViewResponse explain(const QueryParameters& query);

    /// Grows by one with every load, good or bad.
    uint64_t version() const;
    /// The latest load's errors (if it failed) and warnings, for printing.
    std::vector<Diagnostic> diagnostics() const;
    /// The files whose changes reload the scene: the scene file and the meshes it named.
    std::vector<std::string> watched_files() const;

private:
    struct FileStamp {
        std::string path;
        FileVersion version;
        bool operator==(const FileStamp& other) const { return path == other.path && version == other.version; }
    };
    // One load: the description (shared by the scenes built from it), its scenes per
    // conventions, and what it said.
    struct Loaded {
        std::shared_ptr<const SceneDesc> desc;  // the last description that loaded without errors
        std::vector<Diagnostic> errors;         // of the latest attempt; empty when it loaded
        std::vector<Diagnostic> warnings;
        uint64_t version = 0;
    };
    struct Request;
    struct Prepared;  // a request with its scene and camera, ready to render

    static FileStamp stamp(const std::string& path);
    bool prepare(const QueryParameters& query, bool explaining, Prepared& prepared, ViewResponse& refusal);
    std::vector<FileStamp> stamps_of(const SceneDesc* desc) const;
    bool parse_request(const QueryParameters& query, bool explaining, Request& request, std::string& error) const;
    std::shared_ptr<const Scene> scene_for(const std::shared_ptr<const SceneDesc>& desc, const Conventions& conventions,
                                           std::string& error);

    ViewSettings settings_;
    mutable std::mutex mutex_;  // guards loaded_, stamps_ and scenes_
    Loaded loaded_;
    std::vector<FileStamp> stamps_;
    std::map<std::string, std::shared_ptr<const Scene>> scenes_;  // built from loaded_.desc, per conventions
    std::mutex build_mutex_;  // one scene build at a time
    std::atomic<uint64_t> image_tickets_{0};  ///< one per /image request, in order of arrival
    std::atomic<uint64_t> latest_image_{0};   ///< the newest valid request's ticket: it renders
};

/// The viewer's HTML page: one self-contained file (no external scripts, styles or fonts).
const std::string& view_page_html();

}  // namespace raycast
