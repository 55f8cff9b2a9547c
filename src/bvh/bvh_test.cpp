// Tests for the BVH (bvh/build_bvh.h, bvh/bvh.h) and the scene-level closest-hit and any-hit
// queries built on it (scene/scene.h via build_scene). The BVH is only an acceleration: every
// answer must equal a brute-force loop over all primitives with the same primitive tests and the
// documented tie-break (Hit::is_closer), including for rays aimed exactly at shared edges and
// vertices, where near-ties between leaves are likeliest to expose a traversal that culls too
// eagerly. The tree itself must hold every primitive exactly once, have boxes that contain what
// is below them and a bounded depth, and be the same for every thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bvh/build_bvh.h"
#include "bvh/bvh.h"
#include "geometry/triangle.h"
#include "scene/build_scene.h"
#include "scene/scene.h"
#include "scene_builders.h"
#include "trace_test_support.h"

namespace raycast {
namespace {

using namespace test;  // tests/scene_builders.h and tests/trace_test_support.h

// ---------------------------------------------------------------------------------------------
// Tree invariants

bool same_bounds(const Bounds3f& a, const Bounds3f& b) { return a.lower == b.lower && a.upper == b.upper; }

// Node boxes are the exact box of their primitives moved out by one float step on every side,
// and by at least 1e-20, so that a ray lying in a face plane still enters the box (see
// RaysLyingInABoxFaceAreNotCulled).
Bounds3f padded(Bounds3f b) {
    for (int a = 0; a < 3; ++a) {
        b.lower[a] = std::min(std::nextafter(b.lower[a], -INFINITY), b.lower[a] - 1e-20f);
        b.upper[a] = std::max(std::nextafter(b.upper[a], INFINITY), b.upper[a] + 1e-20f);
    }
    return b;
}

// Checks the invariants of a tree built over `prims` (ids = their index); returns the depth of
// the deepest leaf (the root has depth 0).
int check_tree(const Bvh& bvh, const std::vector<BvhPrimitive>& prims, int max_leaf_size) {
    Bounds3f all;
    const std::vector<uint32_t> expected_ids = ids_with_boxes(prims, all);
    if (expected_ids.empty()) {
        EXPECT_TRUE(bvh.empty());
        EXPECT_TRUE(bvh.prim_order.empty());
        return 0;
    }
    EXPECT_FALSE(bvh.empty());
    if (bvh.empty()) return 0;

    // prim_order is a permutation of the non-empty primitives' ids.
    std::vector<uint32_t> order = bvh.prim_order;
    std::sort(order.begin(), order.end());
    EXPECT_EQ(order, expected_ids) << "prim_order is not a permutation of the non-empty primitives";

    EXPECT_TRUE(same_bounds(bvh.nodes[0].bounds, padded(all))) << "the root box is not the box of everything";

    std::vector<int> node_seen(bvh.nodes.size(), 0);
    std::vector<int> slot_seen(bvh.prim_order.size(), 0);
    int max_depth = 0;
    struct Item {
        uint32_t node;
        int depth;
    };
    std::vector<Item> stack{{0, 0}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        if (item.node >= bvh.nodes.size()) {
            ADD_FAILURE() << "child index " << item.node << " out of range";
            return max_depth;
        }
        if (node_seen[item.node]++ > 0) {
            ADD_FAILURE() << "node " << item.node << " reached twice";
            return max_depth;
        }
        const BvhNode& node = bvh.nodes[item.node];
        if (node.is_leaf()) {
            max_depth = std::max(max_depth, item.depth);
            EXPECT_LE(node.count, static_cast<uint32_t>(max_leaf_size)) << "leaf " << item.node;
            if (size_t{node.first} + node.count > bvh.prim_order.size()) {
                ADD_FAILURE() << "leaf " << item.node << " runs past prim_order";
                continue;
            }
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                ++slot_seen[i];
                const uint32_t id = bvh.prim_order[i];
                if (id < prims.size()) {
                    EXPECT_TRUE(contains(node.bounds, prims[id].bounds)) << "leaf " << item.node << ", prim " << id;
                }
            }
        } else {
            for (uint32_t child : {node.first, node.first + 1}) {
                if (child < bvh.nodes.size()) {
                    EXPECT_TRUE(contains(node.bounds, bvh.nodes[child].bounds))
                        << "node " << item.node << " does not contain child " << child;
                }
                stack.push_back({child, item.depth + 1});
            }
        }
    }
    for (size_t i = 0; i < node_seen.size(); ++i) EXPECT_EQ(node_seen[i], 1) << "node " << i << " unreachable";
    for (size_t i = 0; i < slot_seen.size(); ++i) EXPECT_EQ(slot_seen[i], 1) << "prim_order slot " << i;
    // The traversal stack holds kMaxBvhDepth entries; the header promises that median splits
    // below kMaxSahDepth add at most 32 levels.
    EXPECT_LT(max_depth, kMaxBvhDepth);
    EXPECT_LE(max_depth, kMaxSahDepth + 33);
    return max_depth;
}

TEST(BvhBuild, NothingToBuildGivesAnEmptyTree) {
    BvhBuildOptions options;
    EXPECT_TRUE(build_bvh({}, options).empty());
    // Empty boxes can never be hit: they are left out, even when they are all there is.
    std::vector<BvhPrimitive> only_empty(3);
    for (uint32_t i = 0; i < 3; ++i) only_empty[i].id = i;
    const Bvh bvh = build_bvh(only_empty, options);
    EXPECT_TRUE(bvh.empty());
    EXPECT_TRUE(bvh.prim_order.empty());
    EXPECT_EQ(sah_cost(bvh, options), 0);
}

TEST(BvhBuild, OnePrimitiveIsARootLeaf) {
    const std::vector<BvhPrimitive> prims{{box({1, 2, 3}, {4, 5, 6}), 7}};
    const Bvh bvh = build_bvh(prims, BvhBuildOptions{});
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_TRUE(bvh.nodes[0].is_leaf());
    EXPECT_EQ(bvh.nodes[0].first, 0u);
    EXPECT_EQ(bvh.nodes[0].count, 1u);
    EXPECT_EQ(bvh.prim_order, std::vector<uint32_t>{7});
    EXPECT_TRUE(same_bounds(bvh.nodes[0].bounds, padded(prims[0].bounds)));
}

TEST(BvhBuild, TwoSeparateBoxesSplitWithTheHandComputedSahCost) {
    // Unit cubes at x ∈ [0, 1] and [3, 4]. Root box 4×1×1: half area 4 + 1 + 4 = 9; each leaf 3.
    // Splitting costs 1 + (3·1 + 3·1)/9 = 1.667 < 2 (one leaf of two), so the root splits, and
    // sah_cost = (9·1 + 3·1 + 3·1)/9 = 15/9.
    const std::vector<BvhPrimitive> prims{{box({3, 0, 0}, {4, 1, 1}), 0}, {box({0, 0, 0}, {1, 1, 1}), 1}};
    BvhBuildOptions options;
    const Bvh bvh = build_bvh(prims, options);
    ASSERT_EQ(bvh.nodes.size(), 3u);
    EXPECT_FALSE(bvh.nodes[0].is_leaf());
    EXPECT_NEAR(sah_cost(bvh, options), 15.0 / 9.0, 1e-6);  // boxes are one float step larger
    check_tree(bvh, prims, options.max_leaf_size);
}

TEST(BvhBuild, HeavilyOverlappingBoxesShareALeaf) {
    // [0, 1]³ and [0.1, 1.1]×[0, 1]²: the root box's half area is 1.1 + 1 + 1.1 = 3.2, so a
    // split costs 1 + (3 + 3)/3.2 = 2.875 > 2 = the cost of one leaf with both: no split.
    const std::vector<BvhPrimitive> prims{{box({0, 0, 0}, {1, 1, 1}), 0}, {box({0.1f, 0, 0}, {1.1f, 1, 1}), 1}};
    BvhBuildOptions options;
    const Bvh bvh = build_bvh(prims, options);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    EXPECT_EQ(bvh.nodes[0].count, 2u);
    EXPECT_NEAR(sah_cost(bvh, options), 2.0, 1e-6);
    // With at most one primitive per leaf it must split anyway.
    options.max_leaf_size = 1;
    const Bvh forced = build_bvh(prims, options);
    EXPECT_EQ(forced.nodes.size(), 3u);
    check_tree(forced, prims, 1);
}

TEST(BvhBuild, TreeInvariantsHoldForManyShapesOfInput) {
    std::mt19937 rng(12);
    struct Config {
        int max_leaf, bins;
        float traversal_cost = 1;
        int leaf_test_width = 1;
    };
    // The last two: a mesh's settings, whose leaves beat any split and so get no SAH; and leaves
    // so cheap against the traversal that one of up to 24 would beat any split, yet none may hold
    // more than max_leaf.
    for (const Config config : {Config{4, 16}, Config{1, 2}, Config{2, 32}, Config{8, 7}, Config{3, 1000},
                                Config{8, 16, 1, 8}, Config{8, 16, 3, 8}}) {
        BvhBuildOptions options;
        options.max_leaf_size = config.max_leaf;
        options.bin_count = config.bins;
        options.traversal_cost = config.traversal_cost;
        options.leaf_test_width = config.leaf_test_width;
        SCOPED_TRACE("max_leaf " + std::to_string(config.max_leaf) + ", bins " + std::to_string(config.bins) +
                     ", traversal cost " + std::to_string(config.traversal_cost) + ", leaf test width " +
                     std::to_string(config.leaf_test_width));
        for (size_t count : {size_t{1}, size_t{2}, size_t{3}, size_t{5}, size_t{17}, size_t{100}, size_t{3000}}) {
            SCOPED_TRACE("random boxes: " + std::to_string(count));
            const std::vector<BvhPrimitive> prims = random_boxes(rng, count, 10, 2);
            check_tree(build_bvh(prims, options), prims, config.max_leaf);
        }
        {
            SCOPED_TRACE("identical boxes");  // no SAH plane exists: median splits only
            std::vector<BvhPrimitive> prims(200);
            for (uint32_t i = 0; i < prims.size(); ++i) prims[i] = {box({0, 0, 0}, {1, 1, 1}), i};
            check_tree(build_bvh(prims, options), prims, config.max_leaf);
        }
        {
            SCOPED_TRACE("one centroid, many sizes");
            std::vector<BvhPrimitive> prims(150);
            for (uint32_t i = 0; i < prims.size(); ++i) {
                const float s = 0.01f * static_cast<float>(i + 1);
                prims[i] = {box({-s, -s, -s}, {s, s, s}), i};
            }
            check_tree(build_bvh(prims, options), prims, config.max_leaf);
        }
        {
            SCOPED_TRACE("points (zero-size boxes) and empty boxes mixed in");
            std::vector<BvhPrimitive> prims = random_boxes(rng, 500, 5, 1);
            for (size_t i = 0; i < prims.size(); i += 3) prims[i].bounds = Bounds3f{};
            for (size_t i = 1; i < prims.size(); i += 5)
                if (!prims[i].bounds.is_empty()) prims[i].bounds.upper = prims[i].bounds.lower;
            check_tree(build_bvh(prims, options), prims, config.max_leaf);
        }
        {
            // Exponentially spaced boxes: a binned SAH peels off one box per level, so this is
            // the input that reaches kMaxSahDepth and falls back to median splits.
            SCOPED_TRACE("exponentially spaced");
            std::vector<BvhPrimitive> prims(300);
            for (uint32_t i = 0; i < prims.size(); ++i) {
                const float x = std::pow(1.3f, static_cast<float>(i));
                prims[i] = {box({x, 0, 0}, {x * 1.01f, 1, 1}), i};
            }
            const int depth = check_tree(build_bvh(prims, options), prims, config.max_leaf);
            EXPECT_GT(depth, 8);  // not a balanced tree: the case is really exercised
        }
        {
            SCOPED_TRACE("all in a flat plane (zero extent on one axis)");
            std::vector<BvhPrimitive> prims = random_boxes(rng, 400, 5, 1);
            for (BvhPrimitive& p : prims) p.bounds.lower.y = p.bounds.upper.y = 2;
            check_tree(build_bvh(prims, options), prims, config.max_leaf);
        }
        if (HasFailure()) return;
    }
}

// A binned SAH builder should beat (or at worst nearly match) the simplest reasonable tree: halve
// the primitives by centroid along the widest axis until four or fewer remain.
void median_build(std::vector<BvhPrimitive>& prims, uint32_t begin, uint32_t end, Bvh& bvh, uint32_t index) {
    Bounds3f bounds, centroids;
    for (uint32_t i = begin; i < end; ++i) {
        bounds.grow(prims[i].bounds);
        centroids.grow(prims[i].bounds.center());
    }
    bvh.nodes[index].bounds = padded(bounds);  // as build_bvh stores them
    if (end - begin <= 4) {
        bvh.nodes[index].first = begin;
        bvh.nodes[index].count = end - begin;
        return;
    }
    const int axis = max_axis(centroids.extent());
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(prims.begin() + begin, prims.begin() + mid, prims.begin() + end,
                     [axis](const BvhPrimitive& a, const BvhPrimitive& b) {
                         return a.bounds.center()[axis] < b.bounds.center()[axis];
                     });
    const uint32_t first = static_cast<uint32_t>(bvh.nodes.size());
    bvh.nodes[index].first = first;
    bvh.nodes[index].count = 0;
    bvh.nodes.resize(bvh.nodes.size() + 2);
    median_build(prims, begin, mid, bvh, first);
    median_build(prims, mid, end, bvh, first + 1);
}

TEST(BvhBuild, SahCostIsNoWorseThanAMedianSplit) {
    std::mt19937 rng(8);
    BvhBuildOptions options;
    for (int round = 0; round < 4; ++round) {
        std::vector<BvhPrimitive> prims = random_boxes(rng, 4000, 10, round % 2 ? 3.0f : 0.3f);
        if (round >= 2)  // clustered: most boxes in two small blobs, where a median split is poor
            for (size_t i = 0; i < prims.size(); i += 1)
                if (i % 10 != 0) {
                    const Vec3f shift = (i % 2 ? Vec3f{8, 8, 8} : Vec3f{-8, -8, -8});
                    const Vec3f c = prims[i].bounds.center();
                    prims[i].bounds.lower = prims[i].bounds.lower - c + c * 0.05f + shift;
                    prims[i].bounds.upper = prims[i].bounds.upper - c + c * 0.05f + shift;
                }
        Bvh median;
        median.nodes.resize(1);
        std::vector<BvhPrimitive> copy = prims;
        median_build(copy, 0, static_cast<uint32_t>(copy.size()), median, 0);
        median.prim_order.resize(copy.size());
        for (size_t i = 0; i < copy.size(); ++i) median.prim_order[i] = copy[i].id;
        check_tree(median, prims, 4);  // the reference tree itself is valid

        const Bvh sah = build_bvh(prims, options);
        const double sah_value = sah_cost(sah, options), median_value = sah_cost(median, options);
        EXPECT_LE(sah_value, median_value * 1.02) << "round " << round;
        EXPECT_GT(sah_value, 0);
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes, scenes and brute force

void offer(Hit& best, float t, float u, float v, uint32_t object, uint32_t prim) {
    if (is_closer(t, object, prim, best)) best = Hit{t, u, v, object, prim};
}

// A scene, and the triangles of each of its meshes decoded once from their groups (the groups
// hold the mesh's own corners: see LargeMeshBuiltInParallelMatchesBruteForce), for brute force.
struct Checked {
    const Scene& scene;
    std::vector<std::vector<GroupTriangle>> mesh_triangles;

    explicit Checked(const Scene& s) : scene(s), mesh_triangles(s.meshes.size()) {
        for (size_t m = 0; m < s.meshes.size(); ++m)
            for_each_group_triangle(s.meshes[m], [&](const GroupTriangle& tri, uint32_t) { mesh_triangles[m].push_back(tri); });
    }
};

// The closest hit by looking at every primitive of every object, with the same primitive tests
// and object-space rays as the scene, but no BVH.
Hit brute_force(const Checked& checked, const Ray& world_ray, float t_min) {
    const Scene& scene = checked.scene;
    Hit best;
    for (uint32_t id = 0; id < scene.instances.size(); ++id) {
        const Instance& inst = scene.instances[id];
        const Ray ray = inst.transform == kNoTransform ? world_ray
                                                       : to_object_space(scene.object_from_world[inst.transform], world_ray);
        float t = 0;
        TriangleHit h{};
        switch (inst.kind) {
            case ShapeKind::Sphere:
                if (intersect_sphere(scene.spheres[inst.shape], ray, t_min, t)) offer(best, t, 0, 0, id, 0);
                break;
            case ShapeKind::Plane:
                if (intersect_plane(scene.planes[inst.shape], ray, t_min, t)) offer(best, t, 0, 0, id, 0);
                break;
            case ShapeKind::Triangle: {
                const TriangleShape& tri = scene.triangles[inst.shape];
                if (intersect_triangle(make_watertight_ray(ray), tri.p0, tri.p1, tri.p2, t_min, h))
                    offer(best, h.t, h.u, h.v, id, 0);
                break;
            }
            case ShapeKind::Mesh: {
                const WatertightRay w = make_watertight_ray(ray);
                for (const GroupTriangle& tri : checked.mesh_triangles[inst.shape])
                    if (intersect_triangle(w, tri.p0, tri.p1, tri.p2, t_min, h)) offer(best, h.t, h.u, h.v, id, tri.id);
                break;
            }
            case ShapeKind::RevSurface: {
                RevSurfaceHit r;
                if (intersect_rev_surface(scene.rev_surfaces[inst.shape], ray, t_min, INFINITY, false, r))
                    offer(best, r.t, r.u, 0, id, r.piece);
                break;
            }
        }
    }
    return best;
}

// Compares the scene's answer with brute force, field by field; also the any-hit query right at
// the closest t (strictly below it nothing may be found, just above it something must).
// Returns false (after reporting a failure) on a mismatch for this ray.
bool expect_same_as_brute_force(const Checked& checked, const Ray& ray, float t_min, Hit* out = nullptr) {
    const Scene& scene = checked.scene;
    Hit fast;
    intersect(scene, ray, t_min, fast);
    const Hit slow = brute_force(checked, ray, t_min);
    if (out) *out = fast;
    const bool same = fast.is_hit() == slow.is_hit() &&
                      (!slow.is_hit() || (fast.t == slow.t && fast.object == slow.object && fast.prim == slow.prim &&
                                          fast.u == slow.u && fast.v == slow.v));
    EXPECT_TRUE(same) << describe(ray, t_min) << "\n  bvh:         " << describe(fast)
                      << "\n  brute force: " << describe(slow);
    if (!same) return false;
    if (fast.is_hit() && scene.instances[fast.object].kind == ShapeKind::Mesh) {
        // surface_at finds the triangle's corners in the group and lane that Hit::leaf and
        // Hit::lane name.
        const MeshShape& mesh = scene.meshes[scene.instances[fast.object].shape];
        const bool slot_ok = fast.leaf < mesh.groups.size() &&
                             fast.lane < group_triangle_count(&mesh.groups[fast.leaf]) &&
                             group_lane_of(&mesh.groups[fast.leaf], fast.prim) == fast.lane;
        EXPECT_TRUE(slot_ok) << describe(ray, t_min) << ": group " << fast.leaf << " lane " << fast.lane
                             << " does not hold triangle " << fast.prim;
        if (!slot_ok) return false;
    }
    bool occluded_right = true;
    if (slow.is_hit() && std::isfinite(slow.t)) {
        occluded_right = !occluded(scene, ray, t_min, slow.t) && occluded(scene, ray, t_min, std::nextafter(slow.t, INFINITY));
        EXPECT_TRUE(occluded_right) << describe(ray, t_min)
                                    << ": occluded(t_max) must be false at the closest t (exclusive), true just past it";
    } else if (!slow.is_hit()) {
        occluded_right = !occluded(scene, ray, t_min, INFINITY);
        EXPECT_TRUE(occluded_right) << describe(ray, t_min) << ": occluded although nothing is hit";
    }
    return occluded_right;
}

TEST(BvhTraversal, MatchesBruteForceOnRandomTriangleSoups) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    for (size_t count : {size_t{1}, size_t{7}, size_t{300}, size_t{3000}}) {
        SCOPED_TRACE("soup of " + std::to_string(count));
        const TriangleMesh mesh = soup(rng, count, 5, 2);
        const Scene scene = scene_of_mesh(mesh);
        const Checked checked_scene(scene);
        int hits = 0;
        for (int r = 0; r < 3000; ++r) {
            Ray ray;
            ray.origin = {u(rng) * 8, u(rng) * 8, u(rng) * 8};
            if (r % 2 == 0) {
                ray.direction = Vec3f{u(rng), u(rng), u(rng)} * (0.1f + 3 * u01(rng));  // random, not unit
            } else {
                ray.direction = shared_point(mesh, rng) - ray.origin;  // exactly at vertices and edges
            }
            if (r % 50 == 7) ray.direction.x = 0;  // axis-parallel components
            if (r % 50 == 8) ray.direction.y = ray.direction.z = 0;
            const float t_min = r % 5 == 0 ? 0.5f * u01(rng) : (r % 97 == 0 ? -INFINITY : 0.0f);
            Hit hit;
            if (!expect_same_as_brute_force(checked_scene, ray, t_min, &hit)) return;
            hits += hit.is_hit();
        }
        if (count >= 300) {
            EXPECT_GT(hits, 1000);  // the rays do find things
        }
    }
}

TEST(BvhTraversal, EveryRayFromInsideAClosedSphereMeshHits) {
    // A closed mesh has no holes: a ray from inside must hit it, whatever its direction, also when
    // aimed exactly at the mesh's shared vertices and edges (seams and poles included).
    std::mt19937 rng(22);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    const Vec3f centre{0.3f, -0.2f, 0.1f};
    const TriangleMesh mesh = sphere_mesh(centre, 2, 24, 48);
    const Scene scene = scene_of_mesh(mesh);
    const Checked checked_scene(scene);
    for (int r = 0; r < 20000; ++r) {
        Vec3f origin = centre + Vec3f{u(rng), u(rng), u(rng)} * 1.1f;
        if (r % 10 == 0) origin = centre;
        Vec3f direction;
        switch (r % 4) {
            case 0: direction = Vec3f{u(rng), u(rng), u(rng)} * (0.01f + 5 * u01(rng)); break;
            case 1: direction = shared_point(mesh, rng) - origin; break;
            case 2: direction = mesh.positions[std::uniform_int_distribution<size_t>(0, mesh.positions.size() - 1)(rng)] - origin; break;
            default: direction = Vec3f{0, u(rng) < 0 ? -1.0f : 1.0f, 0}; break;  // straight at the poles
        }
        if (length(direction) == 0) continue;
        const Ray ray{origin, direction};
        Hit hit;
        if (!expect_same_as_brute_force(checked_scene, ray, 0, &hit)) return;
        ASSERT_TRUE(hit.is_hit()) << describe(ray, 0) << " escaped through the closed mesh";
        // The hit is on the tessellated sphere: between the inscribed radius and 2.
        const float distance = length(ray.at(hit.t) - centre);
        EXPECT_GT(distance, 1.95f);
        EXPECT_LT(distance, 2.0001f);
    }
}

TEST(BvhTraversal, RaysAtTheSharedEdgesAndVerticesOfAGridHitAndMatchBruteForce) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    const int n = 48;
    const TriangleMesh mesh = grid_mesh(rng, n, 0.1f);
    const Scene scene = scene_of_mesh(mesh);
    const Checked checked_scene(scene);
    for (int r = 0; r < 10000; ++r) {
        // A vertex or edge point of the height field, seen from above at a steep enough angle.
        const Vec3f target = shared_point(mesh, rng);
        if (target.x <= 0 || target.y <= 0 || target.x >= n || target.y >= n) continue;  // border: one side only
        const Vec3f origin = target + Vec3f{u(rng) * 3, u(rng) * 3, 2 + 8 * u01(rng)};
        const Ray ray{origin, (target - origin) * (r % 3 == 0 ? 1.0f : 0.25f + 2 * u01(rng))};
        Hit hit;
        if (!expect_same_as_brute_force(checked_scene, ray, 0, &hit)) return;
        ASSERT_TRUE(hit.is_hit()) << describe(ray, 0) << " slipped through the grid";
        EXPECT_NEAR(length(ray.at(hit.t) - target), 0, 1e-3f);
    }
}

// A ray with a zero direction component whose origin lies exactly in a face plane of a box does
// meet the box (boxes are closed), yet the slab test computes (face − origin)·(1/1e-30) = 0 for
// that face, so the slab would end (or start) at t = 0 and the box be skipped: for direction +0
// the upper face, for −0 the lower one. Axis-aligned rays at integer coordinates (orthographic
// views of modelled geometry) meet this. build_bvh therefore stores every box a little larger
// than its contents (one float step, at least 1e-20), so such a ray lies strictly inside the slab
// of any box whose triangles it can touch.
TEST(BvhTraversal, RaysLyingInABoxFaceAreNotCulled) {
    // The box test on the box build_bvh stores for the unit cube, with rays lying in the cube's
    // faces x = 1 and x = 0.
    const Bounds3f unit = padded(box({0, 0, 0}, {1, 1, 1}));
    float t_entry = 0;
    for (const float dx : {0.0f, -0.0f}) {
        for (const float x : {0.0f, 1.0f}) {
            const BoxRay ray = make_box_ray({{x, 0.5f, 5}, {dx, 0, -1}}, 0);
            EXPECT_TRUE(intersect_box(unit, ray, INFINITY, t_entry)) << "face x = " << x << ", direction x = " << dx;
        }
    }

    // A unit square of two triangles, and a ray straight down its right edge: the brute-force
    // loop hits the edge (its edge function is exactly 0), the BVH misses the whole mesh.
    TriangleMesh square;
    square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    square.indices = {0, 1, 2, 0, 2, 3};
    const Scene square_scene = scene_of_mesh(square);
    const Checked checked_square_scene(square_scene);
    const Ray down_the_edge{{1, 0.5f, 5}, {0, 0, -1}};
    ASSERT_TRUE(brute_force(checked_square_scene, down_the_edge, 0).is_hit());
    expect_same_as_brute_force(checked_square_scene, down_the_edge, 0);
    expect_same_as_brute_force(checked_square_scene, {{0, 0.5f, 5}, {-0.0f, 0, -1}}, 0);  // left edge, −0

    // Straight down through every inner vertex and edge midpoint of a height field: every ray
    // hits, and the closest hit (ties: the lower triangle index) must be brute force's.
    std::mt19937 rng(23);
    const int n = 16;
    const Scene grid_scene = scene_of_mesh(grid_mesh(rng, n, 0.1f));
    const Checked checked_grid_scene(grid_scene);
    for (int j = 1; j < 2 * n; ++j)
        for (int i = 1; i < 2 * n; ++i)
            if (!expect_same_as_brute_force(checked_grid_scene, {{static_cast<float>(i) / 2, static_cast<float>(j) / 2, 5}, {0, 0, -1}}, 0))
                return;

    // From the centre of a closed sphere mesh to each of its vertices (the poles and the vertices
    // at φ = 0 and 180 degrees give zero components).
    const Vec3f centre{0.3f, -0.2f, 0.1f};
    const TriangleMesh ball = sphere_mesh(centre, 2, 24, 48);
    const Scene ball_scene = scene_of_mesh(ball);
    const Checked checked_ball_scene(ball_scene);
    for (const Vec3f& p : ball.positions)
        if (!expect_same_as_brute_force(checked_ball_scene, {centre, p - centre}, 0)) return;
}

TEST(BvhTraversal, AHitLiesNoNearerThanHalfTheCullSlackBeforeItsLeafsBox) {
    // leaf_floor(e) = e - |e|/2048: 100 - 0.048828125, exactly.
    EXPECT_EQ(leaf_floor(100.0f), 99.951171875f);
    EXPECT_EQ(leaf_floor(-100.0f), -100.048828125f);
    EXPECT_EQ(at_leaf_floor(99.96f, 100.0f), 99.96f);  // at or beyond the floor: as it is
    EXPECT_EQ(at_leaf_floor(99.951171875f, 100.0f), 99.951171875f);
    EXPECT_EQ(at_leaf_floor(std::nextafter(99.951171875f, 0.0f), 100.0f), 99.951171875f);
    EXPECT_EQ(at_leaf_floor(1.78f, 1.936f), leaf_floor(1.936f));
    EXPECT_EQ(at_leaf_floor(-1e30f, -INFINITY), -1e30f);  // no box was tested: no floor
    // A hit at or beyond the floor culls nothing in front of its own leaf: its cull distance
    // still reaches the leaf's entry, so the leaf is visited whatever was found first.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> exponent(-30, 30);
    for (int i = 0; i < 10000; ++i) {
        const float entry = std::pow(10.0f, exponent(rng));
        EXPECT_GE(cull_distance(leaf_floor(entry)), entry) << entry;
    }

    // traverse_bvh gives each leaf the entry intersect_box finds for the leaf's box: unit cubes
    // at z in [-1, 0] and [-6, -5], a ray down z from z = 5 enters them at t = 5 and t = 10.
    const std::vector<BvhPrimitive> prims{{box({0, 0, -1}, {1, 1, 0}), 0}, {box({0, 0, -6}, {1, 1, -5}), 1}};
    const Bvh bvh = build_bvh(prims, BvhBuildOptions{});
    ASSERT_EQ(bvh.nodes.size(), 3u);
    const BoxRay ray = make_box_ray({{0.5f, 0.5f, 5}, {0, 0, -1}}, 0);
    std::vector<std::pair<uint32_t, float>> leaves;  // (first primitive, t_entry) as visited
    traverse_bvh(bvh, ray, [] { return INFINITY; }, [&](uint32_t first, uint32_t, float t_entry) {
        leaves.emplace_back(first, t_entry);
        return false;
    });
    ASSERT_EQ(leaves.size(), 2u);
    for (const auto& [first, t_entry] : leaves) {
        const BvhNode& leaf = bvh.nodes[bvh.nodes[1].first == first ? 1 : 2];
        float expected = 0;
        ASSERT_TRUE(intersect_box(leaf.bounds, ray, INFINITY, expected));
        EXPECT_EQ(t_entry, expected);
        EXPECT_NEAR(t_entry, bvh.prim_order[first] == 0 ? 5.0f : 10.0f, 1e-4f);
    }
    EXPECT_EQ(bvh.prim_order[leaves[0].first], 0u);  // nearer first
}

TEST(BvhTraversal, ExactTiesGoToTheLowerTriangleIndex) {
    // Each of the first 200 triangles is listed again (same vertices, same order) at index
    // 200 + i: the copy gives exactly the same t, so is_closer must keep the original.
    std::mt19937 rng(24);
    std::uniform_real_distribution<float> u(-1, 1);
    TriangleMesh mesh = soup(rng, 200, 3, 2);
    const size_t original = mesh.triangle_count();
    for (size_t i = 0; i < original * 3; ++i) mesh.indices.push_back(mesh.indices[i]);
    const Scene scene = scene_of_mesh(mesh);
    const Checked checked_scene(scene);
    int hits = 0;
    for (int r = 0; r < 3000; ++r) {
        const Vec3f origin{u(rng) * 6, u(rng) * 6, u(rng) * 6};
        const Ray ray{origin, (r % 2 ? shared_point(mesh, rng) : Vec3f{u(rng), u(rng), u(rng)} * 3) - origin};
        Hit hit;
        if (!expect_same_as_brute_force(checked_scene, ray, 0, &hit)) return;
        if (hit.is_hit()) {
            ++hits;
            EXPECT_LT(hit.prim, original) << "a duplicate won the tie: " << describe(hit);
        }
    }
    EXPECT_GT(hits, 500);
}

TEST(SceneIntersect, MatchesBruteForceOverMixedTransformedObjects) {
    // Objects in file order: 0 a soup mesh, 1 the same mesh again (exact ties: object 0 must
    // win), 2 a sphere, 3 a triangle, 4 the closed sphere mesh under a rotation, a non-uniform
    // scale and a translation, 5 a transformed sphere, 6 a plane under a transform, 7 the grid
    // mesh rotated, 8 a triangle equal to one of the soup's triangles (ties with object 0).
    std::mt19937 rng(25);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    SceneDesc desc = scene_desc();
    const TriangleMesh soup_mesh = soup(rng, 400, 3, 1.5f);
    const TriangleMesh ball = sphere_mesh({0, 0, 0}, 1, 12, 24);
    const TriangleMesh grid = grid_mesh(rng, 8, 0.2f);
    const int soup_index = add_mesh(desc, soup_mesh);
    const int ball_index = add_mesh(desc, ball);
    const int grid_index = add_mesh(desc, grid);
    std::vector<ObjectDesc>& objects = desc.root->children;
    objects.push_back(mesh_object(soup_index));
    objects.push_back(mesh_object(soup_index));
    ObjectDesc sphere;
    sphere.kind = ObjectDesc::Kind::Sphere;
    sphere.material = 0;
    sphere.sphere = {{1, 1, 1}, 1.2f};
    objects.push_back(sphere);
    ObjectDesc triangle;
    triangle.kind = ObjectDesc::Kind::Triangle;
    triangle.material = 0;
    triangle.vertices[0] = {-4, -4, -1};
    triangle.vertices[1] = {4, -4, -1};
    triangle.vertices[2] = {0, 4, -1.5f};
    objects.push_back(triangle);
    const Mat4 ball_transform =
        Mat4::translate({2, -1, 0.5f}) * Mat4::rotate({1, 2, 3}, 40) * Mat4::scale({2, 0.7f, 1.3f});
    objects.push_back(transform(ball_transform, mesh_object(ball_index)));
    ObjectDesc ellipsoid = sphere;
    ellipsoid.sphere = {{0, 0, 0}, 1};
    objects.push_back(transform(Mat4::translate({-2, 2, 1}) * Mat4::scale({0.5f, 2, 1}), ellipsoid));
    ObjectDesc plane;
    plane.kind = ObjectDesc::Kind::Plane;
    plane.material = 0;
    plane.plane = {{0, 0, 2}, -10};  // z = −5, normal not unit
    objects.push_back(transform(Mat4::rotate_x(10), plane));
    objects.push_back(transform(Mat4::translate({-4, -4, 2}) * Mat4::rotate_z(30) * Mat4::scale({0.5f, 0.5f, 1}),
                                  mesh_object(grid_index)));
    ObjectDesc copy = triangle;
    copy.vertices[0] = corner(soup_mesh, 5, 0);
    copy.vertices[1] = corner(soup_mesh, 5, 1);
    copy.vertices[2] = corner(soup_mesh, 5, 2);
    objects.push_back(copy);
    const Scene scene = scene_with(std::move(desc));
    const Checked checked_scene(scene);
    ASSERT_EQ(scene.instances.size(), 9u);

    std::vector<int> hits_per_object(9, 0);
    for (int r = 0; r < 6000; ++r) {
        Ray ray;
        ray.origin = {u(rng) * 7, u(rng) * 7, u(rng) * 7};
        switch (r % 4) {
            case 0:
                ray.direction = Vec3f{u(rng), u(rng), u(rng)} * (0.1f + 2 * u01(rng));
                break;
            case 1:
                ray.direction = shared_point(soup_mesh, rng) - ray.origin;
                break;
            case 2:  // at the transformed ball's vertices and edges, in world space
                ray.direction = transform_point(ball_transform, shared_point(ball, rng)) - ray.origin;
                break;
            default:  // at the 5th soup triangle, which object 8 duplicates
                ray.direction = (corner(soup_mesh, 5, 0) + corner(soup_mesh, 5, 1) + corner(soup_mesh, 5, 2)) * (1.0f / 3) +
                                Vec3f{u(rng), u(rng), u(rng)} * 0.05f - ray.origin;
        }
        const float t_min = r % 7 == 0 ? u01(rng) : 0.0f;
        Hit hit;
        if (!expect_same_as_brute_force(checked_scene, ray, t_min, &hit)) return;
        if (hit.is_hit()) ++hits_per_object[hit.object];
    }
    // Every object but the shadowed duplicates is seen; ties always go to the first in file order.
    EXPECT_EQ(hits_per_object[1], 0) << "object 1 duplicates object 0";
    EXPECT_EQ(hits_per_object[8], 0) << "object 8 duplicates a triangle of object 0";
    for (int object : {0, 2, 3, 4, 5, 6, 7}) EXPECT_GT(hits_per_object[object], 0) << "object " << object;
}

TEST(SceneIntersect, EmptySceneHasNoHits) {
    const Scene scene = scene_with(scene_desc());
    Hit hit;
    intersect(scene, {{0, 0, 0}, {0, 0, -1}}, 0, hit);
    EXPECT_FALSE(hit.is_hit());
    EXPECT_FALSE(occluded(scene, {{0, 0, 0}, {0, 0, -1}}, 0, INFINITY));
}

// ---------------------------------------------------------------------------------------------
// Large meshes: the parallel build path

// A mesh's wide BVH and groups: every triangle of the mesh in exactly one group of one leaf, with
// its exact corners, inside the leaf's box; groups within their limits.
void check_mesh_shape(const MeshShape& shape, const TriangleMesh& mesh) {
    EXPECT_EQ(shape.triangle_count, mesh.triangle_count());
    EXPECT_TRUE(shape.mesh.positions.empty() && shape.mesh.indices.empty()) << "the mesh should be dropped";
    std::vector<int> seen(mesh.triangle_count(), 0);
    ASSERT_FALSE(shape.bvh.empty());
    for (const WideBvhNode& node : shape.bvh.nodes)
        for (uint32_t slot = 0; slot < node.child_count; ++slot) {
            if (!is_wide_leaf(node.child[slot])) continue;
            const Bounds3f box = child_bounds(node, slot);
            const GroupBlock* group = &shape.groups[node.child[slot] & kWidePayloadMask];
            for (;; group = next_group(group)) {
                expect_group_of(group, mesh, seen);
                for (uint32_t lane = 0; lane < group_triangle_count(group); ++lane) {
                    const GroupTriangle tri = group_triangle(group, lane);
                    Bounds3f b;
                    for (const Vec3f& p : {tri.p0, tri.p1, tri.p2}) b.grow(p);
                    EXPECT_TRUE(contains(box, b)) << "triangle " << tri.id << " outside its leaf";
                }
                if (group_ends_leaf(group)) break;
            }
        }
    for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "triangle " << i << " is in " << seen[i] << " groups";
}

bool same_nodes(const Bvh& a, const Bvh& b) {
    if (a.nodes.size() != b.nodes.size() || a.prim_order != b.prim_order) return false;
    for (size_t i = 0; i < a.nodes.size(); ++i)
        if (!same_bounds(a.nodes[i].bounds, b.nodes[i].bounds) || a.nodes[i].first != b.nodes[i].first ||
            a.nodes[i].count != b.nodes[i].count)
            return false;
    return true;
}

TEST(BvhBuild, TreeIsIdenticalForAnyThreadCount) {
    // build_bvh.cpp builds subtrees of 16384 primitives or more as separate pieces (on their own
    // threads when there are spare ones); 70000 primitives make nested pieces.
    std::mt19937 rng(26);
    std::vector<BvhPrimitive> prims = random_boxes(rng, 70000, 50, 2);
    for (size_t i = 0; i < 20000; ++i) prims[i].bounds = prims[i % 7].bounds;  // many equal boxes too
    BvhBuildOptions options;
    options.threads = 1;
    const Bvh one = build_bvh(prims, options);
    check_tree(one, prims, options.max_leaf_size);
    for (int threads : {2, 4}) {
        options.threads = threads;
        const Bvh many = build_bvh(prims, options);
        EXPECT_TRUE(same_nodes(one, many)) << threads << " threads build a different tree";
    }
}

TEST(BvhTraversal, LargeMeshBuiltInParallelMatchesBruteForce) {
    std::mt19937 rng(27);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    const TriangleMesh mesh = soup(rng, 40000, 20, 1.5f);
    const Scene scene = scene_of_mesh(mesh, 4);
    const Checked checked_scene(scene);
    const Scene serial = scene_of_mesh(mesh, 1);
    ASSERT_EQ(scene.meshes.size(), 1u);
    const MeshShape& shape = scene.meshes[0];
    const MeshShape& serial_shape = serial.meshes[0];
    ASSERT_EQ(shape.bvh.nodes.size(), serial_shape.bvh.nodes.size());
    for (size_t i = 0; i < shape.bvh.nodes.size(); ++i) {
        const WideBvhNode &a = shape.bvh.nodes[i], &b = serial_shape.bvh.nodes[i];
        ASSERT_TRUE(std::memcmp(a.bounds, b.bounds, sizeof a.bounds) == 0 &&
                    std::memcmp(a.child, b.child, sizeof a.child) == 0 && a.child_count == b.child_count)
            << "node " << i << " differs between 4 threads and 1";
    }
    ASSERT_EQ(shape.groups.size(), serial_shape.groups.size());
    EXPECT_EQ(std::memcmp(shape.groups.data(), serial_shape.groups.data(), shape.groups.size() * sizeof(GroupBlock)), 0);
    check_mesh_shape(shape, mesh);
    int hits = 0;
    for (int r = 0; r < 300; ++r) {
        const Vec3f origin{u(rng) * 25, u(rng) * 25, u(rng) * 25};
        const Vec3f direction = r % 2 ? shared_point(mesh, rng) - origin : Vec3f{u(rng), u(rng), u(rng)};
        Hit hit;
        if (!expect_same_as_brute_force(checked_scene, {origin, direction}, 0, &hit)) return;
        hits += hit.is_hit();
    }
    EXPECT_GT(hits, 150);
}

}  // namespace
}  // namespace raycast
