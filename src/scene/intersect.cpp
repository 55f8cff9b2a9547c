// Closest-hit and any-hit queries over the two-level scene: planes in a loop, then the instance
// BVH, whose leaves send the ray (moved to object space where needed) to a shape's own test.
#include <cmath>

#include "base/simd_clones.h"
#include "geometry/triangle.h"
#include "scene/intersect_packet.h"
#include "scene/scene.h"

namespace raycast {

namespace {

// Offers a candidate hit; keeps it if it beats the current best.
inline void offer(Hit& best, float t, float u, float v, uint32_t object, uint32_t prim, uint32_t leaf = 0) {
    if (is_closer(t, object, prim, best)) best = Hit{t, u, v, object, prim, leaf};
}

// How many shapes of a kind the scene holds (for checking an instance's index).
size_t shape_count(const Scene& scene, ShapeKind kind) {
    switch (kind) {
        case ShapeKind::Sphere: return scene.spheres.size();
        case ShapeKind::Plane: return scene.planes.size();
        case ShapeKind::Triangle: return scene.triangles.size();
        case ShapeKind::Mesh: return scene.meshes.size();
        case ShapeKind::RevSurface: return scene.rev_surfaces.size();
    }
    return 0;
}

template <bool kAnyHit>
struct Query {
    const Scene& scene;
    float t_min;
    float t_max;  // any-hit: hits must be nearer than this
    Hit& best;
    TraceCounters* counters;
    const uint8_t* skip_back_faces = nullptr;  // any-hit: per instance, as occluded() takes it
    // Closest-hit: where the ray enters the box of the instance BVH's leaf being tested (-inf
    // where no box was tested); a sphere's, triangle's or surface's hit is moved up to that
    // leaf's floor (at_leaf_floor; a mesh's hits are held to its own BVH's leaves in the kernel).
    float leaf_entry = -INFINITY;

    void offer_shape(float t, float u, float v, uint32_t object, uint32_t prim) {
        offer(best, at_leaf_floor(t, leaf_entry), u, v, object, prim);
    }

    // Returns true when an any-hit query has its answer.
    bool mesh(const MeshShape& shape, const Ray& ray, uint32_t object) {
        if (shape.bvh.empty()) return false;
        const MeshRayKernel& kernel = best_mesh_ray_kernel();
        if (kAnyHit)
            return kernel.occluded(single_ray_view(shape, skip_back_faces && skip_back_faces[object]), ray, t_min, t_max);
        kernel.intersect(single_ray_view(shape, false), ray, t_min, object, best,
                         counters ? &counters->nodes_visited : nullptr);
        return false;
    }

    bool instance(uint32_t id, const Ray& world_ray) {
        RAYCAST_DCHECK(id < scene.instances.size());
        const Instance& inst = scene.instances[id];
        RAYCAST_DCHECK(inst.transform == kNoTransform || inst.transform < scene.object_from_world.size());
        RAYCAST_DCHECK(inst.shape < shape_count(scene, inst.kind));
        const Ray ray = inst.transform == kNoTransform ? world_ray
                                                       : to_object_space(scene.object_from_world[inst.transform], world_ray);
        switch (inst.kind) {
            case ShapeKind::Sphere: {
                float t;
                if (!intersect_sphere(scene.spheres[inst.shape], ray, t_min, t)) return false;
                if (kAnyHit) return t < t_max;
                offer_shape(t, 0, 0, id, 0);
                return false;
            }
            case ShapeKind::Triangle: {
                const TriangleShape& tri = scene.triangles[inst.shape];
                TriangleHit hit;
                if (!intersect_triangle(make_watertight_ray(ray), tri.p0, tri.p1, tri.p2, t_min, hit)) return false;
                if (kAnyHit) return hit.t < t_max;
                offer_shape(hit.t, hit.u, hit.v, id, 0);
                return false;
            }
            case ShapeKind::Mesh:
                return mesh(scene.meshes[inst.shape], ray, id);
            case ShapeKind::Plane: {
                float t;
                if (!intersect_plane(scene.planes[inst.shape], ray, t_min, t)) return false;
                if (kAnyHit) return t < t_max;
                offer_shape(t, 0, 0, id, 0);
                return false;
            }
            case ShapeKind::RevSurface: {
                // A hit at exactly the best t still goes to offer(), which breaks the tie.
                RevSurfaceHit hit;
                if (!intersect_rev_surface(scene.rev_surfaces[inst.shape], ray, t_min,
                                           kAnyHit ? t_max : std::nextafter(best.t, INFINITY), kAnyHit, hit,
                                           counters ? &counters->nodes_visited : nullptr))
                    return false;
                if (kAnyHit) return true;
                offer_shape(hit.t, hit.u, 0, id, hit.piece);
                return false;
            }
        }
        return false;
    }

    // instance(), with the commonest case, a mesh in world space, taken here: instance() is too
    // large to inline, and a call on the way to every mesh's kernel was 3% of a 1k-triangle
    // render's single rays.
    bool visit(uint32_t id, const Ray& ray) {
        RAYCAST_DCHECK(id < scene.instances.size());
        const Instance& inst = scene.instances[id];
        if (inst.kind == ShapeKind::Mesh && inst.transform == kNoTransform) return mesh(scene.meshes[inst.shape], ray, id);
        return instance(id, ray);
    }

    bool run(const Ray& ray) {
        for (uint32_t id : scene.plane_instances)
            if (instance(id, ray)) return true;
        const uint32_t* ids = scene.instance_bvh.prim_order.data();
        if (scene.instance_bvh.nodes.size() == 1) {
            // One leaf (a scene of a mesh or two): its box is the union of what the instances
            // test first thing anyway.
            const BvhNode& leaf = scene.instance_bvh.nodes[0];
            for (uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
                if (visit(ids[i], ray)) return true;
            return false;
        }
        const BoxRay box_ray = make_box_ray(ray, t_min);
        return traverse_bvh(
            scene.instance_bvh, box_ray, [&] { return kAnyHit ? t_max : best.t; },
            [&](uint32_t first, uint32_t count, float t_entry) {
                leaf_entry = t_entry;
                for (uint32_t i = first; i < first + count; ++i)
                    if (visit(ids[i], ray)) return true;
                return false;
            },
            counters ? &counters->nodes_visited : nullptr);
    }
};

}  // namespace

void intersect_two_level(const Scene& scene, const Ray& ray, float t_min, Hit& hit, TraceCounters* counters) {
    Query<false>{scene, t_min, INFINITY, hit, counters}.run(ray);
    RAYCAST_DCHECK(!hit.is_hit() || hit.t > t_min);
}

bool occluded_two_level(const Scene& scene, const Ray& ray, float t_min, float t_max, const uint8_t* skip_back_faces) {
    Hit unused;
    return Query<true>{scene, t_min, t_max, unused, nullptr, skip_back_faces}.run(ray);
}

namespace {

// normalize_any_length lane by lane: what normalize_lanes gives where every length is ordinary.
// Out of line and cold: kept out of surface_points, whose loops it slowed by its presence alone.
[[gnu::cold]] [[gnu::noinline]] void normalize_any_length_lanes(LaneVectors& v, int count) {
    for (int j = 0; j < count; ++j) v.set(j, normalize_any_length(v.at(j)));
}

// The largest coordinate of a triangle's corners (SurfacePoint::geometry_scale, before any transform).
float corner_scale(Vec3f p0, Vec3f p1, Vec3f p2) {
    const float a = max_abs(p0), b = max_abs(p1), c = max_abs(p2);
    const float ab = a > b ? a : b;
    return ab > c ? ab : c;
}

}  // namespace

SurfacePoint surface_at(const Scene& scene, const Ray& ray, const Hit& hit) {
    const Instance& inst = scene.instances[hit.object];
    SurfacePoint surface;
    surface.position = ray.at(hit.t);
    surface.material = inst.material;
    const Ray object_ray = inst.transform == kNoTransform ? ray : to_object_space(scene.object_from_world[inst.transform], ray);
    Vec3f normal;
    switch (inst.kind) {
        case ShapeKind::Sphere: {
            const Sphere& sphere = scene.spheres[inst.shape];
            normal = normalize_any_length(object_ray.at(hit.t) - sphere.center);
            surface.geometry_scale = max_abs(sphere.center) + sphere.radius;
            break;
        }
        case ShapeKind::Plane:
            normal = normalize_any_length(scene.planes[inst.shape].normal);
            break;
        case ShapeKind::Triangle: {
            const TriangleShape& tri = scene.triangles[inst.shape];
            normal = triangle_normal(tri.p0, tri.p1, tri.p2);
            surface.geometry_scale = corner_scale(tri.p0, tri.p1, tri.p2);
            break;
        }
        case ShapeKind::RevSurface:
            normal = rev_surface_normal(scene.rev_surfaces[inst.shape], hit.prim, hit.u, object_ray.at(hit.t));
            break;
        case ShapeKind::Mesh: {
            const MeshShape& shape = scene.meshes[inst.shape];
            const TriangleMesh& mesh = shape.mesh;
            RAYCAST_DCHECK(hit.leaf < shape.groups.size());
            const GroupBlock* group = &shape.groups[hit.leaf];
            RAYCAST_DCHECK(hit.lane < group_triangle_count(group));
            const GroupTriangle corners = group_triangle(group, hit.lane);
            RAYCAST_DCHECK(corners.id == hit.prim);
            normal = triangle_normal(corners.p0, corners.p1, corners.p2);
            surface.geometric_normal = normal;
            surface.geometry_scale = corner_scale(corners.p0, corners.p1, corners.p2);
            if (mesh.has_normals()) {
                const uint32_t* n = &mesh.normal_indices[3 * size_t{hit.prim}];
                if (n[0] != kNoNormal && n[1] != kNoNormal && n[2] != kNoNormal) {
                    const float w0 = 1 - hit.u - hit.v;
                    const Vec3f smooth = normalize_any_length(mesh.normals[n[0]] * w0 + mesh.normals[n[1]] * hit.u +
                                                              mesh.normals[n[2]] * hit.v);
                    if (dot(smooth, smooth) > 0) normal = smooth;
                }
            }
            break;
        }
    }
    if (inst.kind != ShapeKind::Mesh) surface.geometric_normal = normal;
    if (inst.transform != kNoTransform) {
        const Mat4& object_from_world = scene.object_from_world[inst.transform];
        normal = transform_normal(object_from_world, normal);
        surface.geometric_normal = transform_normal(object_from_world, surface.geometric_normal);
        // The test ran in object space, where an error in t is the same but the direction is
        // longer or shorter: in world units the shape's scale goes with the world direction.
        if (surface.geometry_scale > 0) {
            const float world_scale = surface.geometry_scale * (max_abs(ray.direction) / max_abs(object_ray.direction));
            surface.geometry_scale = std::isfinite(world_scale) ? world_scale : 0.0f;
        }
    }
    surface.normal = normal;
    return surface;
}

RAYCAST_SIMD_CLONES
void surface_points(const Scene& scene, const Ray* rays, const Hit* hits, const int* lanes, int count,
                    SurfaceLanes& out) {
    RAYCAST_DCHECK(count <= kMaxPacketLanes);
    // The corners of the lanes' mesh triangles. The other lanes, found below, get a stand-in of
    // unit normal: every lane then goes through the SIMD loops, none as an unusual length.
    LaneVectors p0, p1, p2;
    int others[kMaxPacketLanes];
    int other_count = 0;
    // Neighbouring lanes mostly hit one object: what the lanes need of it is looked up once per
    // run of lanes on it (a lookup per lane was most of this function's time).
    uint32_t last_object = kNoObject;
    uint32_t material = 0;
    const GroupBlock* groups = nullptr;  // the object's groups when it is a flat mesh, else null
    for (int j = 0; j < count; ++j) {
        const Hit& hit = hits[lanes[j]];
        RAYCAST_DCHECK(hit.is_hit());
        if (hit.object != last_object) {
            last_object = hit.object;
            const Instance& inst = scene.instances[hit.object];
            material = inst.material;
            const bool flat_mesh = inst.kind == ShapeKind::Mesh && inst.transform == kNoTransform &&
                                   !scene.meshes[inst.shape].mesh.has_normals();
            groups = flat_mesh ? scene.meshes[inst.shape].groups.data() : nullptr;
        }
        out.material[j] = material;
        if (!groups) {
            p0.set(j, {0, 0, 0});
            p1.set(j, {1, 0, 0});
            p2.set(j, {0, 1, 0});
            others[other_count++] = j;
            continue;
        }
        RAYCAST_DCHECK(hit.leaf < scene.meshes[scene.instances[hit.object].shape].groups.size());
        const GroupBlock* group = groups + hit.leaf;
        RAYCAST_DCHECK(hit.lane < group_triangle_count(group));
        const GroupTriangle corners = group_triangle(group, hit.lane);
        RAYCAST_DCHECK(corners.id == hit.prim);
        p0.set(j, corners.p0);
        p1.set(j, corners.p1);
        p2.set(j, corners.p2);
    }
    // corner_scale, lane by lane: the largest of nine finite coordinates is the same found in any
    // order, and these loops of comparisons and fabs are SIMD.
    for (int j = 0; j < count; ++j) {
        const float a = std::fabs(p0.x[j]), b = std::fabs(p0.y[j]), c = std::fabs(p0.z[j]);
        const float d = std::fabs(p1.x[j]), e = std::fabs(p1.y[j]), f = std::fabs(p1.z[j]);
        const float g = std::fabs(p2.x[j]), h = std::fabs(p2.y[j]), i = std::fabs(p2.z[j]);
        const float ab = a > b ? a : b, cd = c > d ? c : d, ef = e > f ? e : f, gh = g > h ? g : h;
        const float abcd = ab > cd ? ab : cd, efgh = ef > gh ? ef : gh;
        const float all8 = abcd > efgh ? abcd : efgh;
        out.geometry_scale[j] = all8 > i ? all8 : i;
    }
    // ray.at(t) and triangle_normal, operation for operation: normalize_any_length((p1 − p0) × (p2 − p0)).
    LaneVectors& normal = out.normal;
    for (int j = 0; j < count; ++j) {
        const Ray& ray = rays[lanes[j]];
        const float t = hits[lanes[j]].t;
        out.position.x[j] = ray.origin.x + ray.direction.x * t;
        out.position.y[j] = ray.origin.y + ray.direction.y * t;
        out.position.z[j] = ray.origin.z + ray.direction.z * t;
    }
    // normalize_any_length, as triangle_normal does: a lane whose cross product is too long or too
    // short to square in float (has_ordinary_length) is normalised on its own. Nearly always
    // none is: asked in the same SIMD loop.
    int unusual_lanes = 0;
    for (int j = 0; j < count; ++j) {
        const float ax = p1.x[j] - p0.x[j], ay = p1.y[j] - p0.y[j], az = p1.z[j] - p0.z[j];
        const float bx = p2.x[j] - p0.x[j], by = p2.y[j] - p0.y[j], bz = p2.z[j] - p0.z[j];
        const float nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
        normal.x[j] = nx;
        normal.y[j] = ny;
        normal.z[j] = nz;
        const float squared = nx * nx + ny * ny + nz * nz;
        unusual_lanes |= static_cast<int>(!(squared > 1e-30f) | !(squared < 1e30f));
    }
    if (unusual_lanes != 0) {
        normalize_any_length_lanes(normal, count);
    } else {
        float length[kMaxPacketLanes];
        normalize_lanes(normal, length, count);
    }
    out.geometric_normal = normal;  // a flat triangle's, and overwritten for the others
    for (int i = 0; i < other_count; ++i) {
        const int j = others[i];
        const SurfacePoint surface = surface_at(scene, rays[lanes[j]], hits[lanes[j]]);
        normal.set(j, surface.normal);
        out.geometric_normal.set(j, surface.geometric_normal);
        out.geometry_scale[j] = surface.geometry_scale;
    }
}

size_t Scene::triangle_count() const {
    size_t count = 0;
    for (const Instance& inst : instances) {
        if (inst.kind == ShapeKind::Triangle) ++count;
        if (inst.kind == ShapeKind::Mesh) count += meshes[inst.shape].triangle_count;
    }
    return count;
}

}  // namespace raycast

namespace raycast {

void intersect_instance(const Scene& scene, uint32_t id, const Ray& world_ray, float t_min, float leaf_entry,
                        Hit& hit) {
    Query<false>{scene, t_min, INFINITY, hit, nullptr, nullptr, leaf_entry}.instance(id, world_ray);
}

bool occluded_instance(const Scene& scene, uint32_t id, const Ray& world_ray, float t_min, float t_max) {
    Hit unused;
    return Query<true>{scene, t_min, t_max, unused, nullptr}.instance(id, world_ray);
}

}  // namespace raycast
