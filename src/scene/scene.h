// The render-ready scene: flat arrays of shapes, each placed by an instance, a BVH over the
// instances and one per unique mesh (two levels, so a mesh used several times is stored once).
// The renderer asks it two things: the closest hit (intersect) and any hit (occluded).
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/wide_bvh.h"
#include "geometry/hit.h"
#include "geometry/plane.h"
#include "geometry/rev_surface.h"
#include "geometry/sphere.h"
#include "geometry/triangle_groups.h"
#include "geometry/triangle_mesh.h"
#include "math/mat4.h"
#include "scene/back_faces.h"
#include "scene/camera.h"
#include "scene/conventions.h"
#include "scene/light.h"
#include "scene/material.h"

namespace raycast {

/// A unique mesh with its own BVH, in its object space. Built, it keeps only what tracing and
/// shading read: the wide BVH, the triangles packed in groups in leaf order (each group holds its
/// triangles' corners and ids), and the file's vertex normals. The positions and the index list
/// are dropped: every triangle's corners are in its group.
struct MeshShape {
    TriangleMesh mesh;  ///< only `normals` and `normal_indices` are kept (empty without vn)
    WideBvh bvh;        ///< leaf payloads: the block in `groups` where the leaf's first group
                        ///< starts; prim_order is dropped (each group holds its triangles' ids)
    LargeVector<GroupBlock> groups;  ///< followed by kGroupPaddingBlocks of padding
    Bounds3f bounds;
    size_t triangle_count = 0;  ///< as the file gave them, degenerate ones included
    /// The median of the leaves' sizes (a leaf box's largest side): how far apart rays may lie
    /// before a packet's frustum passes more leaves than its rays enter (packet_kernel.inl).
    float leaf_size = 0;
    /// For a closed mesh (mesh_is_closed), the normal cones of every node's children
    /// (scene/back_faces.h), so that shadow rays may skip its back faces; empty otherwise.
    LargeVector<NodeCones> cones;
};

/// A mesh as the SIMD kernels see it (scene/packet_view.h): its wide BVH, whose leaves' payloads
/// are block indices of their first triangle group in `groups`.
struct MeshView {
    const WideBvhNode* nodes = nullptr;  ///< nullptr for a mesh with nothing to hit
    const GroupBlock* groups = nullptr;
    float leaf_size = 0;                 ///< MeshShape::leaf_size
    float lower[3] = {}, upper[3] = {};  ///< the root's box (MeshShape::bounds)
    /// MeshShape::cones, for any-hit queries that may skip the mesh's back faces: the packet
    /// kernel reads it for the lanes it is told may; the single-ray kernel whenever it is set (the
    /// caller sets it only then). Null: no cones, or no skipping.
    const NodeCones* cones = nullptr;
};

/// The view of a mesh that a single-ray kernel takes: with the mesh's cones when its back faces
/// may be skipped (an any-hit query told so) and it has them.
inline MeshView single_ray_view(const MeshShape& mesh, bool skipping_back_faces) {
    MeshView view{mesh.bvh.nodes.data(), mesh.groups.data()};
    if (skipping_back_faces && !mesh.cones.empty()) view.cones = mesh.cones.data();
    return view;
}

struct TriangleShape {
    Vec3f p0, p1, p2;
};

enum class ShapeKind : uint8_t { Sphere, Plane, Triangle, Mesh, RevSurface };

constexpr uint32_t kNoTransform = 0xffffffffu;

/// An object of the scene file: a shape, where it is (an optional transform) and its material.
/// Instances are numbered in file order, and Hit::object is that number.
struct Instance {
    ShapeKind kind = ShapeKind::Sphere;
    uint32_t shape = 0;     ///< index into the array of its kind
    uint32_t material = 0;  ///< index into Scene::materials
    uint32_t transform = kNoTransform;  ///< index into Scene::object_from_world
};

/// A scene of one object, a mesh in world space (no planes, nothing else). intersect() and
/// occluded() send its single rays to the mesh's kernel from the caller's own code, inline,
/// instead of through the call to the two-level walk: that call cost about 3% of the single rays
/// of a 1k-triangle mesh (docs/performance.md). The functions are null for every other scene.
struct SoleMesh {
    void (*intersect)(const MeshView& mesh, const Ray& ray, float t_min, uint32_t object, Hit& best,
                      uint64_t* nodes_visited) = nullptr;  ///< MeshRayKernel::intersect
    bool (*occluded)(const MeshView& mesh, const Ray& ray, float t_min, float t_max) = nullptr;
    uint32_t instance = 0;
    uint32_t shape = 0;  ///< the instance's index in Scene::meshes
};

struct Scene {
    Camera camera;
    Conventions conventions;
    Vec3f background{0.5f, 0.5f, 0.5f};
    Vec3f ambient{0, 0, 0};
    std::vector<Light> lights;
    std::vector<Material> materials;

    std::vector<Sphere> spheres;
    std::vector<Plane> planes;  ///< in world space (transforms are applied to the plane equation)
    std::vector<TriangleShape> triangles;
    std::vector<MeshShape> meshes;
    std::vector<RevSurface> rev_surfaces;  ///< in object space, like meshes
    std::vector<Mat4> object_from_world;  ///< inverse transforms, M⁻¹, of instances that have one
    /// The largest condition of any transform (its linear part's largest entry times its
    /// inverse's): how much rounding the trip into an object's space can grow. 1 with none.
    float worst_transform_condition = 1;

    std::vector<Instance> instances;
    Bounds3f bounds;  ///< of every bounded object in world space (planes are not); empty if none
    std::vector<uint32_t> plane_instances;  ///< planes are unbounded: tested outside the BVH
    Bvh instance_bvh;                       ///< over the bounded instances; prim ids are instance ids
    SoleMesh sole_mesh;                     ///< set by build_scene where the scene is one mesh

    size_t triangle_count() const;
};

/// Statistics one thread gathers while tracing (summed over threads at the end).
struct TraceCounters {
    uint64_t nodes_visited = 0;
};

/// intersect() and occluded() for any scene: the planes, then the instance BVH (scene/intersect.cpp).
void intersect_two_level(const Scene& scene, const Ray& ray, float t_min, Hit& hit, TraceCounters* counters);
bool occluded_two_level(const Scene& scene, const Ray& ray, float t_min, float t_max, const uint8_t* skip_back_faces);

// The two queries below are inline for SoleMesh's sake. The SIMD kernels must not call them
// (see scene/packet_view.h: a copy compiled for their instruction set could be linked in for
// everyone).

/// The closest hit with t > t_min, if any (hit.is_hit()); ties as is_closer() says.
inline void intersect(const Scene& scene, const Ray& ray, float t_min, Hit& hit, TraceCounters* counters = nullptr) {
    const SoleMesh& sole = scene.sole_mesh;
    if (sole.intersect) {
        const MeshView view = single_ray_view(scene.meshes[sole.shape], false);
        sole.intersect(view, ray, t_min, sole.instance, hit, counters ? &counters->nodes_visited : nullptr);
        return;
    }
    intersect_two_level(scene, ray, t_min, hit, counters);
}

/// Whether anything lies on the ray with t_min < t < t_max (any hit, for shadow rays). Where
/// skip_back_faces[instance] is 1, that instance's mesh is tested only for the triangles that do
/// not all face away from the ray with their neighbours (scene/back_faces.h: the caller vouches
/// that the ray starts and ends outside it).
inline bool occluded(const Scene& scene, const Ray& ray, float t_min, float t_max,
                     const uint8_t* skip_back_faces = nullptr) {
    const SoleMesh& sole = scene.sole_mesh;
    if (sole.occluded) {
        const bool skipping = skip_back_faces && skip_back_faces[sole.instance];
        return sole.occluded(single_ray_view(scene.meshes[sole.shape], skipping), ray, t_min, t_max);
    }
    return occluded_two_level(scene, ray, t_min, t_max, skip_back_faces);
}

/// What shading needs to know about a hit.
struct SurfacePoint {
    Vec3f position;  ///< world space: ray.origin + t·ray.direction
    Vec3f normal;    ///< world space, unit; as the geometry defines it (never flipped); a mesh's
                     ///< vertex normals interpolated where it has them
    /// World space, unit: the normal of the surface's own plane (of the triangle, for a mesh with
    /// vertex normals too). New rays leave the surface on its side of this one: an interpolated
    /// normal can point to the other side of the triangle, and a ray moved that way meets it again.
    Vec3f geometric_normal;
    uint32_t material = 0;
    /// How large the numbers were that the hit's shape was given in, in world units: for a
    /// triangle, the largest coordinate of its corners; for a sphere, its centre's largest
    /// coordinate plus its radius; 0 for planes (whose test's error is that of the point's own
    /// coordinates) and surfaces of revolution (not measured). A point found on a triangle 4000
    /// across, or on a sphere of radius 2000 used as a floor, is only as accurate as the shape's
    /// numbers, however near the origin it lies: new rays leave it by an offset that grows with
    /// this (render/shade.h, hit_travel_scale).
    float geometry_scale = 0;
};

SurfacePoint surface_at(const Scene& scene, const Ray& ray, const Hit& hit);

/// The ray in an instance's object space: direction not renormalised, so t is unchanged.
inline Ray to_object_space(const Mat4& object_from_world, const Ray& ray) {
    return {transform_point(object_from_world, ray.origin), transform_vector(object_from_world, ray.direction)};
}

}  // namespace raycast
