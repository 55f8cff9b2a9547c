// Fuzz target: OBJ text -> parse_obj -> build_mesh_shape. An InputError is an expected outcome;
// anything else is a finding: a crash, a sanitizer report, a hang, another exception, or a broken
// promise of the headers that this target checks:
//  - "the mesh and every message are the same whatever ObjLoadOptions say" (load_obj.h): the text
//    is parsed whole on one thread, in chunks of one line (a seam at every line; inputs over
//    1 KiB in about 64 chunks), on 2 threads for inputs whose length is a multiple of 16, and on
//    one thread in chunks of 16..79 bytes (about 48 chunks over 4 KiB), and the three results
//    must be identical;
//  - a parsed mesh refers only to positions and normals it has;
//  - the mesh BVH (build_bvh.h) is a tree over every triangle with an area exactly once (one with
//    none is never hit, so it stays out: geometry/triangle.h), whose boxes hold
//    their children and triangles, with leaves of at most max_leaf_size (4) triangles and at most
//    kMaxBvhDepth levels (the traversal stack's size); leaf_triangles follow prim_order; and for
//    16384 triangles or more, where subtrees are built on threads, two threads build the same tree.
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
#include "geometry/triangle.h"
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

// Walks the tree from the root; returns the deepest level reached.
int check_node(const MeshShape& shape, uint32_t index, int depth, std::vector<uint8_t>& node_seen,
               std::vector<uint8_t>& slot_seen) {
    const Bvh& bvh = shape.bvh;
    if (index >= bvh.nodes.size()) finding("BVH child index past the nodes");
    if (node_seen[index]++) finding("BVH node reached twice");
    if (depth > kMaxBvhDepth) finding("BVH deeper than kMaxBvhDepth");
    const BvhNode& node = bvh.nodes[index];
    if (node.is_leaf()) {
        if (node.count > 4) finding("BVH leaf with more than max_leaf_size triangles", std::to_string(node.count));
        if (size_t{node.first} + node.count > bvh.prim_order.size()) finding("BVH leaf past prim_order");
        for (uint32_t slot = node.first; slot < node.first + node.count; ++slot) {
            if (slot_seen[slot]++) finding("prim_order slot in two leaves");
            if (!contains(node.bounds, triangle_bounds(shape.mesh, bvh.prim_order[slot])))
                finding("a triangle sticks out of its leaf's box");
        }
        return depth;
    }
    if (size_t{node.first} + 1 >= bvh.nodes.size()) finding("BVH children past the nodes");
    for (uint32_t child = node.first; child < node.first + 2; ++child)
        if (!contains(node.bounds, bvh.nodes[child].bounds)) finding("a child box sticks out of its parent's");
    const int left = check_node(shape, node.first, depth + 1, node_seen, slot_seen);
    const int right = check_node(shape, node.first + 1, depth + 1, node_seen, slot_seen);
    return left > right ? left : right;
}

void check_shape(const MeshShape& shape, size_t triangles) {
    const Bvh& bvh = shape.bvh;
    // Positions are finite (the parser refuses out-of-range numbers), so only a triangle with no
    // area has an empty box.
    std::vector<uint8_t> has_area(triangles, 0);
    size_t with_area = 0;
    for (size_t i = 0; i < triangles; ++i) {
        const uint32_t* corner = &shape.mesh.indices[3 * i];
        has_area[i] = !is_degenerate_triangle(shape.mesh.positions[corner[0]], shape.mesh.positions[corner[1]],
                                              shape.mesh.positions[corner[2]]);
        with_area += has_area[i];
    }
    if (bvh.prim_order.size() != with_area) finding("prim_order does not hold every triangle with an area");
    if (bvh.empty() != (with_area == 0)) finding("the BVH is empty but there are triangles, or the other way round");
    std::vector<uint8_t> seen(triangles, 0);
    for (uint32_t id : bvh.prim_order) {
        if (id >= triangles) finding("prim_order id out of range");
        if (!has_area[id]) finding("a triangle with no area in prim_order");
        if (seen[id]++) finding("triangle twice in prim_order");
    }
    if (shape.leaf_triangles.size() != with_area) finding("leaf_triangles of the wrong size");
    for (size_t i = 0; i < with_area; ++i) {
        const uint32_t* corner = &shape.mesh.indices[3 * size_t{bvh.prim_order[i]}];
        const LeafTriangle& t = shape.leaf_triangles[i];
        if (t.p0 != shape.mesh.positions[corner[0]] || t.p1 != shape.mesh.positions[corner[1]] ||
            t.p2 != shape.mesh.positions[corner[2]])
            finding("leaf_triangles do not follow prim_order");
    }
    if (bvh.empty()) return;
    std::vector<uint8_t> node_seen(bvh.nodes.size(), 0), slot_seen(bvh.prim_order.size(), 0);
    check_node(shape, 0, 1, node_seen, slot_seen);
    for (uint8_t s : node_seen)
        if (!s) finding("BVH node not reachable from the root");
    for (uint8_t s : slot_seen)
        if (!s) finding("prim_order slot in no leaf");
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
    check_shape(shape, triangles);
    if (triangles >= 16384) {
        const MeshShape threaded = build_mesh_shape(mesh, 2);
        if (!same_array(threaded.bvh.prim_order, shape.bvh.prim_order) ||
            !same_array(threaded.bvh.nodes, shape.bvh.nodes))
            finding("the mesh BVH depends on the thread count");
    }
    return 0;
}
