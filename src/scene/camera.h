// Cameras: where the primary ray of each pixel starts and goes.
// Pixel (x, y) counts from the bottom-left; y grows upwards, as the course's images store it.
#pragma once

#include <cmath>

#include "math/lane_vectors.h"
#include "math/ray.h"
#include "scene/conventions.h"
#include "scene/scene_desc.h"

namespace raycast {

struct Camera {
    enum class Projection { Perspective, Orthographic };
    Projection projection = Projection::Perspective;
    Vec3f center;
    Vec3f direction{0, 0, -1};  ///< unit
    Vec3f horizontal{1, 0, 0};  ///< unit, direction × up
    Vec3f up{0, 1, 0};          ///< unit, horizontal × direction
    int width = 1, height = 1;
    float cx = 0.5f, cy = 0.5f;  ///< the image centre in pixel units: width / 2, height / 2
    /// Perspective: focal lengths in pixels, (h/2)/tan(angle/2). Orthographic: pixels per world unit.
    float fx = 1, fy = 1;
    float pixel_offset = 0;  ///< added to integer pixel coordinates (conventions)
    float t_min = 0;         ///< where primary rays start counting hits
    float lens_radius = 0;   ///< thin lens (depth of field); 0 is a pinhole
    float focus_distance = 1;
};

/// Builds the camera from the file's description at the given image size.
/// Requires a valid description (the parser checks direction, up and angle).
Camera make_camera(const CameraDesc& desc, int width, int height, const Conventions& conventions);

/// The two halves of camera_ray below: the image-plane point in camera units, a = (px − cx)/fx along
/// `horizontal` and b = (py − cy)/fy along `up`, depends on one pixel coordinate each, so a
/// renderer can find them once per column and row; camera_ray_at makes the same ray from them.
inline float camera_plane_x(const Camera& camera, float px) { return (px - camera.cx) / camera.fx; }
inline float camera_plane_y(const Camera& camera, float py) { return (py - camera.cy) / camera.fy; }
inline Ray camera_ray_at(const Camera& camera, float a, float b) {
    if (camera.projection == Camera::Projection::Orthographic)
        return {camera.center + a * camera.horizontal + b * camera.up, camera.direction};
    return {camera.center, normalize(a * camera.horizontal + b * camera.up + camera.direction)};
}

/// camera_ray_at for `count` points (a[i], b[i]) at once, into rays[i]: the same rays, with the
/// normalisations' square roots and divisions in plain loops over arrays, which the compiler turns
/// into SIMD instructions (IEEE results lane by lane: the same bits as one ray at a time).
inline void camera_rays_at(const Camera& camera, const float* a, const float* b, int count, Ray* rays) {
    if (camera.projection == Camera::Projection::Orthographic) {
        for (int i = 0; i < count; ++i) rays[i] = camera_ray_at(camera, a[i], b[i]);
        return;
    }
    constexpr int kChunk = kMaxLanes;
    const Vec3f h = camera.horizontal, u = camera.up, d = camera.direction;
    for (int first = 0; first < count; first += kChunk) {
        const int n = count - first < kChunk ? count - first : kChunk;
        LaneVectors direction;
        for (int i = 0; i < n; ++i) {  // a·horizontal + b·up + direction, as camera_ray_at adds them
            direction.x[i] = a[first + i] * h.x + b[first + i] * u.x + d.x;
            direction.y[i] = a[first + i] * h.y + b[first + i] * u.y + d.y;
            direction.z[i] = a[first + i] * h.z + b[first + i] * u.z + d.z;
        }
        float length[kChunk];
        normalize_lanes(direction, length, n);
        for (int i = 0; i < n; ++i) rays[first + i] = {camera.center, direction.at(i)};
    }
}

/// The ray through the point (px, py) of the image plane, in pixel units: the course's pixel
/// (x, y) is the point (x + pixel_offset, y + pixel_offset).
/// Inline: the renderer calls it once per pixel, and a call returns the ray through memory.
inline Ray camera_ray(const Camera& camera, float px, float py) {
    return camera_ray_at(camera, camera_plane_x(camera, px), camera_plane_y(camera, py));
}

/// The same through a thin lens: (lens_u, lens_v) in [0, 1)² picks the point on the aperture.
Ray camera_ray(const Camera& camera, float px, float py, float lens_u, float lens_v);

}  // namespace raycast
