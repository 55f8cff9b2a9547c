// The command line: the course's form `raycast SCENE OUTPUT [options]`, MIT 6.837's form
// `raycast -input SCENE -size W H -output FILE ...`, `explain` (the ray tree of one pixel), and
// the tools `compare` and `merge`.
// Arguments are read into a CliOptions and then checked as a whole.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/compare_images.h"
#include "image/image_io.h"
#include "render/render.h"
#include "scene/conventions.h"

namespace raycast {

/// A mistake on the command line: the program prints it with a hint and exits with status 2.
class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct CliOptions {
    enum class Command { Render, Explain, View, Compare, Merge, Help, Version };
    Command command = Command::Render;

    // render
    std::string scene_path;
    std::string output_path;   ///< the shaded image; may be empty in MIT form when only -depth/-normals are asked
    std::string depth_path;    ///< extra depth image (-depth NEAR FAR FILE, or --depth FILE)
    std::string normals_path;  ///< extra normals image (-normals FILE, or --normals FILE)
    /// --format: output_path's format whatever its name says; nullopt: its extension's. The
    /// course's form only; depth_path and normals_path always follow their names.
    std::optional<ImageFormat> output_format;
    bool mit_form = false;
    int width = 0, height = 0;  ///< 0: the camera's own size
    int threads = 0;            ///< 0: every hardware thread
    bool stats = false;
    bool quiet = false;
    Conventions conventions;
    bool mit_conventions = false;  ///< the conventions are MIT 6.837's (else the course's)
    bool fov_given = false;     ///< --fov was given (else the conventions' own reading, noted when it stretches)
    bool allow_missing_meshes = false;  ///< a mesh file that cannot be found is a warning, not an error
    RenderOptions render;       ///< mode, samples, shadows, crop, depth range, packets, tile size
    float aperture = 0;         ///< thin-lens diameter in world units; 0 is a pinhole
    float focus_distance = 0;   ///< 0: the distance to the point the camera looks at… (see --help)
    bool has_focus_distance = false;

    // explain
    int explain_x = 0, explain_y = 0;  ///< the pixel, row 0 at the top

    // view
    int view_port = 0;                  ///< 0: any free port
    std::string view_host = "127.0.0.1";

    // compare
    std::vector<std::string> inputs;  ///< compare: A B; merge: the pieces
    std::string diff_path;
    bool grade = false;        ///< --max-diff or --max-fraction given: exit 1 beyond the tolerance
    ImageTolerance tolerance;  ///< --max-diff L (default 0) and --max-fraction F (default 0)
    std::string mask_path;     ///< --mask: pixels black in it are ignored

    // merge
    std::string merge_output;

    std::vector<std::string> notes;  ///< things worth telling the user (ignored MIT GUI flags)
};

/// Reads the arguments (argv[0] is the program). Throws UsageError.
CliOptions parse_command_line(int argc, const char* const* argv);

/// The text of --help.
std::string usage_text();

}  // namespace raycast
