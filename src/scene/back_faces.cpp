#include "scene/back_faces.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "base/parallel.h"
#include "scene/camera.h"
#include "scene/light.h"
#include "scene/scene.h"

namespace raycast {

namespace {

// A 64-bit mix of a directed edge (SplitMix64's finaliser of the pair): summed over a mesh's
// edges one way and the other, the two sums differ unless every edge is balanced, but for a
// collision of about one chance in 2^64.
uint64_t edge_hash(uint32_t from, uint32_t to) {
    uint64_t z = ((uint64_t{from} << 32) | to) + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// Vec3d and its arithmetic are geometry/curve.h's.
Vec3d cross(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double length(Vec3d a) { return std::sqrt(dot(a, a)); }

// The normals under a child: the cone stored for it (its integer axis q and the greatest distance
// of a unit normal from q/127), and their sum, for the parent's axis. Not `clear` when a normal
// could not be found.
struct ConeSummary {
    bool clear = true;
    int8_t q[3] = {0, 0, 0};
    double spread = 0;  // max |n − q/127|
    Vec3d sum;          // of the unit normals
};

ConeSummary unclear() {
    ConeSummary s;
    s.clear = false;
    return s;
}

// Every unit normal under a child lies within this of q/127 (the kernels' rounding bound in
// build_normal_cones): the slot's reach, or kNoCone.
uint8_t reach_of(const ConeSummary& s) {
    if (!s.clear) return kNoCone;
    // q·d and τ·|d| in float are each within 1e-4·|d| of their exact values (|q| <= 127·√3, τ <=
    // 254: three products and two sums, a square root); 0.01 covers both, a hundred times over.
    const double reach = std::ceil(127.0 * s.spread + 0.01);
    return reach < kNoCone ? static_cast<uint8_t>(reach) : kNoCone;
}

Vec3d axis_of(const ConeSummary& s) { return {s.q[0] / 127.0, s.q[1] / 127.0, s.q[2] / 127.0}; }

// Picks q for a sum of normals: the nearest integers to 127 times its direction.
bool quantise_axis(Vec3d sum, int8_t q[3]) {
    const double length_of_sum = length(sum);
    if (!(length_of_sum > 0) || !std::isfinite(length_of_sum)) return false;
    const double c[3] = {sum.x / length_of_sum, sum.y / length_of_sum, sum.z / length_of_sum};
    for (int a = 0; a < 3; ++a) {
        // Rounded half away from zero by truncating (std::lround is a library call, and this runs
        // for every node and leaf); |127·c| <= 127.
        const double scaled = 127.0 * c[a];
        q[a] = static_cast<int8_t>(std::clamp(static_cast<int>(scaled + (scaled < 0 ? -0.5 : 0.5)), -127, 127));
    }
    return true;
}

double distance(Vec3d a, Vec3d b) { return length(a - b); }

// A leaf's normals, each checked: a sliver's cross product is too inexact to say which way it faces.
ConeSummary leaf_summary(const GroupBlock* groups, uint32_t first_block) {
    constexpr int kMaxNormals = 64;
    Vec3d normals[kMaxNormals];
    int count = 0;
    ConeSummary s;
    for (const GroupBlock* group = groups + first_block;; group = next_group(group)) {
        for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) {
            const GroupTriangle t = group_triangle(group, lane);
            const Vec3d e1 = to_double(t.p1) - to_double(t.p0), e2 = to_double(t.p2) - to_double(t.p0);
            const Vec3d n = cross(e1, e2);
            const double n_squared = dot(n, n), scale_squared = dot(e1, e1) * dot(e2, e2);
            // Exact float corners, differences and products in double: the normal's direction is
            // off by about 1e-16 · |e1||e2| / |n|, far inside the reach's margin unless |n| is tiny.
            if (!(n_squared > 1e-18 * scale_squared) || !std::isfinite(scale_squared)) s.clear = false;
            if (!s.clear) continue;
            const Vec3d unit = (1.0 / std::sqrt(n_squared)) * n;
            s.sum = s.sum + unit;
            if (count < kMaxNormals) normals[count] = unit;
            ++count;
        }
        if (group_ends_leaf(group)) break;
    }
    if (!s.clear || count > kMaxNormals || !quantise_axis(s.sum, s.q)) return unclear();
    const Vec3d axis = axis_of(s);
    double farthest_squared = 0;
    for (int i = 0; i < count; ++i) {
        const Vec3d offset = normals[i] - axis;
        farthest_squared = std::max(farthest_squared, dot(offset, offset));
    }
    s.spread = std::sqrt(farthest_squared);
    return s;
}

// The cones of node `ref`'s subtree, written to cones[], and the summary of the whole subtree.
// The root's children's subtrees are found on `threads` threads.
ConeSummary subtree_summary(const WideBvh& bvh, const GroupBlock* groups, uint32_t ref, NodeCones* cones,
                            int threads = 1) {
    if (is_wide_leaf(ref)) return leaf_summary(groups, ref & kWidePayloadMask);
    const WideBvhNode& node = bvh.nodes[ref];
    NodeCones& out = cones[ref];
    ConeSummary children[kWideBvhWidth];
    ConeSummary s;
    if (threads > 1)
        parallel_for(node.child_count, threads, [&](size_t slot, int) {
            children[slot] = subtree_summary(bvh, groups, node.child[slot], cones);
        });
    else
        for (uint32_t slot = 0; slot < node.child_count; ++slot)
            children[slot] = subtree_summary(bvh, groups, node.child[slot], cones);
    for (uint32_t slot = 0; slot < kWideBvhWidth; ++slot) {
        for (int a = 0; a < 3; ++a) out.axis[a][slot] = 0;
        out.reach[slot] = kNoCone;
        if (slot >= node.child_count) continue;
        const ConeSummary& c = children[slot];
        for (int a = 0; a < 3; ++a) out.axis[a][slot] = c.q[a];
        out.reach[slot] = reach_of(c);
        s.clear = s.clear && c.clear;
        s.sum = s.sum + c.sum;
    }
    if (!s.clear || !quantise_axis(s.sum, s.q)) return unclear();
    // Every normal under child c is within c.spread of c's axis, which is this far from ours.
    const Vec3d axis = axis_of(s);
    for (uint32_t slot = 0; slot < node.child_count; ++slot)
        s.spread = std::max(s.spread, children[slot].spread + distance(axis_of(children[slot]), axis));
    return s;
}

// Whether p lies outside the box by more than `margin` along some axis.
bool outside_box(Vec3f p, const Bounds3f& box, float margin) {
    return p.x < box.lower.x - margin || p.x > box.upper.x + margin || p.y < box.lower.y - margin ||
           p.y > box.upper.y + margin || p.z < box.lower.z - margin || p.z > box.upper.z + margin;
}

}  // namespace

bool mesh_is_closed(const TriangleMesh& mesh, int threads) {
    const size_t triangles = mesh.triangle_count();
    if (triangles == 0) return false;
    constexpr size_t kChunk = size_t{1} << 16;
    const size_t chunks = (triangles + kChunk - 1) / kChunk;
    std::atomic<uint64_t> forward{0}, backward{0};
    // A mesh of one chunk stays on this thread: waking the helpers costs more than it (0.1 ms of
    // a 0.5 ms build at 1k triangles).
    parallel_for(chunks, chunks > 1 ? threads : 1, [&](size_t chunk, int) {
        uint64_t f = 0, b = 0;
        const size_t end = std::min(triangles, (chunk + 1) * kChunk);
        for (size_t i = chunk * kChunk; i < end; ++i) {
            const uint32_t* c = &mesh.indices[3 * i];
            f += edge_hash(c[0], c[1]) + edge_hash(c[1], c[2]) + edge_hash(c[2], c[0]);
            b += edge_hash(c[1], c[0]) + edge_hash(c[2], c[1]) + edge_hash(c[0], c[2]);
        }
        forward += f;
        backward += b;
    });
    return forward.load() == backward.load();
}

LargeVector<NodeCones> build_normal_cones(const WideBvh& bvh, const GroupBlock* groups, int threads) {
    LargeVector<NodeCones> cones(bvh.nodes.size());
    // Small trees stay on this thread, as in mesh_is_closed.
    constexpr size_t kNodesWorthThreads = 2048;
    if (!bvh.empty()) subtree_summary(bvh, groups, 0, cones.data(), cones.size() >= kNodesWorthThreads ? threads : 1);
    return cones;
}

SkippableBackFaces back_faces_skippable(const Scene& scene, const Camera& camera, const Light& light) {
    const Vec3f c = camera.center;
    if (camera.projection != Camera::Projection::Perspective || camera.lens_radius != 0 || camera.t_min != 0 ||
        !std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
        return {};
    SkippableBackFaces skippable;
    for (size_t id = 0; id < scene.instances.size(); ++id) {
        const Instance& instance = scene.instances[id];
        if (instance.kind != ShapeKind::Mesh || instance.transform != kNoTransform) continue;
        const MeshShape& mesh = scene.meshes[instance.shape];
        if (mesh.cones.empty() || mesh.bounds.is_empty()) continue;
        if (!outside_box(camera.center, mesh.bounds, 0)) continue;
        if (light.kind == Light::Kind::Point) {
            // Clearly outside, so that an instance the light nearly touches does not hold the
            // clearance, and with it every ray's skipping, down to nothing.
            const float scale = std::max({max_abs(light.position), max_abs(mesh.bounds.lower),
                                          max_abs(mesh.bounds.upper), max_abs(camera.center)});
            if (!std::isfinite(scale) || !outside_box(light.position, mesh.bounds, 1e-3f * scale)) continue;
            // How far outside: the light's coordinates and the box's are exact, their differences
            // within an ulp of the larger; 1e-5 of the magnitude covers that many times over.
            const Vec3f p = light.position;
            const Bounds3f& b = mesh.bounds;
            const float outside = std::max({b.lower.x - p.x, p.x - b.upper.x, b.lower.y - p.y, p.y - b.upper.y,
                                            b.lower.z - p.z, p.z - b.upper.z});
            skippable.light_clearance = std::min(skippable.light_clearance, outside - 1e-5f * scale);
        }
        if (skippable.instances.empty()) skippable.instances.resize(scene.instances.size(), 0);
        skippable.instances[id] = 1;
    }
    return skippable;
}

}  // namespace raycast
