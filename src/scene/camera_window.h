// Windows of the image plane whose camera rays miss everything, found without tracing them.
//
// The rays of a pinhole camera through a rectangle of its image plane leave one point and fill
// a cone with four flat sides. A box wholly outside one side (or wholly behind the camera) holds
// nothing those rays can hit, and a BVH walk over such boxes tells whether the window sees any
// object at all. Where the scene fills only part of the image (the course's scenes, the
// benchmark's sphere on its background), the render loop gives a window that sees nothing the
// miss colour at once, instead of making, tracing and shading each of its rays to the same end.
//
// The tests are exact in the sense that matters: never "misses" for a window some ray of which
// the tracer would find a hit for. The planes are found in double precision, and a box must lie
// outside by a margin far wider than the rounding of the rays and of the intersection tests
// (see window_misses_box), so the image is bit for bit the one tracing every ray gives (tests
// compare the two).
#pragma once

#include "math/bounds.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace raycast {

/// The rays of a pinhole camera through the image-plane window [px0, px1] × [py0, py1] (pixel
/// units, as camera_ray takes them), as the planes through the camera's centre that bound them:
/// four sides, and the plane facing horizontal × up, ahead of which every camera ray goes.
struct CameraWindow {
    /// False where nothing can be said (an orthographic or thin-lens camera, whose rays do not
    /// leave one point; a camera that looks behind itself; values that are not finite): then no
    /// box is missed.
    bool bounded = false;
    double origin[3] = {0, 0, 0};
    /// Unit normals pointing into the cone (a side of a window of no width has a zero normal and
    /// culls nothing).
    double normal[5][3] = {};
    /// The corners' directions, a·horizontal + b·up + direction (not unit): every ray's direction
    /// is a positive combination of them, up to its rounding.
    double corner[4][3] = {};
};

CameraWindow camera_window(const Camera& camera, float px0, float px1, float py0, float py1);

/// Whether every ray of the window misses everything inside `box`: the box lies outside one of
/// the window's planes by more than 1e-3 of its farthest corner's distance from the camera plus
/// 1e-4 of the largest coordinate involved (and never less than 1e-12). A computed ray strays
/// from its exact direction by a few float roundings (about 1e-7 of its length), and a hit found
/// in float may lie a few roundings of the coordinates (about 1e-7 of their size) off the
/// surface, so the margin is about a thousand times what rounding could bring back; the floor of
/// 1e-12 stays well above where products of coordinates underflow (about 1e-19), where the
/// tracer's tests lose their relative precision. An empty box is missed.
bool window_misses_box(const CameraWindow& window, const Bounds3f& box);

/// Whether every ray of the window misses the plane: the camera is on one side of it, and every
/// corner's direction points away from it (so every ray's does), each by a margin like
/// window_misses_box's, and more than what the float dot products could lose to underflow.
/// intersect_plane's t = (offset − n·o) / (n·d) is then negative for every ray, rounding included.
bool window_misses_plane(const CameraWindow& window, const Plane& plane);

/// Whether every ray of the window misses the whole scene: every plane (window_misses_plane),
/// and, as far as the boxes show, everything bounded: the instance BVH is walked, and an
/// untransformed mesh's wide BVH down to `mesh_levels` levels, dropping boxes the window misses.
/// False as soon as a box it reaches is not missed (its contents would need the rays themselves),
/// and for an instance BVH of one leaf (which the tracer does not box-test) holding anything but
/// meshes, spheres and triangles that are untransformed or under a transform of condition number
/// at most 100, whose boxes hold all the tracer can hit.
bool window_misses_scene(const Scene& scene, const CameraWindow& window, int mesh_levels = 3);

}  // namespace raycast
