#include "scene/camera_window.h"

#include <algorithm>
#include <cmath>

namespace raycast {
namespace {

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Stack entries for the BVH walks: the instance BVH's depth bound covers both.
constexpr int kStackSize = kMaxBvhDepth + 1;

}  // namespace

CameraWindow camera_window(const Camera& camera, float px0, float px1, float py0, float py1) {
    CameraWindow window;
    if (camera.projection != Camera::Projection::Perspective || camera.lens_radius > 0 || !(camera.t_min >= 0))
        return window;
    const double h[3] = {camera.horizontal.x, camera.horizontal.y, camera.horizontal.z};
    const double u[3] = {camera.up.x, camera.up.y, camera.up.z};
    const double d[3] = {camera.direction.x, camera.direction.y, camera.direction.z};
    // The corners as directions, a·horizontal + b·up + direction (camera_ray_at before it
    // normalises), in order around the window; every ray through the window lies in the cone
    // they span, up to its rounding.
    const double a[2] = {(double{px0} - camera.cx) / camera.fx, (double{px1} - camera.cx) / camera.fx};
    const double b[2] = {(double{py0} - camera.cy) / camera.fy, (double{py1} - camera.cy) / camera.fy};
    const int corner_a[4] = {0, 1, 1, 0}, corner_b[4] = {0, 0, 1, 1};
    double(&corner)[4][3] = window.corner;
    double middle[3] = {0, 0, 0};
    for (int i = 0; i < 4; ++i)
        for (int axis = 0; axis < 3; ++axis) {
            corner[i][axis] = a[corner_a[i]] * h[axis] + b[corner_b[i]] * u[axis] + d[axis];
            middle[axis] += corner[i][axis];
        }
    for (int side = 0; side < 4; ++side) {
        const double* p = corner[side];
        const double* q = corner[(side + 1) % 4];
        double* n = window.normal[side];
        n[0] = p[1] * q[2] - p[2] * q[1];
        n[1] = p[2] * q[0] - p[0] * q[2];
        n[2] = p[0] * q[1] - p[1] * q[0];
        const double length = std::sqrt(dot3(n, n));
        if (!std::isfinite(length)) return window;  // not bounded
        const double scale = length > 0 ? (dot3(n, middle) < 0 ? -1 : 1) / length : 0;  // inwards, unit
        for (int axis = 0; axis < 3; ++axis) n[axis] *= scale;
    }
    for (int axis = 0; axis < 3; ++axis) window.normal[4][axis] = d[axis];  // unit already
    window.origin[0] = camera.center.x;
    window.origin[1] = camera.center.y;
    window.origin[2] = camera.center.z;
    window.bounded = std::isfinite(dot3(window.origin, window.origin)) && std::isfinite(dot3(middle, middle));
    return window;
}

bool window_misses_box(const CameraWindow& window, const Bounds3f& box) {
    if (!window.bounded) return false;
    const double lower[3] = {box.lower.x, box.lower.y, box.lower.z}, upper[3] = {box.upper.x, box.upper.y, box.upper.z};
    // An empty box (nothing bounded: lower above upper) holds nothing; a box with a bound that
    // is NaN or infinite tells nothing.
    bool finite = true, nan = false;
    for (int axis = 0; axis < 3; ++axis) {
        finite = finite && std::isfinite(lower[axis]) && std::isfinite(upper[axis]);
        nan = nan || std::isnan(lower[axis]) || std::isnan(upper[axis]);
    }
    if (nan) return false;
    if (box.is_empty()) return true;
    if (!finite) return false;
    // The box from the camera, its farthest corner's distance, and the largest coordinate.
    double near[3], far[3], farthest_squared = 0, scale = 0;
    for (int axis = 0; axis < 3; ++axis) {
        near[axis] = lower[axis] - window.origin[axis];
        far[axis] = upper[axis] - window.origin[axis];
        farthest_squared += std::max(near[axis] * near[axis], far[axis] * far[axis]);
        scale = std::max({scale, std::fabs(window.origin[axis]), std::fabs(lower[axis]), std::fabs(upper[axis])});
    }
    const double margin = 1e-3 * std::sqrt(farthest_squared) + 1e-4 * scale;
    if (!std::isfinite(margin)) return false;
    for (const double* n : window.normal) {
        // The box's greatest distance into the plane's side: its corner farthest along n.
        double greatest = 0;
        for (int axis = 0; axis < 3; ++axis) greatest += std::max(n[axis] * near[axis], n[axis] * far[axis]);
        if (greatest < -margin) return true;
    }
    return false;
}

bool window_misses_plane(const CameraWindow& window, const Plane& plane) {
    if (!window.bounded) return false;
    const double n[3] = {plane.normal.x, plane.normal.y, plane.normal.z};
    const double normal_length = std::sqrt(dot3(n, n));
    // Which side of the plane the camera is on (the sign of t's numerator), with room for its
    // rounding in float (of offset − n·o, whose terms are at most `size`).
    const double size = std::fabs(double{plane.offset}) + normal_length * std::sqrt(dot3(window.origin, window.origin));
    const double numerator = plane.offset - dot3(n, window.origin);
    if (!std::isfinite(size) || !(std::fabs(numerator) > 1e-4 * size)) return false;
    for (const double* d : window.corner) {
        // t's denominator must have the other sign, by far more than its rounding.
        const double denominator = dot3(n, d);
        const double margin = 1e-3 * normal_length * std::sqrt(dot3(d, d));
        if (numerator > 0 ? !(denominator < -margin) : !(denominator > margin)) return false;
    }
    return true;
}

bool window_misses_scene(const Scene& scene, const CameraWindow& window, int mesh_levels) {
    if (!window.bounded) return false;
    for (uint32_t id : scene.plane_instances)
        if (!window_misses_plane(window, scene.planes[scene.instances[id].shape])) return false;
    const LargeVector<BvhNode>& nodes = scene.instance_bvh.nodes;
    if (nodes.empty()) return true;  // nothing at all
    // Whether the rays miss an untransformed mesh: its wide BVH's children, level by level.
    auto misses_mesh = [&](const MeshShape& mesh) {
        if (mesh.bvh.empty()) return true;
        struct Pending {
            uint32_t node;
            int level;
        };
        Pending stack[kStackSize * kWideBvhWidth];
        int size = 0;
        stack[size++] = {0, 1};
        while (size > 0) {
            const Pending next = stack[--size];
            const WideBvhNode& node = mesh.bvh.nodes[next.node];
            for (uint32_t slot = 0; slot < node.child_count; ++slot) {
                if (window_misses_box(window, child_bounds(node, slot))) continue;
                if (is_wide_leaf(node.child[slot]) || next.level >= mesh_levels) return false;
                stack[size++] = {node.child[slot], next.level + 1};
            }
        }
        return true;
    };
    uint32_t stack[kStackSize];
    int size = 0;
    stack[size++] = 0;
    while (size > 0) {
        const BvhNode& node = nodes[stack[--size]];
        if (window_misses_box(window, node.bounds)) continue;
        if (!node.is_leaf()) {
            stack[size++] = node.first;
            stack[size++] = node.first + 1;
            continue;
        }
        for (uint32_t i = node.first; i < node.first + node.count; ++i) {
            const Instance& instance = scene.instances[scene.instance_bvh.prim_order[i]];
            if (instance.kind != ShapeKind::Mesh || instance.transform != kNoTransform) return false;
            if (!misses_mesh(scene.meshes[instance.shape])) return false;
        }
    }
    return true;
}

}  // namespace raycast
