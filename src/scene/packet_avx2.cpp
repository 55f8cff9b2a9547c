// The packet kernel compiled for avx2 (see packet_kernel.inl; build flags in src/CMakeLists.txt).
#include <immintrin.h>

#include "scene/packet_view.h"

namespace raycast {
namespace packet_avx2 {
namespace {
#include "scene/packet_simd_avx2.h"
// Eight lanes for a node's eight children (the frustum test of packet_kernel.inl).
namespace wide8 {
#include "scene/packet_simd_avx2.h"
}  // namespace wide8
#define RAYCAST_PACKET_FRUSTUM 1
#include "scene/packet_kernel.inl"
}  // namespace

void intersect(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    trace_packet(view, rays, count, t_min, hits);
}

void intersect_packets(const PacketSceneView& view, const Ray* rays, int count, float t_min, Hit* hits) {
    trace_packets(view, rays, count, t_min, hits);
}

void occluded(const PacketSceneView& view, const Ray* rays, int count, float t_min, const float* t_max, bool* blocked,
              const BackFaceSkipping& skipping) {
    trace_packet_occluded(view, rays, count, t_min, t_max, blocked, skipping);
}

}  // namespace packet_avx2
}  // namespace raycast
