// Cameras: where the primary ray of each pixel starts and goes.
// Pixel (x, y) counts from the bottom-left; y grows upwards, as the course's images store it.
#pragma once

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

/// The ray through the point (px, py) of the image plane, in pixel units: the course's pixel
/// (x, y) is the point (x + pixel_offset, y + pixel_offset).
/// Inline: the renderer calls it once per pixel, and a call returns the ray through memory.
inline Ray camera_ray(const Camera& camera, float px, float py) {
    return camera_ray_at(camera, camera_plane_x(camera, px), camera_plane_y(camera, py));
}

/// The same through a thin lens: (lens_u, lens_v) in [0, 1)² picks the point on the aperture.
Ray camera_ray(const Camera& camera, float px, float py, float lens_u, float lens_v);

}  // namespace raycast
