// Wavefront OBJ meshes: v, vn and f (every index form, negative indices, polygons as fans, concave
// ones cut again once every vertex is known: geometry/polygon.h), parsed in
// parallel chunks with located diagnostics. Entry points: load_obj_file, parse_obj.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "base/error.h"
#include "base/file_version.h"
#include "geometry/triangle_mesh.h"

namespace raycast {

/// How to parse; the mesh and every message are the same whatever these say.
struct ObjLoadOptions {
    int threads = 1;         ///< threads that parse chunks of the text at once; values below 1 mean 1
    size_t chunk_bytes = 0;  ///< 0: chosen from the size and threads; tests set it small to exercise chunk seams
    /// When set, receives a warning, located, for each of the first 20 statements that OBJ does not
    /// define (a typo such as 'f1'), which are skipped, and a note counting the rest.
    std::vector<Diagnostic>* warnings = nullptr;
    /// When set, receives the file's version as load_obj_file opened it, before reading it.
    FileVersion* opened = nullptr;
};

/// Reads and parses an OBJ file. Throws InputError: "cannot open OBJ file: ..." located at the file
/// only, or up to 20 diagnostics located at the offending tokens.
TriangleMesh load_obj_file(const std::string& path, const ObjLoadOptions& options = {});

/// Parses OBJ text held in memory; file_name only labels the diagnostics. Same rules as load_obj_file.
TriangleMesh parse_obj(std::string_view text, const std::string& file_name, const ObjLoadOptions& options = {});

}  // namespace raycast
