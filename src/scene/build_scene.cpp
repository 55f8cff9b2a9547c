#include "scene/build_scene.h"

#include <algorithm>
#include <cmath>
#include <new>

#include "base/limits.h"
#include "base/parallel.h"
#include "bvh/build_bvh.h"
#include "geometry/triangle.h"
#include "bvh/wide_bvh.h"
#include "geometry/triangle_groups.h"
#include "scene/intersect_packet.h"

namespace raycast {

namespace {

Diagnostic error_at(const SourceLocation& location, std::string message) {
    return Diagnostic{Severity::Error, location, std::move(message), ""};
}

// The message for a position past kMaxCoordinate, after `where` says whose and how far ("this
// plane lies 2e+19 from the origin"): the camera, lights, objects and planes have one limit.
std::string past_coordinate_limit(const std::string& where, const char* remedy = "scale the scene down") {
    return where + string_printf(", beyond raycast's limit of %g (float arithmetic would overflow): %s",
                                 double(kMaxCoordinate), remedy);
}

// Widens a box by a relative margin, so that rounding in the object-space tests (with a
// float inverse matrix) cannot put a hit just outside the box the BVH holds.
Bounds3f pad(Bounds3f b) {
    for (int axis = 0; axis < 3; ++axis) {
        const float margin = (std::fabs(b.lower[axis]) + std::fabs(b.upper[axis])) * (1.0f / 65536) + 1e-30f;
        b.lower[axis] -= margin;
        b.upper[axis] += margin;
    }
    return b;
}

Bounds3f transform_bounds(const Mat4& m, const Bounds3f& b) {
    Bounds3f result;
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3f p{(corner & 1) ? b.upper.x : b.lower.x, (corner & 2) ? b.upper.y : b.lower.y,
                      (corner & 4) ? b.upper.z : b.lower.z};
        result.grow(transform_point(m, p));
    }
    return result;
}

// The exact box of an ellipsoid M·(sphere): along axis i it reaches r·|row i of M's 3×3 part|.
Bounds3f transformed_sphere_bounds(const Mat4& m, const Sphere& sphere) {
    const Vec3f center = transform_point(m, sphere.center);
    Bounds3f result;
    for (int i = 0; i < 3; ++i) {
        // Squared in float: check_scale holds every entry within 1e18, so a row's squares stay below 3e36.
        const float reach = sphere.radius * std::sqrt(m.m[i][0] * m.m[i][0] + m.m[i][1] * m.m[i][1] + m.m[i][2] * m.m[i][2]);
        result.lower[i] = center[i] - reach;
        result.upper[i] = center[i] + reach;
    }
    return result;
}

// A wide BVH's leaves in leaf order (increasing first primitive), and where each is referred to.
struct LeafRef {
    uint32_t node, slot, first, count;
};

std::vector<LeafRef> leaves_in_order(const WideBvh& bvh) {
    std::vector<LeafRef> leaves;
    if (bvh.empty()) return leaves;
    // Depth first, slots in order: the collapse keeps the binary tree's left-to-right order, so
    // this meets the leaves in the order of their primitive ranges.
    struct Item {
        uint32_t node, slot;
    };
    std::vector<Item> stack{{0, 0}};
    while (!stack.empty()) {
        Item& item = stack.back();
        const WideBvhNode& node = bvh.nodes[item.node];
        if (item.slot == node.child_count) {
            stack.pop_back();
            continue;
        }
        const uint32_t slot = item.slot++;
        const uint32_t child = node.child[slot];
        if (is_wide_leaf(child))
            leaves.push_back({item.node, slot, child & kWidePayloadMask, node.prim_count[slot]});
        else
            stack.push_back({child, 0});
    }
    return leaves;
}

// The mesh's triangles as groups, leaf by leaf in leaf order; each leaf's payload becomes the
// block of its first group. Two passes over chunks of leaves, on several threads: sizes, then the
// groups, each written straight into its place (the result does not depend on the threads).
LargeVector<GroupBlock> build_triangle_groups(const TriangleMesh& mesh, WideBvh& bvh, int threads) {
    const std::vector<LeafRef> leaves = leaves_in_order(bvh);
    constexpr size_t kLeavesPerTask = 2048;
    const size_t tasks = (leaves.size() + kLeavesPerTask - 1) / kLeavesPerTask;
    std::vector<uint32_t> first_block(leaves.size() + 1, 0);
    parallel_for(tasks, threads, [&](size_t task, int) {
        for (size_t i = task * kLeavesPerTask; i < std::min(leaves.size(), (task + 1) * kLeavesPerTask); ++i)
            first_block[i + 1] = triangle_group_blocks(mesh, &bvh.prim_order[leaves[i].first], leaves[i].count);
    });
    for (size_t i = 0; i < leaves.size(); ++i) {
        // A leaf's payload is 31 bits: 2^31 blocks (32 GiB) of groups per mesh.
        if (first_block[i + 1] > kWidePayloadMask - first_block[i]) throw std::bad_alloc();
        first_block[i + 1] += first_block[i];
    }
    LargeVector<GroupBlock> groups;
    if (leaves.empty()) return groups;
    groups.resize(first_block.back() + kGroupPaddingBlocks);
    parallel_for(tasks, threads, [&](size_t task, int) {
        for (size_t i = task * kLeavesPerTask; i < std::min(leaves.size(), (task + 1) * kLeavesPerTask); ++i) {
            const LeafRef& leaf = leaves[i];
            write_triangle_groups(mesh, &bvh.prim_order[leaf.first], leaf.count, &groups[first_block[i]]);
            bvh.nodes[leaf.node].child[leaf.slot] = kWideLeafFlag | first_block[i];
        }
    });
    return groups;
}

Bounds3f sphere_bounds(const Sphere& sphere) {
    const Vec3f reach{sphere.radius, sphere.radius, sphere.radius};
    return {sphere.center - reach, sphere.center + reach};
}

class SceneBuilder {
public:
    SceneBuilder(SceneDesc& desc, const SceneBuildOptions& options) : desc_(desc), options_(options) {}

    Scene build() {
        scene_.conventions = options_.conventions;
        make_camera_and_lights();
        mesh_shape_of_.assign(desc_.meshes.size(), -1);
        if (desc_.root) add_object(*desc_.root, Mat4::identity(), false);
        if (!errors_.empty()) fail(std::move(errors_));
        build_instance_bvh();
        find_sole_mesh();
        return std::move(scene_);
    }

private:
    // Errors found here show their line of the scene file and a caret, as the parser's do.
    [[noreturn]] void fail(std::vector<Diagnostic> errors) const {
        attach_source_lines(errors, desc_.source_text, desc_.file);
        throw InputError(std::move(errors));
    }

    void make_camera_and_lights() {
        if (!desc_.camera) fail({error_at({desc_.file, 0, 0}, "the scene has no camera")});
        const CameraDesc& camera = *desc_.camera;
        const int width = options_.width > 0 ? options_.width : camera.width;
        const int height = options_.height > 0 ? options_.height : camera.height;
        if (width <= 0 || height <= 0)
            fail({error_at(camera.location,
                           "the camera gives no image size: add width and height, or use --size WxH (-size W H)")});
        // Rays start at the camera: beyond the objects' limit, the tests' products overflow as they
        // would for an object there (found by fuzz_render_pipeline: a camera at 1e30 gave NaN pixels).
        const float reach = max_abs(camera.center);
        if (!(reach <= kMaxCoordinate))
            fail({error_at(camera.location,
                           past_coordinate_limit(string_printf("the camera is at coordinates of %g", double(reach))))});
        scene_.camera = make_camera(camera, width, height, options_.conventions);
        scene_.background = desc_.background;
        if (desc_.ambient)
            scene_.ambient = *desc_.ambient;
        else if (options_.conventions.ambient_without_lights && !desc_.has_lights_block)
            scene_.ambient = {1, 1, 1};
        for (const LightDesc& l : desc_.lights) {
            // A point light's distance to a hit is squared on the way to its direction: from past
            // the limit it overflows, and the light silently lit nothing.
            const float light_reach = max_abs(l.position);
            if (l.kind == LightDesc::Kind::Point && !(light_reach <= kMaxCoordinate))
                errors_.push_back(error_at(
                    l.location, past_coordinate_limit(string_printf("this point light is at coordinates of %g",
                                                                    double(light_reach)))));
            Light light;
            light.kind = l.kind == LightDesc::Kind::Directional ? Light::Kind::Directional : Light::Kind::Point;
            light.direction = normalize_any_length(l.direction);
            light.position = l.position;
            light.color = l.color;
            light.attenuation = l.attenuation;
            scene_.lights.push_back(light);
        }
        for (const MaterialDesc& m : desc_.materials) {
            Material material;
            material.diffuse = m.diffuse;
            material.specular = m.specular;
            material.shininess = m.shininess ? *m.shininess : options_.conventions.default_shininess;
            material.reflective = m.reflective;
            material.transparent = m.transparent;
            material.index_of_refraction = m.index_of_refraction;
            scene_.materials.push_back(material);
        }
    }

    // world_from_object: the product of the enclosing transforms; `moved`: whether it is not
    // the identity (kept apart so that an identity Transform costs nothing at render time).
    void add_object(const ObjectDesc& object, const Mat4& world_from_object, bool moved) {
        switch (object.kind) {
            case ObjectDesc::Kind::Group:
                for (const ObjectDesc& child : object.children) add_object(child, world_from_object, moved);
                return;
            case ObjectDesc::Kind::Transform: {
                const Mat4 combined = world_from_object * object.world_from_object;
                const bool combined_moved = moved || !object.world_from_object.is_identity();
                if (combined_moved) {
                    bool invertible = false;
                    const Mat4 object_from_world = inverse(combined, &invertible);
                    // A product too large for float (1e20 twice) cannot be inverted either: it is
                    // said as the scale it is; a flat one (a zero scale, or 1e-25 twice, which is
                    // 0 in float) as what it is.
                    if (!check_scale(object, combined, invertible ? &object_from_world : nullptr)) return;
                    if (!invertible) {
                        errors_.push_back(error_at(object.location,
                                                   "this transform cannot be inverted (it squashes space flat): "
                                                   "check for a zero scale, or scales whose product is 0 in float"));
                        return;
                    }
                }
                for (const ObjectDesc& child : object.children) add_object(child, combined, combined_moved);
                return;
            }
            case ObjectDesc::Kind::Curve:
                return;  // a curve alone is not a surface: nothing to see (the parser says so)
            default:
                add_primitive(object, world_from_object, moved);
        }
    }

    void add_primitive(const ObjectDesc& object, const Mat4& world_from_object, bool moved) {
        // A mesh whose file was not found, left out on request (--allow-missing-meshes).
        if (object.kind == ObjectDesc::Kind::TriangleMesh && object.mesh < 0) return;
        Instance instance;
        instance.material = static_cast<uint32_t>(object.material);
        Mat4 object_from_world;
        if (moved) {
            object_from_world = inverse(world_from_object);
            if (object.kind != ObjectDesc::Kind::Plane) {
                instance.transform = static_cast<uint32_t>(scene_.object_from_world.size());
                scene_.object_from_world.push_back(object_from_world);
            }
        }
        const uint32_t id = static_cast<uint32_t>(scene_.instances.size());
        switch (object.kind) {
            case ObjectDesc::Kind::Sphere:
                instance.kind = ShapeKind::Sphere;
                instance.shape = static_cast<uint32_t>(scene_.spheres.size());
                scene_.spheres.push_back(object.sphere);
                bounds_.push_back({pad(moved ? transformed_sphere_bounds(world_from_object, object.sphere)
                                             : sphere_bounds(object.sphere)),
                                   id});
                check_extent(object, bounds_.back().bounds, moved ? sphere_bounds(object.sphere) : Bounds3f{});
                break;
            case ObjectDesc::Kind::Plane: {
                // n·(M⁻¹p) = d for object-space points is the world plane (M⁻ᵀn)·p = d − n·(M⁻¹'s
                // translation): the same set of points, so the same t along any ray.
                Plane plane = object.plane;
                if (moved) {
                    const Mat4& a = object_from_world;
                    const Vec3f n = plane.normal;
                    plane.normal = {a.m[0][0] * n.x + a.m[1][0] * n.y + a.m[2][0] * n.z,
                                    a.m[0][1] * n.x + a.m[1][1] * n.y + a.m[2][1] * n.z,
                                    a.m[0][2] * n.x + a.m[1][2] * n.y + a.m[2][2] * n.z};
                    plane.offset = plane.offset - dot(n, Vec3f{a.m[0][3], a.m[1][3], a.m[2][3]});
                }
                check_plane_distance(object, plane);
                instance.kind = ShapeKind::Plane;
                instance.shape = static_cast<uint32_t>(scene_.planes.size());
                scene_.planes.push_back(plane);
                scene_.plane_instances.push_back(id);
                break;
            }
            case ObjectDesc::Kind::Triangle: {
                instance.kind = ShapeKind::Triangle;
                instance.shape = static_cast<uint32_t>(scene_.triangles.size());
                const TriangleShape tri{object.vertices[0], object.vertices[1], object.vertices[2]};
                scene_.triangles.push_back(tri);
                Bounds3f b, own;
                for (const Vec3f& p : object.vertices) {
                    b.grow(moved ? transform_point(world_from_object, p) : p);
                    if (moved) own.grow(p);
                }
                // Out of the BVH, a triangle with no area is never tested, so never hit (triangle.h).
                if (!is_degenerate_triangle(tri.p0, tri.p1, tri.p2)) bounds_.push_back({pad(b), id});
                check_extent(object, b, own);
                break;
            }
            case ObjectDesc::Kind::RevSurface: {
                instance.kind = ShapeKind::RevSurface;
                instance.shape = static_cast<uint32_t>(scene_.rev_surfaces.size());
                scene_.rev_surfaces.push_back(make_rev_surface(object.curve));
                const RevSurface& surface = scene_.rev_surfaces.back();
                if (surface.nodes.empty()) return;  // every piece a point or on the axis: never hit
                // Tight even when rotated: the boxes of the cylinders around the monotone pieces.
                bounds_.push_back({pad(rev_surface_bounds(surface, world_from_object)), id});
                check_extent(object, bounds_.back().bounds,
                             moved ? rev_surface_bounds(surface, Mat4::identity()) : Bounds3f{});
                break;
            }
            case ObjectDesc::Kind::TriangleMesh: {
                instance.kind = ShapeKind::Mesh;
                instance.shape = mesh_shape(object.mesh);
                const Bounds3f local = scene_.meshes[instance.shape].bounds;
                if (!local.is_empty()) {
                    bounds_.push_back({pad(moved ? transform_bounds(world_from_object, local) : local), id});
                    check_extent(object, bounds_.back().bounds, moved ? local : Bounds3f{});
                }
                break;
            }
            default:
                return;
        }
        scene_.instances.push_back(instance);
    }

    // Objects are tested in their own space, where a ray's direction is M⁻¹d: a scale past
    // kMaxCoordinate either way squares it out of float's range, below it when M grows (a sphere
    // of radius 1e-25 under UniformScale 1e25 vanished) and above it when M shrinks. The scale is
    // the largest entry of the linear part of M (or the inverse of M⁻¹'s), the transforms around
    // this one included. True when it is within.
    // `object_from_world` is null when M could not be inverted: only M's own scale is checked then.
    bool check_scale(const ObjectDesc& object, const Mat4& world_from_object, const Mat4* object_from_world) {
        auto largest_linear_entry = [](const Mat4& m) {
            float largest = 0;
            for (int row = 0; row < 3; ++row)
                for (int column = 0; column < 3; ++column) largest = std::fmax(largest, std::fabs(m.m[row][column]));
            return largest;
        };
        const float grows = largest_linear_entry(world_from_object);
        const float shrinks = object_from_world ? largest_linear_entry(*object_from_world) : 0.0f;
        if (grows <= kMaxCoordinate && shrinks <= kMaxCoordinate) {
            scene_.worst_transform_condition = std::fmax(scene_.worst_transform_condition, grows * shrinks);
            return true;
        }
        const bool up = !(grows <= kMaxCoordinate);  // an overflow to infinity too
        const std::string by = up && !std::isfinite(grows) ? std::string("more than float holds")
                                                           : string_printf("%g", up ? double(grows) : 1 / double(shrinks));
        errors_.push_back(error_at(
            object.location,
            string_printf("this transform (with those around it) scales by %s, %s raycast's limit of %g (float "
                          "arithmetic would %s): %s",
                          by.c_str(), up ? "beyond" : "below", up ? double(kMaxCoordinate) : 1 / double(kMaxCoordinate),
                          up ? "underflow" : "overflow",
                          up ? "give the objects in it larger coordinates and it a smaller scale"
                             : "give the objects in it smaller coordinates and it a larger scale")));
        return false;
    }

    // Past kMaxCoordinate the float products in the intersection tests overflow and objects would
    // silently vanish: refuse them where they are written. An object under a Transform is tested
    // in its own space, so its own coordinates (`object_bounds`; empty when it has no Transform)
    // are held to the limit too: a sphere of radius 1e20 under UniformScale 1e-20 reached 1 in
    // the world and vanished.
    void check_extent(const ObjectDesc& object, const Bounds3f& world_bounds, const Bounds3f& object_bounds = {}) {
        auto largest_coordinate = [](const Bounds3f& b) {
            return b.is_empty() ? 0.0f : std::fmax(max_abs(b.lower), max_abs(b.upper));
        };
        const float world = largest_coordinate(world_bounds);
        const float own = largest_coordinate(object_bounds);
        if (!(world <= kMaxCoordinate))
            errors_.push_back(error_at(
                object.location,
                past_coordinate_limit(string_printf("this object reaches coordinates of %g", double(world)))));
        else if (!(own <= kMaxCoordinate))
            errors_.push_back(error_at(
                object.location,
                past_coordinate_limit(
                    string_printf("this object reaches coordinates of %g in its own space (before its Transform)",
                                  double(own)),
                    "give it smaller coordinates and its Transform a larger scale")));
    }

    // A plane has no extent, but its points are as far from the origin as it is, and beyond
    // kMaxCoordinate their distance to a point light, squared, overflows: a floor at 1e19 below
    // the camera was drawn black. n·p = d with n not of unit length (a scaled plane) lies |d|/|n|
    // from the origin, found in double so that neither overflows.
    void check_plane_distance(const ObjectDesc& object, const Plane& plane) {
        const double nx = plane.normal.x, ny = plane.normal.y, nz = plane.normal.z;
        const double normal_length = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (!(normal_length > 0)) return;  // never hit (intersect_plane divides by n·d)
        const double distance = std::fabs(double{plane.offset}) / normal_length;
        if (!(distance <= double{kMaxCoordinate}))
            errors_.push_back(error_at(
                object.location, past_coordinate_limit(string_printf("this plane lies %g from the origin", distance))));
    }

    uint32_t mesh_shape(int mesh_index) {
        int& shape = mesh_shape_of_[static_cast<size_t>(mesh_index)];
        if (shape < 0) {
            shape = static_cast<int>(scene_.meshes.size());
            scene_.meshes.push_back(
                build_mesh_shape(std::move(desc_.meshes[static_cast<size_t>(mesh_index)].mesh), options_.threads));
        }
        return static_cast<uint32_t>(shape);
    }

    // A scene of one world-space mesh and nothing else (SoleMesh). Its queries then do what the
    // two-level walk would: the instance BVH is one leaf (whose box it does not test), and no
    // plane waits outside it.
    void find_sole_mesh() {
        const Bvh& bvh = scene_.instance_bvh;
        if (!scene_.plane_instances.empty() || bvh.nodes.size() != 1 || bvh.nodes[0].count != 1) return;
        const uint32_t id = bvh.prim_order[bvh.nodes[0].first];
        const Instance& instance = scene_.instances[id];
        if (instance.kind != ShapeKind::Mesh || instance.transform != kNoTransform) return;
        if (scene_.meshes[instance.shape].bvh.empty()) return;
        const MeshRayKernel& kernel = best_mesh_ray_kernel();
        scene_.sole_mesh = {kernel.intersect, kernel.occluded, id, instance.shape};
    }

    void build_instance_bvh() {
        for (const BvhPrimitive& primitive : bounds_) scene_.bounds.grow(primitive.bounds);
        BvhBuildOptions bvh_options;
        bvh_options.max_leaf_size = 2;
        bvh_options.threads = options_.threads;
        scene_.instance_bvh = build_bvh(std::move(bounds_), bvh_options);
        test_cheap_shapes_first();
    }

    // A leaf's instances are tested in turn, each culled by the nearest hit found so far, so a
    // sphere or a triangle tested first lets the BVH of a mesh (or a surface of revolution)
    // behind it stop at its root, where tested the other way round the mesh is searched to its
    // own hit for nothing: a mesh inside a glass ball cost 1.8x the render time when it came
    // first in the file. The order changes no hit: is_closer() breaks ties by object id.
    void test_cheap_shapes_first() {
        auto costly = [this](uint32_t id) {
            const ShapeKind kind = scene_.instances[id].kind;
            return kind == ShapeKind::Mesh || kind == ShapeKind::RevSurface;
        };
        Bvh& bvh = scene_.instance_bvh;
        for (const BvhNode& node : bvh.nodes) {
            if (!node.is_leaf()) continue;
            auto first = bvh.prim_order.begin() + node.first;
            std::stable_partition(first, first + node.count, [&](uint32_t id) { return !costly(id); });
        }
    }

    SceneDesc& desc_;
    const SceneBuildOptions& options_;
    Scene scene_;
    std::vector<int> mesh_shape_of_;
    std::vector<BvhPrimitive> bounds_;
    std::vector<Diagnostic> errors_;
};

// How many levels deep the object tree goes, found without recursion (the tree may be as deep
// as the nesting limit).
size_t tree_depth(const ObjectDesc& root) {
    size_t deepest = 0;
    std::vector<std::pair<const ObjectDesc*, size_t>> pending{{&root, 1}};
    while (!pending.empty()) {
        const auto [object, depth] = pending.back();
        pending.pop_back();
        deepest = std::max(deepest, depth);
        for (const ObjectDesc& child : object->children) pending.push_back({&child, depth + 1});
    }
    return deepest;
}

}  // namespace

Scene build_scene(SceneDesc desc, const SceneBuildOptions& options) {
    // The builder walks the object tree recursively, one level per nested group or transform:
    // a deep tree gets a stack that holds it in any build.
    Scene scene;
    call_with_stack_for_depth(desc.root ? tree_depth(*desc.root) : 0, [&] {
        scene = SceneBuilder(desc, options).build();
        desc = SceneDesc{};  // the tree's recursive destructor runs here too
    });
    return scene;
}

MeshShape build_mesh_shape(TriangleMesh mesh, int threads) {
    MeshShape shape;
    shape.triangle_count = mesh.triangle_count();
    {
        std::vector<BvhPrimitive> primitives(shape.triangle_count);
        for (size_t i = 0; i < shape.triangle_count; ++i) {
            const uint32_t* corner = &mesh.indices[3 * i];
            const Vec3f p0 = mesh.positions[corner[0]], p1 = mesh.positions[corner[1]], p2 = mesh.positions[corner[2]];
            Bounds3f b;
            // An empty box keeps a triangle with no area out of the tree, so it is never hit (triangle.h).
            if (!is_degenerate_triangle(p0, p1, p2)) {
                b.grow(p0);
                b.grow(p1);
                b.grow(p2);
            }
            primitives[i] = {b, static_cast<uint32_t>(i)};
        }
        BvhBuildOptions options;
        options.threads = threads;
        // A leaf is tested a group (up to 8 triangles) at a time, about the price of one triangle
        // test in scalar code: the SAH counts leaves in groups, and fills them.
        options.max_leaf_size = kGroupMaxTriangles;
        options.leaf_test_width = kGroupMaxTriangles;
        options.traversal_cost = 1.0f;
        shape.bvh = build_wide_bvh(std::move(primitives), options);
    }
    shape.groups = build_triangle_groups(mesh, shape.bvh, threads);
    if (!shape.bvh.empty()) shape.bounds = shape.bvh.bounds;
    if (!shape.bvh.empty() && mesh_is_closed(mesh, threads))
        shape.cones = build_normal_cones(shape.bvh, shape.groups.data(), threads);
    // Every triangle's corners and id are in its group now: what remains is for smooth normals.
    std::vector<uint32_t>().swap(shape.bvh.prim_order);
    std::vector<Vec3f>().swap(mesh.positions);
    std::vector<uint32_t>().swap(mesh.indices);
    shape.mesh = std::move(mesh);
    shape.leaf_size = median_leaf_size(shape.bvh);  // after the frees: it needs a float per leaf
    return shape;
}

}  // namespace raycast
