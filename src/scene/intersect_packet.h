// Closest hits for small groups of coherent rays (a block of neighbouring pixels), and any hits
// for groups of shadow rays, traced together with SIMD instructions: AVX-512, AVX2, SSE2 or
// portable C++, chosen at run time for the CPU. The answers are exactly those intersect() and
// occluded() give for each ray alone, so the image never depends on which path ran. The same
// choice of instruction set picks the single-ray mesh kernel that intersect() itself uses.
#pragma once

#include <vector>

#include "math/lane_vectors.h"
#include "scene/packet_view.h"
#include "scene/scene.h"

namespace raycast {

/// The most rays one packet holds: as many as a LaneVectors (math/lane_vectors.h) has lanes.
constexpr int kMaxPacketLanes = kMaxLanes;

enum class PacketIsa {
    None,      ///< no packets: every ray alone
    Portable,  ///< 4 lanes of plain C++
    Sse2,      ///< 4 lanes
    Avx2,      ///< 8 lanes
    Avx512,    ///< 16 lanes
};

/// "none", "portable", "sse2", "avx2" or "avx512".
const char* packet_isa_name(PacketIsa isa);
/// The instruction set with a name from packet_isa_name, or false if there is none.
bool packet_isa_from_name(const char* name, PacketIsa& isa);
/// Whether this build has the kernel and this CPU can run it.
bool packet_isa_available(PacketIsa isa);
/// The widest instruction set available.
PacketIsa best_packet_isa();
/// Rays per packet: 16, 8, 4, or 1 for None.
int packet_isa_lanes(PacketIsa isa);
/// The single-ray kernel for meshes of an available instruction set (AVX-512's is the AVX2 code
/// with AVX-512VL's permutes, or the AVX2 one on a CPU without VL; None gives the portable one).
/// intersect() and occluded() use best_packet_isa()'s: best_mesh_ray_kernel().
const MeshRayKernel& mesh_ray_kernel(PacketIsa isa);
/// The single-ray kernel of the widest instruction set this CPU runs, chosen once.
const MeshRayKernel& best_mesh_ray_kernel();

/// surface_at's SurfacePoint for several hits, a lane each.
struct SurfaceLanes {
    LaneVectors position, normal, geometric_normal;
    uint32_t material[kMaxPacketLanes];
    float geometry_scale[kMaxPacketLanes];

    SurfacePoint at(int j) const {
        return {position.at(j), normal.at(j), geometric_normal.at(j), material[j], geometry_scale[j]};
    }
};

/// surface_at(scene, rays[k], hits[k]) for k = lanes[j], j < count (all hits), into lane j of
/// `out`: the same bits. Triangles of meshes without vertex normals or transforms (most hits)
/// get their corners one by one and their normal and position in SIMD; every other hit goes
/// through surface_at.
void surface_points(const Scene& scene, const Ray* rays, const Hit* hits, const int* lanes, int count,
                    SurfaceLanes& out);

/// Above this Scene::worst_transform_condition, packets trace ray by ray. A transform near
/// singular (two rows of a Matrix almost alike, its inverse's entries near 1e7) rounds the rays
/// it moves into an object's space so much that a shape's test can report a hit a hair outside
/// the box the object has in the world; whether a ray reaches that test then depends on the
/// traversal's box tests, and `--shadows` and `--mode ao` images differed between instruction
/// sets by a few pixels. Ray by ray every path is the same code. Such scenes agreed across paths
/// at a condition of 1e6 and differed at 1e7 (docs/limits.md); the limit keeps a margin below.
constexpr float kMaxPacketCondition = 1e5f;

/// Traces packets of rays through one scene with one instruction set.
class PacketTracer {
public:
    /// `isa` must be available; PacketIsa::None traces ray by ray, and so does every instruction
    /// set in a scene past kMaxPacketCondition (isa() then says None).
    PacketTracer(const Scene& scene, PacketIsa isa);

    PacketIsa isa() const { return isa_; }
    int lanes() const { return packet_isa_lanes(isa_); }

    /// Closest hits of rays[0..count) with t > t_min; count <= lanes(); hits must start empty.
    void intersect(const Ray* rays, int count, float t_min, Hit* hits) const;
    /// intersect() for each run of lanes() rays of rays[0..count), count <= kMaxSharedPackets *
    /// lanes(): for a block of a pinhole camera's rays, four packets of 4x4 pixels, which walk the
    /// BVH together where the scene allows (see packet_kernel.inl), with the same hits.
    void intersect_packets(const Ray* rays, int count, float t_min, Hit* hits) const;

    /// blocked[k] = occluded(scene, rays[k], t_min, t_max[k]) for k < count <= lanes(): whether
    /// anything lies on ray k with t_min < t < t_max[k]. The rays need not share an origin or a
    /// direction (shadow rays from a packet's hits towards one light), but coherent ones are
    /// traced faster. The rays `skipping` marks pass over the back faces it allows, as
    /// occluded() with its instances does for each.
    void occluded(const Ray* rays, int count, float t_min, const float* t_max, bool* blocked,
                  const BackFaceSkipping& skipping = {}) const;

private:
    const Scene& scene_;
    PacketIsa isa_;
    PacketKernel kernel_;
    std::vector<MeshView> meshes_;
    PacketSceneView view_;
};

}  // namespace raycast
