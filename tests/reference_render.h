// A brute-force reference for the renderer, for differential tests: no BVH and no packets, one
// ray at a time, every primitive of every instance tested, the closest hit kept by is_closer()
// (geometry/hit.h). Rays are moved to object space and tested with the primitives' own
// functions, as the scene does, so the hits must be identical, bit for bit, to those of
// intersect() and of every packet kernel, but for one difference by design, which the reference
// marks: a hit that rounding puts before the box of its BVH leaf, which the BVH moves up to that
// leaf's floor (bvh.h's leaf_floor). Shading uses the renderer's own radiance functions
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
    /// The closest hit with t > t_min, testing everything. If `uncertain` is given, it is set to
    /// whether that hit may differ from intersect()'s by design, not by a defect: its t lies before
    /// the box that holds it in the scene's BVH, or nearly (see hit_is_uncertain in the .cpp).
    Hit intersect(const Ray& ray, float t_min, bool* uncertain = nullptr) const;
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
    /// Per instance, the box of the instance BVH's leaf that holds it, where intersect() moves its
    /// hits up to that leaf's floor: spheres, free triangles and surfaces of revolution, when the
    /// BVH has more than one leaf. Empty for the others.
    std::vector<Bounds3f> floor_boxes_;
};

/// The image render_image(scene, options) makes (without a crop; Cost mode is not supported: it
/// counts BVH nodes), with every camera ray's hit found by brute force. If `uncertain` is given,
/// it gets one flag per pixel (rows from the bottom, as Image): whether some camera sample's hit
/// there is uncertain (ReferenceScene::intersect), so that the render may differ there by design;
/// in depth mode with the range taken from the hits, every pixel is, if one is.
Image reference_render(const ReferenceScene& reference, const RenderOptions& options,
                       std::vector<uint8_t>* uncertain = nullptr);

}  // namespace raycast::test
