#include "reference_render.h"

#include <algorithm>
#include <cmath>

#include "bvh/bvh.h"
#include "geometry/rev_surface.h"
#include "geometry/triangle.h"
#include "geometry/triangle_groups.h"
#include "render/integrator.h"
#include "render/sampler.h"

namespace raycast::test {

ReferenceScene::ReferenceScene(const Scene& scene) : scene_(scene) {
    // A built mesh keeps its triangles only in its groups (its positions and index list are
    // dropped), so the reference reads them there: every group, in storage order, never through
    // the BVH. That a group holds exactly the mesh's triangles with an area, with their own
    // corners, is fuzz_obj_loader's and the triangle-group tests' to check; what this checks is
    // that the wide BVH and every kernel find the nearest of them.
    for (const MeshShape& shape : scene.meshes) {
        std::vector<MeshTriangle> triangles;
        const size_t end = shape.groups.size() - std::min<size_t>(shape.groups.size(), kGroupPaddingBlocks);
        for (const GroupBlock* group = shape.groups.data(); group < shape.groups.data() + end; group = next_group(group)) {
            const uint32_t leaf = static_cast<uint32_t>(group - shape.groups.data());
            for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) {
                const GroupTriangle tri = group_triangle(group, lane);
                triangles.push_back({tri.p0, tri.p1, tri.p2, tri.id, leaf, lane});
            }
        }
        // The mesh's own order, as brute force over the file would test them.
        std::sort(triangles.begin(), triangles.end(),
                  [](const MeshTriangle& a, const MeshTriangle& b) { return a.id < b.id; });
        triangles_.push_back(std::move(triangles));
    }
    // The boxes of the instance BVH's leaves, read from its nodes: these decide nothing here but
    // which hits are uncertain (hit_is_uncertain). With one leaf, intersect() tests no box.
    floor_boxes_.resize(scene.instances.size());
    const Bvh& bvh = scene.instance_bvh;
    if (bvh.nodes.size() > 1)
        for (const BvhNode& node : bvh.nodes)
            for (uint32_t i = node.first; node.is_leaf() && i < node.first + node.count; ++i)
                if (scene.instances[bvh.prim_order[i]].kind != ShapeKind::Mesh) floor_boxes_[bvh.prim_order[i]] = node.bounds;
}

namespace {

// Whether a hit at t, found by brute force, may be one that intersect() finds elsewhere by
// design: every path moves a hit reported before the box of the BVH leaf that holds it up to
// that leaf's floor (leaf_floor, bvh.h; docs/reliability.md, finding 11), which brute force,
// knowing no leaves, cannot do. `box` holds the primitive and lies inside that leaf's box (the
// leaf's own box, or a mesh triangle's box, which its mesh's leaf holds), so the ray enters the
// leaf no later than `box`. The hit is uncertain when the ray misses `box` or the hit lies before
// the entry by more than half the floor's margin (a quarter of the cull slack): the other half
// covers the different roundings of the kernels' box tests. A true hit lies in `box`: its
// computed t is that far before it only through rounding (a triangle 2000 wide seen from just
// above its plane; AFloorSeenFromJustAboveHasNoHoles).
bool hit_is_uncertain(const Bounds3f& box, const Ray& ray, float t_min, float t) {
    float entry;
    if (!intersect_box(box, make_box_ray(ray, t_min), INFINITY, entry)) return true;
    return t < entry - std::fabs(entry) * (1.0f / 4096);
}

Bounds3f triangle_box(Vec3f p0, Vec3f p1, Vec3f p2) {
    Bounds3f box;
    box.grow(p0);
    box.grow(p1);
    box.grow(p2);
    return box;
}

}  // namespace

// Calls visit(t, u, v, object, prim, leaf, lane, uncertain) for the nearest hit (t > t_min) of
// every primitive; `uncertain` is hit_is_uncertain's answer for it.
// Triangles with no area are skipped: the scene's rule is that they are never hit
// (geometry/triangle.h, is_degenerate_triangle).
template <typename Visit>
void ReferenceScene::for_each_hit(const Ray& world_ray, float t_min, Visit&& visit) const {
    for (uint32_t id = 0; id < scene_.instances.size(); ++id) {
        const Instance& instance = scene_.instances[id];
        const Ray ray = instance.transform == kNoTransform
                            ? world_ray
                            : to_object_space(scene_.object_from_world[instance.transform], world_ray);
        float t = 0;
        TriangleHit hit;
        // Instance BVH leaves are in world space (their t is the same along the object-space ray).
        const Bounds3f& floor_box = floor_boxes_[id];
        auto uncertain = [&](float hit_t) {
            return !floor_box.is_empty() && hit_is_uncertain(floor_box, world_ray, t_min, hit_t);
        };
        switch (instance.kind) {
            case ShapeKind::Sphere:
                if (intersect_sphere(scene_.spheres[instance.shape], ray, t_min, t))
                    visit(t, 0.0f, 0.0f, id, 0u, 0u, 0u, uncertain(t));
                break;
            case ShapeKind::Plane:
                if (intersect_plane(scene_.planes[instance.shape], ray, t_min, t)) visit(t, 0.0f, 0.0f, id, 0u, 0u, 0u, false);
                break;
            case ShapeKind::Triangle: {
                const TriangleShape& tri = scene_.triangles[instance.shape];
                if (is_degenerate_triangle(tri.p0, tri.p1, tri.p2)) break;
                if (intersect_triangle(make_watertight_ray(ray), tri.p0, tri.p1, tri.p2, t_min, hit))
                    visit(hit.t, hit.u, hit.v, id, 0u, 0u, 0u, uncertain(hit.t));
                break;
            }
            case ShapeKind::RevSurface: {
                // The surface's own exact test, over the whole ray (no BVH above it to cull).
                RevSurfaceHit rev;
                if (intersect_rev_surface(scene_.rev_surfaces[instance.shape], ray, t_min, INFINITY, false, rev))
                    visit(rev.t, rev.u, 0.0f, id, rev.piece, 0u, 0u, uncertain(rev.t));
                break;
            }
            case ShapeKind::Mesh: {
                // A mesh's leaves are in its object space.
                const WatertightRay watertight = make_watertight_ray(ray);
                for (const MeshTriangle& tri : triangles_[instance.shape]) {
                    if (!is_degenerate_triangle(tri.p0, tri.p1, tri.p2) &&
                        intersect_triangle(watertight, tri.p0, tri.p1, tri.p2, t_min, hit))
                        visit(hit.t, hit.u, hit.v, id, tri.id, tri.leaf, tri.lane,
                              hit_is_uncertain(triangle_box(tri.p0, tri.p1, tri.p2), ray, t_min, hit.t));
                }
                break;
            }
        }
    }
}

Hit ReferenceScene::intersect(const Ray& ray, float t_min, bool* uncertain) const {
    // Only the closest hit's doubt matters: moving any other hit up leaves it farther still.
    Hit best;
    bool best_uncertain = false;
    for_each_hit(ray, t_min, [&](float t, float u, float v, uint32_t object, uint32_t prim, uint32_t leaf,
                                 uint32_t lane, bool hit_uncertain) {
        if (!is_closer(t, object, prim, best)) return;
        best = Hit{t, u, v, object, prim, leaf, lane};
        best_uncertain = hit_uncertain;
    });
    if (uncertain) *uncertain = best_uncertain;
    return best;
}

bool ReferenceScene::occluded(const Ray& ray, float t_min, float t_max) const {
    bool blocked = false;
    for_each_hit(ray, t_min,
                 [&](float t, float, float, uint32_t, uint32_t, uint32_t, uint32_t, bool) { blocked |= t < t_max; });
    return blocked;
}

namespace {

// Written out from the render loop's definition (docs/architecture.md, render/sampler.h): the
// pixel's own point, or for several samples or a lens, the stratified offset and lens point.
Ray reference_camera_ray(const Camera& camera, int x, int y, int s, int spp) {
    const float px = static_cast<float>(x) + camera.pixel_offset;
    const float py = static_cast<float>(y) + camera.pixel_offset;
    if (spp == 1 && camera.lens_radius <= 0) return camera_ray(camera, px, py);
    const uint32_t index = static_cast<uint32_t>(y) * static_cast<uint32_t>(camera.width) + static_cast<uint32_t>(x);
    const Vec2f offset = pixel_sample_offset(index, s, spp);
    const Vec2f lens = lens_sample(index, s);
    return camera_ray(camera, px + (offset.x - 0.5f), py + (offset.y - 0.5f), lens.x, lens.y);
}

}  // namespace

Image reference_render(const ReferenceScene& reference, const RenderOptions& options, std::vector<uint8_t>* uncertain) {
    const Scene& scene = reference.scene();
    const Camera& camera = scene.camera;
    const Integrator integrator = make_integrator(scene, options);
    const int spp = std::max(1, options.samples_per_pixel);
    Image image(camera.width, camera.height);
    std::vector<float> depths(static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height), INFINITY);
    std::vector<uint8_t> doubts(depths.size(), 0);
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            const uint32_t index = static_cast<uint32_t>(y) * static_cast<uint32_t>(camera.width) + static_cast<uint32_t>(x);
            Vec3f sum;
            for (int s = 0; s < spp; ++s) {
                const Ray ray = reference_camera_ray(camera, x, y, s, spp);
                bool hit_uncertain = false;
                const Hit hit = reference.intersect(ray, camera.t_min, &hit_uncertain);
                if (hit.is_hit()) depths[index] = hit.t;
                doubts[index] |= hit_uncertain ? 1 : 0;
                // A fresh context per sample: depth 0, weight 1, vacuum, the sample's random numbers.
                Sampler sampler(index, s);
                uint32_t budget = kMaxRaysPerSample;
                RayCounts counts;
                TraceContext context;
                context.sampler = &sampler;
                context.counts = &counts;
                context.rays_left = &budget;
                const Vec3f color = integrator.radiance(integrator, ray, hit, context);
                sum = s == 0 ? color : sum + color;
            }
            image.at(x, y) = spp > 1 ? sum / static_cast<float>(spp) : sum;
        }
    if (options.mode == RenderMode::Depth) {
        // Grey = clamp((far − t)/(far − near)), near white; the range is the options' or that of the hits.
        float near = options.depth_near, far = options.depth_far;
        if (near == 0 && far == 0) {
            // A hit moved elsewhere may move the range, and so every pixel.
            if (std::find(doubts.begin(), doubts.end(), 1) != doubts.end()) std::fill(doubts.begin(), doubts.end(), 1);
            near = INFINITY;
            far = -INFINITY;
            for (float t : depths)
                if (std::isfinite(t)) near = std::min(near, t), far = std::max(far, t);
        }
        for (size_t i = 0; i < depths.size(); ++i) {
            if (!std::isfinite(depths[i])) continue;
            const float grey = far > near ? std::clamp((far - depths[i]) / (far - near), 0.0f, 1.0f) : 1.0f;
            image.pixels[i] = {grey, grey, grey};
        }
    }
    if (uncertain) *uncertain = std::move(doubts);
    return image;
}

}  // namespace raycast::test
