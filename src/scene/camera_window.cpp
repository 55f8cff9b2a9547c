#include "scene/camera_window.h"

#include <algorithm>
#include <cmath>

namespace raycast {
namespace {

double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void cross3(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

// Stack entries for the BVH walks: the instance BVH's depth bound covers both.
constexpr int kStackSize = kMaxBvhDepth + 1;

// The least margin, in world units. Below about 1e-19 products of coordinates underflow, and
// the tracer's float tests lose their relative precision (a triangle test's edge functions are
// such products): no window is claimed to miss anything that close.
constexpr double kLeastMargin = 1e-12;

// The least margin on a plane test's dot products: each float product in them may underflow,
// by up to 2^-150 (about 7e-46).
constexpr double kLeastProductMargin = 1e-40;

// Whether a transform is close enough to orthogonal for its world box to hold what the tracer
// hits: the condition number of the 3x3 part of object_from_world (infinity norms, in double) is
// at most 100. The tracer moves rays into object space with the float matrix; its rounding,
// about 1e-7 of the coordinates, comes back to world space times at most that condition number,
// 1e-5 of the coordinates, which the margin's 1e-4 covers.
bool well_conditioned(const Mat4& object_from_world) {
    double a[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[r][c] = object_from_world.m[r][c];
    const double cofactor[3][3] = {
        {a[1][1] * a[2][2] - a[1][2] * a[2][1], a[1][2] * a[2][0] - a[1][0] * a[2][2], a[1][0] * a[2][1] - a[1][1] * a[2][0]},
        {a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0], a[0][1] * a[2][0] - a[0][0] * a[2][1]},
        {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2], a[0][0] * a[1][1] - a[0][1] * a[1][0]}};
    const double determinant = a[0][0] * cofactor[0][0] + a[0][1] * cofactor[0][1] + a[0][2] * cofactor[0][2];
    // The inverse is the cofactors' transpose over the determinant: its rows are their columns.
    double norm = 0, inverse_norm = 0;
    for (int r = 0; r < 3; ++r) {
        norm = std::max(norm, std::fabs(a[r][0]) + std::fabs(a[r][1]) + std::fabs(a[r][2]));
        inverse_norm = std::max(inverse_norm, std::fabs(cofactor[0][r]) + std::fabs(cofactor[1][r]) + std::fabs(cofactor[2][r]));
    }
    const double condition = norm * inverse_norm / std::fabs(determinant);
    return std::isfinite(condition) && condition <= 100;
}

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
        double* n = window.normal[side];
        cross3(corner[side], corner[(side + 1) % 4], n);
        const double length = std::sqrt(dot3(n, n));
        if (!std::isfinite(length)) return window;  // not bounded
        const double scale = length > 0 ? (dot3(n, middle) < 0 ? -1 : 1) / length : 0;  // inwards, unit
        for (int axis = 0; axis < 3; ++axis) n[axis] *= scale;
    }
    // Every exact direction a·horizontal + b·up + direction has the same component along
    // horizontal × up, direction's (horizontal and up are each at right angles to it): the plane
    // facing that way has every ray ahead of it, if that component is clearly positive. (Not
    // `direction` itself: make_camera rounds horizontal, and when `up` nearly parallels
    // `direction` the two are not quite at right angles, so that a wide window's rays may point
    // a little behind the plane facing `direction`.)
    double ahead[3];
    cross3(h, u, ahead);
    const double ahead_length = std::sqrt(dot3(ahead, ahead));
    double widest = 0;
    for (const double* c : corner) widest = std::max(widest, std::sqrt(dot3(c, c)));
    const double along = ahead_length > 0 ? std::fabs(dot3(ahead, d)) / ahead_length : 0;
    if (along > 1e-3 * widest) {
        const double scale = (dot3(ahead, d) < 0 ? -1 : 1) / ahead_length;
        for (int axis = 0; axis < 3; ++axis) window.normal[4][axis] = ahead[axis] * scale;
    }
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
    const double margin = 1e-3 * std::sqrt(farthest_squared) + 1e-4 * scale + kLeastMargin;
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
    // The float products may also underflow, each by up to 2^-150 (kLeastProductMargin).
    const double size = std::fabs(double{plane.offset}) + normal_length * std::sqrt(dot3(window.origin, window.origin));
    const double numerator = plane.offset - dot3(n, window.origin);
    if (!std::isfinite(size) || !(std::fabs(numerator) > 1e-4 * size + kLeastProductMargin)) return false;
    for (const double* d : window.corner) {
        // t's denominator must have the other sign, by far more than its rounding (the corner's
        // direction is not unit: both sides scale with its length).
        const double denominator = dot3(n, d);
        const double margin = (1e-3 * normal_length + kLeastProductMargin) * std::sqrt(dot3(d, d));
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
    // An instance BVH of one leaf is not box-tested by the tracer (intersect.cpp, traverse_packet):
    // its instances are tested whatever the ray. Their boxes hold what the tracer can hit only
    // for meshes, spheres and triangles that are untransformed or under a transform close to
    // orthogonal (well_conditioned): a transformed object is traced through the float inverse of
    // its matrix, which for a matrix far from orthogonal reaches well outside the box made with
    // the matrix itself. And a surface of revolution's tests are counted.
    if (nodes.size() == 1)
        for (uint32_t i = nodes[0].first; i < nodes[0].first + nodes[0].count; ++i) {
            const Instance& instance = scene.instances[scene.instance_bvh.prim_order[i]];
            const bool box_holds_it =
                (instance.kind == ShapeKind::Mesh || instance.kind == ShapeKind::Sphere ||
                 instance.kind == ShapeKind::Triangle) &&
                (instance.transform == kNoTransform || well_conditioned(scene.object_from_world[instance.transform]));
            if (!box_holds_it) return false;
        }
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
