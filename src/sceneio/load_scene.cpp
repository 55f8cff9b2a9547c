#include "sceneio/load_scene.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include "base/limits.h"
#include "sceneio/load_obj.h"
#include "sceneio/parse_scene.h"

namespace raycast {

namespace {

bool is_regular_file(const std::string& path) {
    struct stat info;
    return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

std::string folder_of(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace

std::vector<MeshCandidate> mesh_candidates(const std::string& mesh_path, const std::string& scene_file) {
    std::vector<MeshCandidate> tried{{mesh_path, "from the working directory"}};
    if (mesh_path.empty() || mesh_path[0] == '/') return tried;
    const std::string folder = folder_of(scene_file);
    if (folder.empty()) {
        tried.push_back({"../" + mesh_path, "from the scene file's parent folder"});
    } else {
        tried.push_back({folder + mesh_path, "next to the scene file"});
        tried.push_back({folder + "../" + mesh_path, "from the scene file's parent folder"});
    }
    return tried;
}

std::string find_mesh_file(const std::string& mesh_path, const std::string& scene_file) {
    for (const MeshCandidate& candidate : mesh_candidates(mesh_path, scene_file))
        if (is_regular_file(candidate.path)) return candidate.path;
    return {};
}

namespace {

class MeshLoader {
public:
    MeshLoader(SceneDesc& desc, const SceneLoadOptions& options) : desc_(desc), options_(options) {}

    void load_all(ObjectDesc& object) {
        if (object.kind == ObjectDesc::Kind::TriangleMesh) load(object);
        for (ObjectDesc& child : object.children) load_all(child);
    }

    std::vector<Diagnostic>& errors() { return errors_; }
    std::vector<Diagnostic>& warnings() { return warnings_; }

private:
    void load(ObjectDesc& object) {
        const std::vector<MeshCandidate> tried = mesh_candidates(object.mesh_path, desc_.file);
        const std::string* found = nullptr;
        const std::string* in_memory = nullptr;
        if (options_.in_memory_meshes) {
            const auto text = options_.in_memory_meshes->find(object.mesh_path);
            if (text != options_.in_memory_meshes->end()) {
                found = &object.mesh_path;
                in_memory = &text->second;
            }
        }
        for (size_t i = 0; i < tried.size() && !in_memory && !found; ++i)
            if (is_regular_file(tried[i].path)) found = &tried[i].path;
        if (!found) {
            std::string message = "cannot open OBJ file " + quote(object.mesh_path) + ": tried ";
            for (size_t i = 0; i < tried.size(); ++i) {
                if (i > 0) message += i + 1 == tried.size() ? " and " : ", ";
                message += quote(tried[i].path) + " (" + tried[i].how + ")";
            }
            if (options_.allow_missing_meshes) {
                warnings_.push_back({Severity::Warning, object.mesh_path_location, message, ""});
                warnings_.push_back({Severity::Note, line_only(object.mesh_path_location),
                                     "the scene is rendered without this mesh (--allow-missing-meshes)", ""});
            } else {
                errors_.push_back({Severity::Error, object.mesh_path_location, message, ""});
                errors_.push_back({Severity::Note, line_only(object.mesh_path_location),
                                   "--allow-missing-meshes renders the rest of the scene without it", ""});
            }
            return;
        }
        auto known = index_of_path_.find(*found);
        if (known != index_of_path_.end()) {
            object.mesh = known->second;
            return;
        }
        // A file that failed is reported once, where it was first named; each later naming gets a
        // note, not the same errors again.
        if (failed_paths_.count(*found)) {
            errors_.push_back({Severity::Note, object.mesh_path_location, "the same mesh is named here too", ""});
            return;
        }
        try {
            ObjLoadOptions obj_options;
            obj_options.threads = options_.threads;
            std::vector<Diagnostic> obj_warnings;
            obj_options.warnings = &obj_warnings;
            FileVersion version;
            obj_options.opened = &version;
            MeshDesc mesh{*found, in_memory ? parse_obj(*in_memory, *found, obj_options)
                                            : load_obj_file(*found, obj_options), version};
            for (Diagnostic& warning : obj_warnings) warnings_.push_back(std::move(warning));
            // Located at the first TriangleMesh that names the file; the others share its mesh.
            if (mesh.mesh.triangle_count() == 0)
                warnings_.push_back({Severity::Warning, object.location,
                                     "the OBJ file " + quote(*found) + " has no faces ('f' lines): this mesh draws nothing",
                                     ""});
            object.mesh = static_cast<int>(desc_.meshes.size());
            index_of_path_[*found] = object.mesh;
            desc_.meshes.push_back(std::move(mesh));
        } catch (const InputError& error) {
            for (const Diagnostic& d : error.diagnostics()) errors_.push_back(d);
            errors_.push_back({Severity::Note, object.mesh_path_location, "the mesh was named here", ""});
            failed_paths_.insert(*found);
        }
    }

    static std::string quote(const std::string& s) { return "'" + s + "'"; }
    // A note about the line just shown: located, without repeating the line and its caret.
    static SourceLocation line_only(SourceLocation at) {
        at.column = 0;
        return at;
    }

    SceneDesc& desc_;
    const SceneLoadOptions& options_;
    std::map<std::string, int> index_of_path_;
    std::set<std::string> failed_paths_;
    std::vector<Diagnostic> errors_;
    std::vector<Diagnostic> warnings_;
};

}  // namespace

std::string read_text_file(const std::string& path, const char* what, int64_t max_bytes) {
    struct stat info;
    if (::stat(path.c_str(), &info) != 0) throw InputError(path, std::string("cannot open ") + what + ": " + std::strerror(errno));
    if (S_ISDIR(info.st_mode)) throw InputError(path, std::string("cannot open ") + what + ": it is a directory");
    if (int64_t(info.st_size) > max_bytes)
        throw InputError(path, string_printf("cannot open %s: it is %lld bytes, more than the limit of %lld", what,
                                             (long long)info.st_size, (long long)max_bytes));
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) throw InputError(path, std::string("cannot open ") + what + ": " + std::strerror(errno));
    std::string text;
    char buffer[65536];
    size_t got;
    while ((got = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
        text.append(buffer, got);
        if (int64_t(text.size()) > max_bytes) break;
    }
    const bool failed = std::ferror(file) != 0;
    std::fclose(file);
    if (failed) throw InputError(path, std::string("cannot read ") + what);
    if (int64_t(text.size()) > max_bytes)
        throw InputError(path, string_printf("cannot open %s: it is more than the limit of %lld bytes", what,
                                             (long long)max_bytes));
    return text;
}

SceneDesc load_scene_text(const std::string& text, const std::string& file_name, const SceneLoadOptions& options) {
    SceneDesc desc = parse_scene(text, file_name);
    if (desc.root) {
        MeshLoader loader(desc, options);
        loader.load_all(*desc.root);
        if (!loader.errors().empty()) {
            std::vector<Diagnostic> all = std::move(loader.errors());
            attach_source_lines(all, desc.source_text, file_name);
            throw InputError(std::move(all));
        }
        attach_source_lines(loader.warnings(), desc.source_text, file_name);
        for (Diagnostic& warning : loader.warnings()) desc.warnings.push_back(std::move(warning));
    }
    return desc;
}

SceneDesc load_scene_file(const std::string& path, const SceneLoadOptions& options) {
    return load_scene_text(read_text_file(path, "scene file", kMaxSceneFileBytes), path, options);
}

}  // namespace raycast
