// Random scene files that use the whole grammar (every camera, light, material field, object kind
// and transform item, nested groups and transforms, meshes in every OBJ index form), and random
// render settings, for the differential test (tests/differential_render_test.cpp) and the
// end-to-end fuzz target (fuzz/fuzz_render_pipeline.cpp). The choices come from a seed or from
// the fuzzer's bytes, so the same generator serves both. Scenes are valid: what raycast refuses
// in them is refused by design (numbers at the edges of the float range, when asked for).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "render/render_options.h"
#include "scene/build_scene.h"

namespace raycast::test {

/// Where the generator's choices come from: a seed (a splitmix64 stream), or bytes read in order,
/// with zeros after the last, so that a fuzzer's mutations of a byte change one choice.
class Choices {
public:
    explicit Choices(uint64_t seed) : state_(seed) {}
    Choices(const uint8_t* data, size_t size) : data_(data), size_(size), from_bytes_(true) {}

    /// A whole number in [0, n), n >= 1.
    uint32_t below(uint32_t n);
    /// True about once in n times.
    bool one_in(uint32_t n) { return below(n) == 0; }
    /// One of 257 evenly spaced values from lo to hi: never closer to 0 than a step, unless 0.
    float between(float lo, float hi);
    /// An element of a non-empty list.
    template <typename T>
    const T& pick(const std::vector<T>& list) {
        return list[below(static_cast<uint32_t>(list.size()))];
    }

private:
    uint32_t next_bits(int bytes);

    const uint8_t* data_ = nullptr;
    size_t size_ = 0;
    size_t position_ = 0;
    bool from_bytes_ = false;
    uint64_t state_ = 0;
};

/// How large and how wild a scene may be.
struct SceneLimits {
    int max_objects = 8;        ///< primitives in the whole scene, at least 1
    int max_depth = 3;          ///< groups and transforms nested inside the top Group
    int max_mesh_vertices = 12; ///< per OBJ file
    int max_deep_nesting = 0;   ///< now and then, an object wrapped in up to this many more levels
    bool extreme_numbers = false;  ///< now and then, numbers at the edges of the float range
    /// Half the OBJ files closed meshes (every edge used once each way: a UV sphere of a few rings
    /// and segments, its vertices moved along their radii or anywhere in the mesh's box, so that
    /// it may pass through itself, wound either way), for the tests of skipping back faces
    /// (scene/back_faces.h). Off, no choice is spent on it: the fuzzer's inputs keep their scenes.
    bool closed_meshes = false;
};

struct RandomScene {
    std::string text;                           ///< the scene file
    std::map<std::string, std::string> meshes;  ///< OBJ files by the path the scene names them with
    /// Every number is 0 or between 1e-3 and 1e3 in magnitude, and every matrix well conditioned:
    /// nothing a render of it computes should overflow, so every pixel must be finite.
    bool moderate = true;
};

RandomScene random_scene(Choices& choices, const SceneLimits& limits);

/// Settings for building and rendering a random scene.
struct RandomRender {
    SceneBuildOptions build;  ///< size, conventions (course or MIT, field-of-view axis, back faces, specular)
    RenderOptions render;     ///< mode, samples, shadows, bounces, weight; one thread, no crop
    float lens_radius = 0;    ///< when positive: a thin lens focused at focus_distance (set on the camera)
    float focus_distance = 1;
};

/// Picks settings for an image of width x height, with a mode among `modes`. The packet ISA is
/// left at the best one this CPU runs.
RandomRender random_render(Choices& choices, int width, int height, const std::vector<RenderMode>& modes);

/// Applies the lens of `settings` to a built scene's camera.
void apply_lens(const RandomRender& settings, Scene& scene);

}  // namespace raycast::test
