#include "scene/camera.h"

#include <cmath>

namespace raycast {

Camera make_camera(const CameraDesc& desc, int width, int height, const Conventions& conventions) {
    Camera camera;
    camera.projection = desc.kind == CameraDesc::Kind::Perspective ? Camera::Projection::Perspective
                                                                   : Camera::Projection::Orthographic;
    camera.center = desc.center;
    camera.direction = normalize_any_length(desc.direction);
    // horizontal = normalize(direction × up) with `up` as written (the course's formula, rounding
    // included), unless its length is so extreme that the cross product would overflow or vanish.
    const Vec3f up = has_ordinary_length(desc.up) ? desc.up : normalize_any_length(desc.up);
    camera.horizontal = normalize(cross(camera.direction, up));
    camera.up = cross(camera.horizontal, camera.direction);
    camera.width = width;
    camera.height = height;
    camera.cx = static_cast<float>(width) / 2;
    camera.cy = static_cast<float>(height) / 2;
    camera.pixel_offset = conventions.pixel_offset;
    // `angle` (or `size`) spans the image height; with FovAxis::Both the width spans it too.
    const float span_x = static_cast<float>(conventions.fov_axis == FovAxis::Both ? width : height);
    const float span_y = static_cast<float>(height);
    if (camera.projection == Camera::Projection::Perspective) {
        const float radians = desc.angle_degrees * 3.14159265358979f / 180.0f;
        const float tan_half = std::tan(radians / 2);
        camera.fx = (span_x / 2) / tan_half;
        camera.fy = (span_y / 2) / tan_half;
    } else {
        camera.fx = span_x / desc.size;
        camera.fy = span_y / desc.size;
        if (conventions.orthographic_sees_behind) camera.t_min = -INFINITY;
    }
    return camera;
}

Ray camera_ray(const Camera& camera, float px, float py, float lens_u, float lens_v) {
    const Ray pinhole = camera_ray(camera, px, py);
    if (camera.lens_radius <= 0 || camera.projection != Camera::Projection::Perspective) return pinhole;
    // Points at the focus distance (measured along the view direction) stay sharp: every ray
    // through the lens for this pixel passes through the pinhole ray's point on that plane.
    const float t_focus = camera.focus_distance / dot(pinhole.direction, camera.direction);
    const Vec3f focus_point = pinhole.at(t_focus);
    // Concentric mapping of the unit square to the disk (Shirley and Chiu), no clumping.
    const float sx = 2 * lens_u - 1, sy = 2 * lens_v - 1;
    float r = 0, phi = 0;
    if (sx != 0 || sy != 0) {
        const float quarter_pi = 0.785398163397448f;
        if (std::fabs(sx) > std::fabs(sy)) {
            r = sx;
            phi = quarter_pi * (sy / sx);
        } else {
            r = sy;
            phi = 2 * quarter_pi - quarter_pi * (sx / sy);
        }
    }
    const Vec3f origin = camera.center + camera.lens_radius * r *
                                             (std::cos(phi) * camera.horizontal + std::sin(phi) * camera.up);
    // A far focus (up to the coordinate limit, and more at a wide angle's edges) puts the point so
    // far that its distance, squared, overflows: normalize() made every such direction zero.
    return {origin, normalize_any_length(focus_point - origin)};
}

}  // namespace raycast
