// What the SIMD packet kernels see of a scene: plain structs of pointers, built once per render
// by PacketTracer. The kernels (packet_<isa>.cpp) are compiled with their own instruction-set
// flags, so they must not use inline functions or templates from shared headers: a copy
// compiled for AVX-512 could otherwise be linked in for everyone. They read these structs'
// fields and call the plain functions declared here for the work they leave to scalar code.
#pragma once

#include <cstdint>

#include "scene/scene.h"

namespace raycast {

struct PacketMeshView {
    const BvhNode* nodes = nullptr;
    const LeafTriangle* triangles = nullptr;
    const uint32_t* prim_ids = nullptr;
    uint32_t node_count = 0;
};

struct PacketSceneView {
    const Scene* scene = nullptr;
    const Instance* instances = nullptr;
    const Mat4* object_from_world = nullptr;
    const PacketMeshView* meshes = nullptr;
    const BvhNode* instance_nodes = nullptr;
    const uint32_t* instance_ids = nullptr;
    uint32_t instance_node_count = 0;
    const uint32_t* plane_instances = nullptr;
    uint32_t plane_count = 0;
};

/// The closest hit of one instance along a world-space ray, merged into `hit` (scalar code,
/// defined in intersect.cpp): the kernels use it for spheres, single triangles, planes, and
/// meshes whose rays cannot share one watertight axis permutation.
void intersect_instance(const Scene& scene, uint32_t id, const Ray& world_ray, float t_min, Hit& hit);

using PacketKernel = void (*)(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);

// One kernel per instruction set; which exist depends on the compiler and the target.
namespace packet_portable {
void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);
}
namespace packet_sse2 {
void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);
}
namespace packet_avx2 {
void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);
}
namespace packet_avx512 {
void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits);
}

}  // namespace raycast
