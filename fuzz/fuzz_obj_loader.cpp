// Fuzz target: OBJ text -> parse_obj -> build_mesh_shape. An InputError is an expected outcome;
// anything else is a finding: a crash, a sanitizer report, a hang, another exception, or a broken
// promise of the headers that this target checks:
//  - "the mesh and every message are the same whatever ObjLoadOptions say" (load_obj.h): the text
//    is parsed whole on one thread, in chunks of one line (a seam at every line; inputs over
//    1 KiB in about 64 chunks), on 2 threads for inputs whose length is a multiple of 16, and on
//    one thread in chunks of 16..79 bytes (about 48 chunks over 4 KiB), and the three results
//    must be identical;
//  - a parsed mesh refers only to positions and normals it has;
//  - the mesh's wide BVH (wide_bvh.h) is a tree whose boxes hold their children, at most
//    kMaxBvhDepth levels deep (the traversal stack's size), whose leaves are runs of triangle
//    groups (triangle_groups.h) within their limits, holding every triangle with an area exactly
//    once with its own corners, inside the leaf's box (one with none is never hit, so it stays
//    out: geometry/triangle.h); and for 16384 triangles or more, where subtrees are built
//    on threads, two threads build the same tree and groups.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "base/error.h"
#include "bvh/bvh.h"
#include "bvh/wide_bvh.h"
#include "geometry/triangle.h"
#include "geometry/triangle_groups.h"
#include "scene/build_scene.h"
#include "sceneio/load_obj.h"

namespace {

using namespace raycast;

[[noreturn]] void finding(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz_obj_loader: FINDING: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
    std::abort();
}

// What parse_obj gave: a mesh, or the diagnostics of its InputError.
struct Outcome {
    std::optional<TriangleMesh> mesh;
    std::vector<Diagnostic> diagnostics;
};

Outcome parse(std::string_view text, int threads, size_t chunk_bytes) {
    ObjLoadOptions options;
    options.threads = threads;
    options.chunk_bytes = chunk_bytes;
    Outcome outcome;
    try {
        outcome.mesh = parse_obj(text, "fuzz.obj", options);
    } catch (const InputError& error) {
        outcome.diagnostics = error.diagnostics();
        if (outcome.diagnostics.empty()) finding("InputError without diagnostics");
        if (outcome.diagnostics.size() > 20) finding("more than 20 diagnostics");
        for (const Diagnostic& d : outcome.diagnostics) (void)format_diagnostic(d);
    }
    return outcome;
}

template <typename T, typename Allocator>
bool same_array(const std::vector<T, Allocator>& a, const std::vector<T, Allocator>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

void check_same(const Outcome& a, const Outcome& b, const char* how) {
    if (a.mesh.has_value() != b.mesh.has_value())
        finding("one way of parsing fails and the other does not", how);
    if (a.mesh) {
        if (!same_array(a.mesh->positions, b.mesh->positions) || !same_array(a.mesh->indices, b.mesh->indices) ||
            !same_array(a.mesh->normals, b.mesh->normals) ||
            !same_array(a.mesh->normal_indices, b.mesh->normal_indices))
            finding("the mesh depends on how the text is cut into chunks", how);
        return;
    }
    if (a.diagnostics.size() != b.diagnostics.size())
        finding("the number of diagnostics depends on the chunks",
                std::string(how) + ": " + std::to_string(a.diagnostics.size()) + " vs " +
                    std::to_string(b.diagnostics.size()));
    for (size_t i = 0; i < a.diagnostics.size(); ++i) {
        const Diagnostic& x = a.diagnostics[i];
        const Diagnostic& y = b.diagnostics[i];
        if (x.severity != y.severity || x.location.line != y.location.line || x.location.column != y.location.column ||
            x.message != y.message || x.source_line != y.source_line)
            finding("a diagnostic depends on the chunks",
                    std::string(how) + ":\n" + format_diagnostic(x) + "\nvs\n" + format_diagnostic(y));
    }
}

void check_mesh(const TriangleMesh& mesh) {
    if (mesh.indices.size() % 3 != 0) finding("indices not a multiple of 3");
    for (uint32_t index : mesh.indices)
        if (index >= mesh.positions.size()) finding("a face refers to a missing vertex");
    if (mesh.has_normals()) {
        if (mesh.normal_indices.size() != mesh.indices.size()) finding("normal_indices and indices differ in size");
        for (uint32_t index : mesh.normal_indices)
            if (index != kNoNormal && index >= mesh.normals.size()) finding("a face refers to a missing normal");
    }
}

bool contains(const Bounds3f& outer, const Bounds3f& inner) {
    for (int axis = 0; axis < 3; ++axis)
        if (inner.lower[axis] < outer.lower[axis] || inner.upper[axis] > outer.upper[axis]) return false;
    return true;
}

Bounds3f triangle_bounds(const TriangleMesh& mesh, uint32_t triangle) {
    Bounds3f b;
    for (size_t k = 0; k < 3; ++k) b.grow(mesh.positions[mesh.indices[3 * size_t{triangle} + k]]);
    return b;
}

// Checks a leaf's run of groups against the mesh: limits, corners, ids seen once, boxes.
void check_leaf(const MeshShape& shape, const TriangleMesh& mesh, uint32_t first_block, const Bounds3f& box,
                std::vector<uint8_t>& seen) {
    const size_t end = shape.groups.size() - kGroupPaddingBlocks;
    for (size_t block = first_block;;) {
        if (block >= end) finding("a leaf's groups run past the group array");
        const GroupBlock* group = &shape.groups[block];
        const uint32_t k = group_triangle_count(group), v = group_vertex_count(group);
        if (k < 1 || k > static_cast<uint32_t>(kGroupMaxTriangles)) finding("a group of the wrong size");
        if (v < 1 || v > static_cast<uint32_t>(kGroupMaxVertices)) finding("a group with the wrong vertex count");
        if (block + group_layout::group_blocks(k, v) > end) finding("a group runs past the group array");
        const unsigned char* corners = group->bytes + group_layout::group_corners_offset();  // runs past bytes[16]
        for (uint32_t c = 0; c < 3 * k; ++c)
            if (corners[c] >= v) finding("a corner past the group's vertices");
        for (uint32_t lane = 0; lane < k; ++lane) {
            const GroupTriangle tri = group_triangle(group, lane);
            if (tri.id >= seen.size()) finding("a triangle id out of range");
            if (seen[tri.id]++) finding("a triangle in two groups");
            if (tri.p0 != mesh.positions[mesh.indices[3 * size_t{tri.id}]] ||
                tri.p1 != mesh.positions[mesh.indices[3 * size_t{tri.id} + 1]] ||
                tri.p2 != mesh.positions[mesh.indices[3 * size_t{tri.id} + 2]])
                finding("a group's corners are not the mesh's");
            if (!contains(box, triangle_bounds(mesh, tri.id))) finding("a triangle sticks out of its leaf's box");
        }
        if (group_ends_leaf(group)) return;
        block += group_layout::group_blocks(k, v);
    }
}

// Walks the tree from the root; returns the deepest level reached.
int check_node(const MeshShape& shape, const TriangleMesh& mesh, uint32_t index, const Bounds3f& box, int depth,
               std::vector<uint8_t>& node_seen, std::vector<uint8_t>& seen) {
    const WideBvh& bvh = shape.bvh;
    if (index >= bvh.nodes.size()) finding("BVH child index past the nodes");
    if (node_seen[index]++) finding("BVH node reached twice");
    if (depth > kMaxBvhDepth) finding("BVH deeper than kMaxBvhDepth");
    const WideBvhNode& node = bvh.nodes[index];
    if (node.child_count < 1 || node.child_count > static_cast<uint32_t>(kWideBvhWidth)) finding("a node's child count");
    int deepest = depth;
    for (uint32_t slot = 0; slot < static_cast<uint32_t>(kWideBvhWidth); ++slot) {
        const Bounds3f child = child_bounds(node, slot);
        if (slot >= node.child_count) {
            if (!child.is_empty()) finding("an empty slot with a box");
            continue;
        }
        if (!contains(box, child)) finding("a child box sticks out of its parent's");
        if (is_wide_leaf(node.child[slot])) {
            check_leaf(shape, mesh, node.child[slot] & kWidePayloadMask, child, seen);
        } else {
            const int level = check_node(shape, mesh, node.child[slot], child, depth + 1, node_seen, seen);
            deepest = level > deepest ? level : deepest;
        }
    }
    return deepest;
}

void check_shape(const MeshShape& shape, const TriangleMesh& mesh) {
    const size_t triangles = mesh.triangle_count();
    const WideBvh& bvh = shape.bvh;
    // Positions are finite (the parser refuses out-of-range numbers), so only a triangle with no
    // area has an empty box.
    std::vector<uint8_t> has_area(triangles, 0);
    size_t with_area = 0;
    for (size_t i = 0; i < triangles; ++i) {
        const uint32_t* corner = &mesh.indices[3 * i];
        has_area[i] = !is_degenerate_triangle(mesh.positions[corner[0]], mesh.positions[corner[1]], mesh.positions[corner[2]]);
        with_area += has_area[i];
    }
    if (bvh.empty() != (with_area == 0)) finding("the BVH is empty but there are triangles, or the other way round");
    if (shape.triangle_count != triangles) finding("triangle_count is not the mesh's");
    if (!shape.mesh.positions.empty() || !shape.mesh.indices.empty()) finding("the mesh keeps its positions");
    if (bvh.empty()) return;
    std::vector<uint8_t> node_seen(bvh.nodes.size(), 0), seen(triangles, 0);
    check_node(shape, mesh, 0, bvh.bounds, 1, node_seen, seen);
    for (uint8_t s : node_seen)
        if (!s) finding("BVH node not reachable from the root");
    for (size_t i = 0; i < triangles; ++i) {
        if (has_area[i] && !seen[i]) finding("a triangle with an area in no group");
        if (!has_area[i] && seen[i]) finding("a triangle with no area in a group");
    }
}

// Field by field: a node's padding bytes are not part of it.
bool same_nodes(const WideBvh& a, const WideBvh& b) {
    if (a.nodes.size() != b.nodes.size()) return false;
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const WideBvhNode &x = a.nodes[i], &y = b.nodes[i];
        if (std::memcmp(x.child, y.child, sizeof x.child) != 0 || std::memcmp(x.bounds, y.bounds, sizeof x.bounds) != 0 ||
            std::memcmp(x.prim_count, y.prim_count, sizeof x.prim_count) != 0 || x.child_count != y.child_count)
            return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // The view covers exactly the fuzzer's buffer, so ASan sees any read past its end.
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const Outcome whole = parse(text, 1, 0);
    // Every chunk reports up to 20 errors of its own before they are merged, so thousands of
    // chunks make a large bad input slow: inputs over 1 KiB are cut into about 64 chunks.
    // Starting threads costs ~6 ms per input under ASan (7x the rest), so 1 input in 16, picked
    // by its length, is parsed on 2 threads and the others on 1 (the same chunks either way).
    const int threads = size % 16 == 0 ? 2 : 1;
    check_same(whole, parse(text, threads, size <= 1024 ? 1 : size / 64), "whole vs 1-line chunks");
    check_same(whole, parse(text, 1, size <= 4096 ? 16 + size % 64 : size / 48 + size % 64), "whole vs small chunks");
    if (!whole.mesh) return 0;

    const TriangleMesh& mesh = *whole.mesh;
    check_mesh(mesh);
    const size_t triangles = mesh.triangle_count();
    const MeshShape shape = build_mesh_shape(mesh, 1);
    check_shape(shape, mesh);
    if (triangles >= 16384) {
        const MeshShape threaded = build_mesh_shape(mesh, 2);
        if (!same_nodes(threaded.bvh, shape.bvh) || !same_array(threaded.groups, shape.groups))
            finding("the mesh BVH depends on the thread count");
    }
    return 0;
}
