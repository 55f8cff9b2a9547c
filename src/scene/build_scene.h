// From the file's description to the render-ready scene: groups and transforms are flattened
// into instances, planes are moved to world space, and BVHs are built.
#pragma once

#include "scene/conventions.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"

namespace raycast {

struct SceneBuildOptions {
    int width = 0, height = 0;  ///< image size; 0 keeps the camera's own
    Conventions conventions;
    int threads = 1;  ///< for BVH construction
};

/// Builds the scene. Throws InputError (located at the offending node) when the description cannot
/// be rendered: no camera or image size, a transform that cannot be inverted.
Scene build_scene(SceneDesc desc, const SceneBuildOptions& options);

/// Builds a mesh's wide BVH and its triangle groups, then drops its positions and index list
/// (exposed for tests and benchmarks).
MeshShape build_mesh_shape(TriangleMesh mesh, int threads);

}  // namespace raycast
