// Shadow rays that may pass over back faces. A closed mesh divides space into inside and outside
// (its winding number: how many times it wraps a point). A segment between two points outside it
// crosses it as often going in as coming out, and it goes in only through faces that face it
// (normal · direction < 0). So if neither end is inside, the segment meets the mesh if and only if
// it meets a face that faces it: the faces it would leave through need not be tested. Around a lit
// point every face faces the light, away from its shadow ray, so a shadow ray that finds nothing
// in the way, as nearly all do, can skip nearly every leaf it passes near (docs/performance.md).
//
// Three things make it hold for a camera hit's shadow ray and an untransformed closed mesh:
//   - the camera's centre is outside the mesh's box, so outside the mesh: every camera ray starts
//     outside, and reaches its first hit without crossing anything, so it arrives from outside;
//   - the shadow ray leaves the hit's plane on the camera's side (origin_on_camera_side), so it
//     starts where the camera ray arrived from;
//   - the light is a directional one (the ray goes on for ever), or a point light outside the
//     mesh's box by more than how far the ray's end may lie from the light: its start's offset
//     from the hit and rounding (ends_clear_of_boxes). Without that, the end of a ray from a far
//     hit, whose offset is large, could lie inside a mesh turned inside out, where a ray can leave
//     through faces that face away from it.
// One premise is not checked: the second says the shadow ray starts where the camera ray came
// from, but it starts its offset (about 1e-5 of the coordinates) off the hit, and another
// surface nearer than that puts its start inside a mesh. Where objects touch (within
// √(2·radius·offset) of where a ball rests on a floor) testing every face then finds the ray
// blocked by the far side of the mesh it starts in, and skipping lets the light in: it can only
// ever light a pixel more (RenderTest.SkippingBackFacesCanOnlyLetLightInWhereObjectsTouch shows
// 44 of 2,304 pixels in a close-up at floor level; --test-every-face turns skipping off). The
// check that would close it, the short segment from the camera ray's side of the hit to the
// shadow rays' start tested against every face, cost as much as skipping saved. Elsewhere the
// image differs only where float arithmetic decides the answer either way (a ray grazing a
// silhouette edge).
// Entry points: NodeCones, mesh_is_closed, build_normal_cones, back_faces_skippable,
// ends_clear_of_boxes.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "base/large_allocator.h"
#include "bvh/wide_bvh.h"
#include "geometry/triangle_groups.h"
#include "geometry/triangle_mesh.h"
#include "math/vec.h"

namespace raycast {

struct Camera;
struct Light;
struct Scene;

/// The normals of the triangles under each child of a wide BVH node, as a cone: an axis q (a
/// vector of integers, about 127 long) and a reach τ such that every triangle's unit normal n
/// lies within τ/127 of q/127. A ray direction d with q·d > τ·|d| (in float, as the kernels
/// compute it: (qx·dx + qy·dy) + qz·dz and √((dx·dx + dy·dy) + dz·dz)) has n·d > 0 for every one
/// of those triangles: all of them face away from it. τ includes a margin for that arithmetic's
/// rounding (see build_normal_cones). 32 bytes per node, half a cache line.
struct alignas(32) NodeCones {
    int8_t axis[3][kWideBvhWidth];  ///< axis[a][slot]: component a of the child's axis q
    uint8_t reach[kWideBvhWidth];   ///< the child's τ; kNoCone where it cannot tell
};
static_assert(sizeof(NodeCones) == 32, "a node's cones should fill half a cache line");

/// Which rays of an any-hit query may pass over which back faces: the faces of the instances
/// marked in `instances` (back_faces_skippable's answer for the query's light), for the rays marked
/// in `rays` (one flag per ray of a packet; the single-ray occluded() takes the instances alone).
struct BackFaceSkipping {
    const uint8_t* instances = nullptr;  ///< per instance, 1 where it may; null: none may
    const bool* rays = nullptr;          ///< per ray of the packet; read only when `instances` is set
};

/// A reach no direction beats: |q·d| <= |q||d| <= 127·√3·|d| < 255·|d|.
constexpr uint8_t kNoCone = 255;

/// Whether the children's triangles all face away from `direction`, computed exactly as the
/// kernels compute it (they repeat it in their own instruction sets). `length` is
/// √((dx·dx + dy·dy) + dz·dz); a length that is not between 1e-15 and 1e15 never skips, so that
/// neither the squares nor the products underflow or overflow.
inline bool faces_away(const NodeCones& cones, uint32_t slot, Vec3f direction, float length) {
    if (!(length >= 1e-15f && length <= 1e15f)) return false;
    const float dot = static_cast<float>(cones.axis[0][slot]) * direction.x +
                      static_cast<float>(cones.axis[1][slot]) * direction.y +
                      static_cast<float>(cones.axis[2][slot]) * direction.z;
    return dot > static_cast<float>(cones.reach[slot]) * length;
}

/// Whether every edge of the mesh is used as often from one end to the other as back (edges as
/// pairs of vertex indices): then it has no boundary, and every point off it has a winding number.
/// Compared by a 64-bit hash of each directed edge, summed both ways, so a mesh with a boundary
/// passes only if those sums collide (about one chance in 2^64). Runs on `threads` threads.
bool mesh_is_closed(const TriangleMesh& mesh, int threads);

/// The cones of every node of a mesh's wide BVH (node i's children: element i), from the triangles
/// in its groups (the leaves' payloads are their first blocks). A child that holds a triangle with
/// no clear normal (a sliver) gets kNoCone, and so do its ancestors. Runs on `threads` threads.
LargeVector<NodeCones> build_normal_cones(const WideBvh& bvh, const GroupBlock* groups, int threads);

/// What the shadow rays of camera hits towards one light may skip (those that leave their hit on
/// the camera's side and end clear of the boxes: ends_clear_of_boxes).
struct SkippableBackFaces {
    /// For each instance of the scene, 1 where they may skip its back faces: an untransformed mesh
    /// that has cones (it is closed), the camera a pinhole whose rays start at its centre (t_min
    /// 0) outside the mesh's box, and the light directional or a point outside the box by more
    /// than a thousandth of the coordinates' magnitude. Empty when no instance qualifies.
    std::vector<uint8_t> instances;
    /// A point light's least distance outside those instances' boxes (along the axis where it is
    /// farthest out), less a margin for the rounding of its coordinates; infinity for a
    /// directional light.
    float light_clearance = std::numeric_limits<float>::infinity();
};

SkippableBackFaces back_faces_skippable(const Scene& scene, const Camera& camera, const Light& light);

/// Whether a shadow ray that starts `offset` (ray_offset_distance) off its hit and runs
/// `distance` to the light (infinity: a directional light, or one too far to say, and the ray
/// goes on for ever) ends outside the boxes `skippable` relies on. It ends within offset plus
/// rounding (a few ulps of the distance and of the hit's coordinates, which the offset exceeds)
/// of the light; this allows three offsets and 1e-5 of the distance. Both shading paths ask it
/// with the same numbers.
inline bool ends_clear_of_boxes(const SkippableBackFaces& skippable, float offset, float distance) {
    if (distance == std::numeric_limits<float>::infinity()) return true;
    return 3 * offset + 1e-5f * distance < skippable.light_clearance;
}

/// Whether a shadow ray from a camera hit starts on the camera's side of the hit's plane:
/// offset_ray_origin moves it off the plane of `geometric_normal` to the side of `to_light`, and
/// the camera ray came from the side of `to_viewer`. False when that one lies in the plane (or is
/// NaN), and for a normal that is not of unit length (a zero or tiny one would start the ray
/// about at the hit, on either side).
inline bool origin_on_camera_side(Vec3f geometric_normal, Vec3f to_light, Vec3f to_viewer) {
    if (!(dot(geometric_normal, geometric_normal) > 0.5f)) return false;
    // offset_ray_origin_by's own test: the origin goes to the normal's negative side where this is < 0.
    const bool origin_negative = dot(geometric_normal, to_light) < 0;
    const float viewer_side = dot(geometric_normal, to_viewer);
    return origin_negative ? viewer_side < 0 : viewer_side > 0;
}

}  // namespace raycast
