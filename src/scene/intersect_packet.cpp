#include "scene/intersect_packet.h"

#include <cstring>

#include "base/check.h"

namespace raycast {

namespace {

PacketKernel kernel_for(PacketIsa isa) {
    switch (isa) {
        case PacketIsa::None:
            return {};
        case PacketIsa::Portable:
            return {&packet_portable::intersect, &packet_portable::occluded, &packet_portable::intersect_packets};
        case PacketIsa::Sse2:
#ifdef RAYCAST_HAVE_SSE2_KERNEL
            return {&packet_sse2::intersect, &packet_sse2::occluded, &packet_sse2::intersect_packets};
#else
            return {};
#endif
        case PacketIsa::Avx2:
#ifdef RAYCAST_HAVE_AVX2_KERNEL
            return {&packet_avx2::intersect, &packet_avx2::occluded, &packet_avx2::intersect_packets};
#else
            return {};
#endif
        case PacketIsa::Avx512:
#ifdef RAYCAST_HAVE_AVX512_KERNEL
            return {&packet_avx512::intersect, &packet_avx512::occluded, &packet_avx512::intersect_packets};
#else
            return {};
#endif
    }
    return {};
}

bool cpu_runs(PacketIsa isa) {
#if defined(__x86_64__) || defined(__i386__)
    switch (isa) {
        case PacketIsa::Sse2:
            return __builtin_cpu_supports("sse2");
        case PacketIsa::Avx2:
            return __builtin_cpu_supports("avx2");
        case PacketIsa::Avx512:
            return __builtin_cpu_supports("avx512f");
        default:
            return true;
    }
#else
    return isa == PacketIsa::None || isa == PacketIsa::Portable;
#endif
}

}  // namespace

const char* packet_isa_name(PacketIsa isa) {
    switch (isa) {
        case PacketIsa::None: return "none";
        case PacketIsa::Portable: return "portable";
        case PacketIsa::Sse2: return "sse2";
        case PacketIsa::Avx2: return "avx2";
        case PacketIsa::Avx512: return "avx512";
    }
    return "none";
}

bool packet_isa_from_name(const char* name, PacketIsa& isa) {
    for (PacketIsa candidate : {PacketIsa::None, PacketIsa::Portable, PacketIsa::Sse2, PacketIsa::Avx2, PacketIsa::Avx512})
        if (std::strcmp(name, packet_isa_name(candidate)) == 0) {
            isa = candidate;
            return true;
        }
    return false;
}

bool packet_isa_available(PacketIsa isa) {
    return isa == PacketIsa::None || (kernel_for(isa).intersect != nullptr && cpu_runs(isa));
}

const MeshRayKernel& mesh_ray_kernel(PacketIsa isa) {
    RAYCAST_CHECK(packet_isa_available(isa));
    static const MeshRayKernel portable{&ray_portable::intersect, &ray_portable::occluded, &ray_portable::test_group};
#ifdef RAYCAST_HAVE_SSE2_KERNEL
    static const MeshRayKernel sse2{&ray_sse2::intersect, &ray_sse2::occluded, &ray_sse2::test_group};
    if (isa == PacketIsa::Sse2) return sse2;
#endif
#ifdef RAYCAST_HAVE_AVX512_RAY_KERNEL
    // The AVX2 kernel's 8-lane code (a node has 8 children, one AVX register per bound) with
    // AVX-512VL's two-register permute.
    static const MeshRayKernel avx512{&ray_avx512::intersect, &ray_avx512::occluded, &ray_avx512::test_group};
    if (isa == PacketIsa::Avx512 && __builtin_cpu_supports("avx512vl")) return avx512;
#endif
#ifdef RAYCAST_HAVE_AVX2_KERNEL
    static const MeshRayKernel avx2{&ray_avx2::intersect, &ray_avx2::occluded, &ray_avx2::test_group};
    if (isa == PacketIsa::Avx2 || isa == PacketIsa::Avx512) return avx2;
#endif
    return portable;
}

const MeshRayKernel& best_mesh_ray_kernel() {
    static const MeshRayKernel& kernel = mesh_ray_kernel(best_packet_isa());
    return kernel;
}

PacketIsa best_packet_isa() {
    for (PacketIsa isa : {PacketIsa::Avx512, PacketIsa::Avx2, PacketIsa::Sse2, PacketIsa::Portable})
        if (packet_isa_available(isa)) return isa;
    return PacketIsa::None;
}

int packet_isa_lanes(PacketIsa isa) {
    switch (isa) {
        case PacketIsa::None: return 1;
        case PacketIsa::Portable: return 4;
        case PacketIsa::Sse2: return 4;
        case PacketIsa::Avx2: return 8;
        case PacketIsa::Avx512: return 16;
    }
    return 1;
}

namespace {

// The instruction set a tracer uses for `scene`: the one asked for, or none (every ray alone)
// where a transform is so badly conditioned that the paths could disagree (kMaxPacketCondition).
PacketIsa isa_for(const Scene& scene, PacketIsa isa) {
    RAYCAST_CHECK(packet_isa_available(isa));
    return scene.worst_transform_condition <= kMaxPacketCondition ? isa : PacketIsa::None;
}

}  // namespace

PacketTracer::PacketTracer(const Scene& scene, PacketIsa isa)
    : scene_(scene), isa_(isa_for(scene, isa)), kernel_(kernel_for(isa_)) {
    meshes_.reserve(scene.meshes.size());
    for (const MeshShape& mesh : scene.meshes)
        meshes_.push_back({mesh.bvh.empty() ? nullptr : mesh.bvh.nodes.data(),
                           mesh.groups.data(),
                           mesh.leaf_size,
                           {mesh.bounds.lower.x, mesh.bounds.lower.y, mesh.bounds.lower.z},
                           {mesh.bounds.upper.x, mesh.bounds.upper.y, mesh.bounds.upper.z},
                           mesh.cones.empty() ? nullptr : mesh.cones.data()});
    view_.scene = &scene;
    view_.instances = scene.instances.data();
    view_.object_from_world = scene.object_from_world.data();
    view_.meshes = meshes_.data();
    view_.instance_nodes = scene.instance_bvh.nodes.data();
    view_.instance_ids = scene.instance_bvh.prim_order.data();
    view_.instance_node_count = static_cast<uint32_t>(scene.instance_bvh.nodes.size());
    view_.plane_instances = scene.plane_instances.data();
    view_.plane_count = static_cast<uint32_t>(scene.plane_instances.size());
    view_.spheres = scene.spheres.data();
    view_.planes = scene.planes.data();
}

void PacketTracer::intersect(const Ray* rays, int count, float t_min, Hit* hits) const {
    RAYCAST_DCHECK(count >= 0 && count <= lanes());
    for (int k = 0; k < count; ++k) RAYCAST_DCHECK(!hits[k].is_hit());
    if (!kernel_.intersect) {
        for (int k = 0; k < count; ++k) raycast::intersect(scene_, rays[k], t_min, hits[k]);
        return;
    }
    kernel_.intersect(view_, rays, count, t_min, hits);
}

void PacketTracer::intersect_packets(const Ray* rays, int count, float t_min, Hit* hits) const {
    RAYCAST_DCHECK(count >= 0 && count <= kMaxSharedPackets * lanes());
    for (int k = 0; k < count; ++k) RAYCAST_DCHECK(!hits[k].is_hit());
    if (!kernel_.intersect_packets) {
        for (int k = 0; k < count; ++k) raycast::intersect(scene_, rays[k], t_min, hits[k]);
        return;
    }
    if (count > 0) kernel_.intersect_packets(view_, rays, count, t_min, hits);
}

void PacketTracer::occluded(const Ray* rays, int count, float t_min, const float* t_max, bool* blocked,
                            const BackFaceSkipping& skipping) const {
    RAYCAST_DCHECK(count >= 0 && count <= lanes());
    if (!kernel_.occluded) {
        for (int k = 0; k < count; ++k)
            blocked[k] = raycast::occluded(scene_, rays[k], t_min, t_max[k],
                                           skipping.instances && skipping.rays[k] ? skipping.instances : nullptr);
        return;
    }
    kernel_.occluded(view_, rays, count, t_min, t_max, blocked, skipping);
}

}  // namespace raycast
