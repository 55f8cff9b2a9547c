// Writing a triangle mesh as a Wavefront OBJ file (v, vn, f), the inverse of load_obj for the
// meshes raycast makes itself: tessellated surfaces of revolution, for tests and comparisons.
#pragma once

#include <string>

#include "geometry/triangle_mesh.h"

namespace raycast {

/// The mesh as OBJ text: `v` lines, `vn` lines if it has normals, and one `f` per triangle
/// (`f a//n b//n c//n` with normals). Floats are written with 9 significant digits, so that
/// load_obj reads back exactly the same numbers.
std::string obj_text(const TriangleMesh& mesh);

/// Writes obj_text(mesh) to `path`. Throws InputError(path, "cannot write OBJ file: ...").
void write_obj_file(const std::string& path, const TriangleMesh& mesh);

}  // namespace raycast
