// Reads a scene file and the OBJ meshes it names: the whole input stage of the pipeline.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "scene/scene_desc.h"

namespace raycast {

struct SceneLoadOptions {
    int threads = 1;  ///< for parsing large OBJ files
    /// A mesh file that is found nowhere becomes a warning (and the object is left out) instead of
    /// an error: the course starter's leniency, for scenes shared without their large meshes.
    bool allow_missing_meshes = false;
    /// For tests and fuzzing: OBJ text by mesh path as the scene writes it. A TriangleMesh whose
    /// path is here is parsed from this text and the file system is not asked.
    const std::map<std::string, std::string>* in_memory_meshes = nullptr;
};

/// Reads and parses the scene file, then loads every OBJ file it names, each once. A relative mesh
/// path is tried as written (from the working directory, the course's rule), then from the scene
/// file's folder, then from that folder's parent. Throws InputError with every problem found;
/// warnings (including meshes left out with allow_missing_meshes) go to SceneDesc::warnings.
SceneDesc load_scene_file(const std::string& path, const SceneLoadOptions& options = {});

/// The same for scene text in memory; `file_name` labels diagnostics and gives the folder for
/// mesh paths.
SceneDesc load_scene_text(const std::string& text, const std::string& file_name, const SceneLoadOptions& options = {});

/// A place a scene's relative mesh path is looked for, and how it was found, for messages.
struct MeshCandidate {
    std::string path;
    const char* how;
};

/// Where load_scene_file looks for the mesh a scene names as `mesh_path`, in order: as written
/// (from the working directory, the course's rule), next to the scene file (MIT 6.837's layout),
/// and in the scene folder's parent (the course's layout, testcases/ beside mesh/, when raycast
/// runs from elsewhere). An absolute path is only itself.
std::vector<MeshCandidate> mesh_candidates(const std::string& mesh_path, const std::string& scene_file);

/// The first of mesh_candidates that is a file; "" when none is.
std::string find_mesh_file(const std::string& mesh_path, const std::string& scene_file);

/// Reads a whole file; throws InputError(path, "cannot open <what>: <reason>") when it cannot,
/// including for a directory or a file larger than max_bytes.
std::string read_text_file(const std::string& path, const char* what, int64_t max_bytes);

}  // namespace raycast
