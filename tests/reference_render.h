// A brute-force reference for the renderer, for differential tests: no BVH and no packets, one
// ray at a time, every primitive of every instance tested, the closest hit kept by is_closer()
// (geometry/hit.h). Rays are moved to object space and tested with the primitives' own
// functions, as the scene does, so the hits must be identical, bit for bit, to those of
// intersect() and of every packet kernel. Shading uses the renderer's own radiance functions
// (render/integrator.h): what this checks is which surface each camera ray finds.
#pragma once

#include <cstdint>
#include <vector>

#include "image/image.h"
#include "render/render_options.h"
#include "scene/scene.h"

namespace raycast::test {

/// A scene prepared for brute force: each mesh's triangles in the mesh's own order, with the group
/// that holds each one (Hit::leaf, where surface_at finds it).
class ReferenceScene {
public:
    explicit ReferenceScene(const Scene& scene);

    const Scene& scene() const { return scene_; }
    /// The closest hit with t > t_min, testing everything.
    Hit intersect(const Ray& ray, float t_min) const;
    /// Whether some primitive is hit with t_min < t < t_max.
    bool occluded(const Ray& ray, float t_min, float t_max) const;

private:
    template <typename Visit>
    void for_each_hit(const Ray& ray, float t_min, Visit&& visit) const;

    struct MeshTriangle {
        Vec3f p0, p1, p2;
        uint32_t id = 0;    ///< the triangle's index in its mesh
        uint32_t leaf = 0;  ///< the first block of its group
        uint32_t lane = 0;  ///< its place in the group
    };

    const Scene& scene_;
    std::vector<std::vector<MeshTriangle>> triangles_;  ///< per mesh, by id
};

/// The image render_image(scene, options) makes (without a crop; Cost mode is not supported: it
/// counts BVH nodes), with every camera ray's hit found by brute force.
Image reference_render(const ReferenceScene& reference, const RenderOptions& options);

}  // namespace raycast::test
