// The scene-file parser: text in, SceneDesc out, every problem reported as a located diagnostic.
// It accepts the course's grammar (docs/scene-format.md) and MIT 6.837's (assignments 1-4), with
// fields of a block in any order and `#` comments. It never prints and never exits.
#pragma once

#include <string>
#include <string_view>

#include "scene/scene_desc.h"

namespace raycast {

/// Parses scene text. TriangleMesh objects keep the path as written (mesh == -1): load_scene.h
/// loads the files. Throws InputError with every error found (at most kMaxReportedErrors) and
/// the warnings among them; on success the warnings are in SceneDesc::warnings.
SceneDesc parse_scene(std::string_view text, const std::string& file_name);

}  // namespace raycast
