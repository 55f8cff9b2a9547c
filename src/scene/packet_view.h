// What the SIMD kernels see of a scene: plain structs of pointers (built once per render by
// PacketTracer for the packet kernels, per query for the single-ray kernels: MeshView, in
// scene.h, by single_ray_view).
// The kernels (packet_<isa>.cpp, ray_<isa>.cpp) are compiled with their own instruction-set
// flags, so they must not use inline functions or templates from shared headers: a copy
// compiled for AVX-512 could otherwise be linked in for everyone. They read these structs'
// fields and call the plain functions declared here for the work they leave to scalar code.
#pragma once

#include <cstdint>

#include "bvh/bvh.h"
#include "bvh/wide_bvh.h"
#include "geometry/triangle_groups.h"
#include "scene/scene.h"

namespace raycast {

/// A packet of rays from one origin is walked through a mesh as a frustum (one test for a node's
/// children, for every ray) unless its rays lie farther apart where they reach the mesh's box
/// than this many leaves (MeshView::leaf_size): then the frustum would pass many leaves that few
/// of its rays enter, and each ray's own box tests, lane by lane, do less work.
constexpr float kFrustumMaxFootprint = 2.0f;

/// The most packets that PacketKernel::intersect_packets walks together (an 8x8 block of pixels
/// in 4x4 packets).
constexpr int kMaxSharedPackets = 4;

struct PacketSceneView {
    const Scene* scene = nullptr;
    const Instance* instances = nullptr;
    const Mat4* object_from_world = nullptr;
    const MeshView* meshes = nullptr;
    const BvhNode* instance_nodes = nullptr;
    const uint32_t* instance_ids = nullptr;
    uint32_t instance_node_count = 0;
    const uint32_t* plane_instances = nullptr;
    uint32_t plane_count = 0;
    const Sphere* spheres = nullptr;  ///< scene.spheres, tested in SIMD
    const Plane* planes = nullptr;    ///< scene.planes, likewise
};

/// The closest hit of one instance along a world-space ray, merged into `hit` (at
/// at_leaf_floor(t, leaf_entry): leaf_entry is where the ray enters the box of the instance
/// BVH's leaf that holds it, -inf for none), and whether one instance has a hit with
/// t_min < t < t_max (scalar code, defined in intersect.cpp): the packet kernels use them for
/// spheres, single triangles and planes.
void intersect_instance(const Scene& scene, uint32_t id, const Ray& world_ray, float t_min, float leaf_entry, Hit& hit);
bool occluded_instance(const Scene& scene, uint32_t id, const Ray& world_ray, float t_min, float t_max);

/// A packet kernel: closest hits of a packet, and any hits of a packet with a t_max per ray.
struct PacketKernel {
    void (*intersect)(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) = nullptr;
    void (*occluded)(const PacketSceneView& view, const Ray* rays, int count, float t_min, const float* t_max,
                     bool* blocked, const BackFaceSkipping& skipping) = nullptr;
    void (*intersect_packets)(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) = nullptr;
};

/// What one group test found, lane by lane (lane i: the group's triangle i): hits has bit i set
/// when triangle i is hit at t[i] > t_min with barycentrics u[i], v[i]. Tests compare it with the
/// scalar test.
struct GroupLanes {
    unsigned hits = 0;
    float t[kGroupMaxTriangles], u[kGroupMaxTriangles], v[kGroupMaxTriangles];
};

/// A single-ray kernel: one ray, in the mesh's object space, against one mesh (which must have a
/// BVH: mesh.nodes is not null). Hits count when t > t_min.
struct MeshRayKernel {
    /// Merges the mesh's closest hit into `best` (as is_closer orders them; `object` is the
    /// instance); adds the child boxes it tests to *nodes_visited when that is given.
    void (*intersect)(const MeshView& mesh, const Ray& ray, float t_min, uint32_t object, Hit& best,
                      uint64_t* nodes_visited) = nullptr;
    /// Whether the mesh has a hit with t_min < t < t_max, passing over the children whose
    /// triangles all face away from the ray when mesh.cones is set.
    bool (*occluded)(const MeshView& mesh, const Ray& ray, float t_min, float t_max) = nullptr;
    /// Tests every triangle of one group, as the other two do.
    void (*test_group)(const GroupBlock* group, const Ray& ray, float t_min, GroupLanes& lanes) = nullptr;
};

// One kernel of each kind per instruction set; which exist depends on the compiler and the target.
#define RAYCAST_DECLARE_PACKET_KERNEL                                                                      \
    void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);        \
    void intersect_packets(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits); \
    void occluded(const PacketSceneView& view, const Ray* rays, int count, float t_min, const float* t_max, \
                  bool* blocked, const BackFaceSkipping& skipping);
namespace packet_portable {
RAYCAST_DECLARE_PACKET_KERNEL
}
namespace packet_sse2 {
RAYCAST_DECLARE_PACKET_KERNEL
}
namespace packet_avx2 {
RAYCAST_DECLARE_PACKET_KERNEL
}
namespace packet_avx512 {
RAYCAST_DECLARE_PACKET_KERNEL
}
#undef RAYCAST_DECLARE_PACKET_KERNEL
#define RAYCAST_DECLARE_RAY_KERNEL                                                                               \
    void intersect(const MeshView& mesh, const Ray& ray, float t_min, uint32_t object, Hit& best,                 \
                   uint64_t* nodes_visited);                                                                      \
    bool occluded(const MeshView& mesh, const Ray& ray, float t_min, float t_max);                                \
    void test_group(const GroupBlock* group, const Ray& ray, float t_min, GroupLanes& lanes);
namespace ray_portable {
RAYCAST_DECLARE_RAY_KERNEL
}
namespace ray_sse2 {
RAYCAST_DECLARE_RAY_KERNEL
}
namespace ray_avx2 {
RAYCAST_DECLARE_RAY_KERNEL
}
namespace ray_avx512 {
RAYCAST_DECLARE_RAY_KERNEL
}
#undef RAYCAST_DECLARE_RAY_KERNEL

}  // namespace raycast
