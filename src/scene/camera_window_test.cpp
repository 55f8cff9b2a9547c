// Windows of the image plane that see nothing (scene/camera_window.h). The one property that
// matters is that "missed" is never wrong: for every box or plane a window is said to miss, the
// camera's own rays (camera_ray, in float) through many points of the window, corners and edges
// included, meet none of it (checked in double precision here). The tests also check that the
// test is not vacuous: boxes and planes clearly outside a window, worked out by hand or by
// projecting them, are missed.
#include "scene/camera_window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/plane.h"
#include "scene_builders.h"

namespace raycast {
namespace {

using test::perspective;

// Looking down −z from the origin, 90° across a 64×64 image: fx = fy = 32, cx = cy = 32, so
// pixel point (px, py) looks along ((px − 32)/32, (py − 32)/32, −1).
Camera square_camera() {
    return make_camera(perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 64, 64), 64, 64, Conventions::course());
}

Bounds3f box(Vec3f lower, Vec3f upper) { return {lower, upper}; }

// Whether the float ray meets the box (closed) at some t > 0: the slab test in double.
bool ray_meets_box(const Ray& ray, const Bounds3f& b) {
    double t0 = 0, t1 = INFINITY;
    const float o[3] = {ray.origin.x, ray.origin.y, ray.origin.z}, d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    const float lo[3] = {b.lower.x, b.lower.y, b.lower.z}, hi[3] = {b.upper.x, b.upper.y, b.upper.z};
    for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0) {
            if (o[axis] < lo[axis] || o[axis] > hi[axis]) return false;
            continue;
        }
        double a = (double{lo[axis]} - o[axis]) / d[axis], c = (double{hi[axis]} - o[axis]) / d[axis];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
    }
    return t0 <= t1;
}

// The points of the window a renderer's rays may pass through: a 9×9 grid with the corners and
// edges, and random points.
std::vector<Vec2f> window_points(float px0, float px1, float py0, float py1, std::mt19937& random) {
    std::vector<Vec2f> points;
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j)
            points.push_back({px0 + (px1 - px0) * static_cast<float>(i) / 8, py0 + (py1 - py0) * static_cast<float>(j) / 8});
    std::uniform_real_distribution<float> x(px0, px1), y(py0, py1);
    for (int k = 0; k < 40; ++k) points.push_back({x(random), y(random)});
    return points;
}

TEST(CameraWindowTest, BoxesInsideTheWindowAreSeenAndBoxesBesideOrBehindItAreMissed) {
    const Camera camera = square_camera();
    // The right half of the image, px in [32, 64]: directions x/(−z) from 0 to 1.
    const CameraWindow right = camera_window(camera, 32, 64, 0, 64);
    ASSERT_TRUE(right.bounded);
    EXPECT_FALSE(window_misses_box(right, box({0.5f, -0.1f, -2}, {0.7f, 0.1f, -1})));  // x/(−z) in [0.25, 0.7]
    EXPECT_FALSE(window_misses_box(right, box({-0.1f, -0.1f, -2}, {0.1f, 0.1f, -1})));  // across the left side
    EXPECT_TRUE(window_misses_box(right, box({-0.7f, -0.1f, -2}, {-0.5f, 0.1f, -1})));  // left of it
    EXPECT_TRUE(window_misses_box(right, box({2.5f, -0.1f, -2}, {3, 0.1f, -1})));       // x/(−z) > 1.25: right of it
    EXPECT_TRUE(window_misses_box(right, box({0.5f, 2.5f, -2}, {0.7f, 3, -1})));        // above it
    EXPECT_TRUE(window_misses_box(right, box({0.5f, -0.1f, 1}, {0.7f, 0.1f, 2})));      // behind the camera
    // A box around the camera is seen, and so is one reaching from behind into the window.
    EXPECT_FALSE(window_misses_box(right, box({-1, -1, -1}, {1, 1, 1})));
    EXPECT_FALSE(window_misses_box(right, box({0.2f, -0.1f, -1}, {0.3f, 0.1f, 5})));
    // Nothing in an empty box.
    EXPECT_TRUE(window_misses_box(right, Bounds3f{}));
}

TEST(CameraWindowTest, ABoxJustOutsideIsKeptByTheMargin) {
    const Camera camera = square_camera();
    const CameraWindow right = camera_window(camera, 32, 64, 0, 64);
    // The window's left side is the plane x = 0. At distance about 10, the margin is about 1e-2:
    // a box 1e-3 to its left is kept (the rays are not traced past it), one 0.5 to its left is not.
    EXPECT_FALSE(window_misses_box(right, box({-0.101f, -0.1f, -10}, {-0.001f, 0.1f, -9.9f})));
    EXPECT_TRUE(window_misses_box(right, box({-0.6f, -0.1f, -10}, {-0.5f, 0.1f, -9.9f})));
    // Far from the origin the coordinates' rounding counts too: the same box moved to 1e6 along
    // y with the camera is kept, though its distance from the camera is the same.
    Camera far = camera;
    far.center = {0, 1e6f, 0};
    const CameraWindow far_right = camera_window(far, 32, 64, 0, 64);
    EXPECT_FALSE(window_misses_box(far_right, box({-0.6f, 1e6f - 0.1f, -10}, {-0.5f, 1e6f + 0.1f, -9.9f})));
}

TEST(CameraWindowTest, NothingIsMissedWhereTheRaysDoNotLeaveOnePoint) {
    Camera camera = square_camera();
    const Bounds3f beside = box({-0.7f, -0.1f, -2}, {-0.5f, 0.1f, -1});
    ASSERT_TRUE(window_misses_box(camera_window(camera, 32, 64, 0, 64), beside));
    Camera lens = camera;
    lens.lens_radius = 0.1f;  // a thin lens: every ray has its own origin
    EXPECT_FALSE(camera_window(lens, 32, 64, 0, 64).bounded);
    EXPECT_FALSE(window_misses_box(camera_window(lens, 32, 64, 0, 64), beside));
    Camera orthographic = camera;
    orthographic.projection = Camera::Projection::Orthographic;
    EXPECT_FALSE(camera_window(orthographic, 32, 64, 0, 64).bounded);
    Camera behind = camera;
    behind.t_min = -INFINITY;  // a camera that sees behind itself
    EXPECT_FALSE(camera_window(behind, 32, 64, 0, 64).bounded);
    Camera nan = camera;
    nan.center.x = NAN;
    EXPECT_FALSE(camera_window(nan, 32, 64, 0, 64).bounded);
    EXPECT_FALSE(camera_window(camera, 32, INFINITY, 0, 64).bounded);
    EXPECT_FALSE(window_misses_box(camera_window(camera, 32, 64, 0, 64), box({-0.7f, -0.1f, -2}, {NAN, 0.1f, -1})));
    EXPECT_FALSE(window_misses_box(camera_window(camera, 32, 64, 0, 64), box({-INFINITY, -0.1f, -2}, {-0.5f, 0.1f, -1})));
    // A window of no width keeps the sides it has.
    const CameraWindow line = camera_window(camera, 48, 48, 0, 64);
    ASSERT_TRUE(line.bounded);
    EXPECT_TRUE(window_misses_box(line, beside));
    EXPECT_FALSE(window_misses_box(line, box({0.4f, -0.1f, -2}, {0.6f, 0.1f, -1})));  // x/(−z) = 0.5 inside
}

// Random cameras, windows and boxes near the windows' sides: every box said to be missed is
// met by none of the camera's rays through the window, and the boxes that project clearly
// outside are said to be missed.
TEST(CameraWindowTest, MissedBoxesAreMetByNoRayOfTheWindow) {
    std::mt19937 random(7);
    std::uniform_real_distribution<float> unit(-1, 1), positive(0, 1);
    int missed = 0, clearly_outside = 0, checked = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        const Vec3f center{unit(random) * 5, unit(random) * 5, unit(random) * 5};
        const Vec3f direction{unit(random), unit(random), unit(random)};
        if (length(direction) < 0.2f) continue;
        const int w = 40 + static_cast<int>(positive(random) * 200), h = 30 + static_cast<int>(positive(random) * 200);
        const Camera camera = make_camera(perspective(center, direction, {unit(random), 1, unit(random)},
                                                      20 + positive(random) * 120, w, h),
                                          w, h, Conventions::course());
        const float px0 = positive(random) * static_cast<float>(w), py0 = positive(random) * static_cast<float>(h);
        const float px1 = px0 + 1 + positive(random) * 64, py1 = py0 + 1 + positive(random) * 64;
        const CameraWindow window = camera_window(camera, px0, px1, py0, py1);
        ASSERT_TRUE(window.bounded);
        // A small box around a point seen through a pixel point near the window (within a few
        // pixels of a side, inside or out), at some distance.
        const float qx = px0 + (px1 - px0) * (positive(random) * 1.4f - 0.2f);
        const float qy = py0 + (py1 - py0) * (positive(random) * 1.4f - 0.2f);
        const float distance = 0.5f + positive(random) * 20;
        const Vec3f p = camera_ray(camera, qx, qy).at(distance);
        const float half = positive(random) * 0.05f * distance;
        const Bounds3f b = box(p - Vec3f{half, half, half}, p + Vec3f{half, half, half});
        // Where the box projects: all eight corners in front and beyond one side by two pixels?
        bool outside[4] = {true, true, true, true};
        for (int i = 0; i < 8; ++i) {
            const Vec3f corner{(i & 1) ? b.upper.x : b.lower.x, (i & 2) ? b.upper.y : b.lower.y, (i & 4) ? b.upper.z : b.lower.z};
            const Vec3f v = corner - camera.center;
            const float depth = dot(v, camera.direction);
            if (!(depth > 0)) {
                for (bool& o : outside) o = false;
                break;
            }
            const float x = camera.cx + camera.fx * dot(v, camera.horizontal) / depth;
            const float y = camera.cy + camera.fy * dot(v, camera.up) / depth;
            outside[0] = outside[0] && x < px0 - 2;
            outside[1] = outside[1] && x > px1 + 2;
            outside[2] = outside[2] && y < py0 - 2;
            outside[3] = outside[3] && y > py1 + 2;
        }
        const bool is_clearly_outside = outside[0] || outside[1] || outside[2] || outside[3];
        const bool is_missed = window_misses_box(window, b);
        if (is_clearly_outside) {
            ++clearly_outside;
            EXPECT_TRUE(is_missed) << "trial " << trial;
        }
        if (!is_missed) continue;
        ++missed;
        for (const Vec2f& q : window_points(px0, px1, py0, py1, random)) {
            ++checked;
            ASSERT_FALSE(ray_meets_box(camera_ray(camera, q.x, q.y), b))
                << "trial " << trial << ": the ray through (" << q.x << ", " << q.y << ") meets a box said to be missed";
        }
    }
    // Both kinds were met often enough for the checks to mean something.
    EXPECT_GT(missed, 150);
    EXPECT_GT(clearly_outside, 80);
    EXPECT_GT(checked, 15000);
}

TEST(CameraWindowTest, APlaneIsMissedByWindowsThatLookAwayFromIt) {
    // 1 above the floor y = 0, looking down −z: the upper half of the image (py > 32, y up)
    // looks above the horizon.
    Camera camera = square_camera();
    camera.center = {0, 1, 0};
    const Plane floor{{0, 1, 0}, 0};
    EXPECT_TRUE(window_misses_plane(camera_window(camera, 0, 64, 34, 64), floor));
    EXPECT_FALSE(window_misses_plane(camera_window(camera, 0, 64, 0, 30), floor));
    EXPECT_FALSE(window_misses_plane(camera_window(camera, 0, 64, 30, 34), floor));  // across the horizon
    EXPECT_FALSE(window_misses_plane(camera_window(camera, 0, 64, 32, 64), floor));  // up to the horizon's rays
    // The same plane written with its normal the other way round, and scaled, is the same plane.
    EXPECT_TRUE(window_misses_plane(camera_window(camera, 0, 64, 34, 64), Plane{{0, -2, 0}, 0}));
    // A camera on the plane: its rays start where t = 0, and rounding decides; nothing is missed.
    Camera on_floor = camera;
    on_floor.center = {0, 0, 0};
    EXPECT_FALSE(window_misses_plane(camera_window(on_floor, 0, 64, 34, 64), floor));
    // A plane of no normal is never hit, but nothing is claimed about it either.
    EXPECT_FALSE(window_misses_plane(camera_window(camera, 0, 64, 34, 64), Plane{{0, 0, 0}, 1}));
}

TEST(CameraWindowTest, MissedPlanesAreHitByNoRayOfTheWindow) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(-1, 1), positive(0, 1);
    int missed = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const Vec3f direction{unit(random), unit(random), unit(random)};
        if (length(direction) < 0.2f) continue;
        const Camera camera = make_camera(perspective({unit(random) * 3, unit(random) * 3, unit(random) * 3}, direction,
                                                      {0, 1, 0}, 20 + positive(random) * 120, 64, 48),
                                          64, 48, Conventions::course());
        const float px0 = positive(random) * 64, py0 = positive(random) * 48;
        const float px1 = px0 + 1 + positive(random) * 32, py1 = py0 + 1 + positive(random) * 32;
        const Plane plane{{unit(random), unit(random), unit(random)}, unit(random) * 4};
        if (!window_misses_plane(camera_window(camera, px0, px1, py0, py1), plane)) continue;
        ++missed;
        for (const Vec2f& q : window_points(px0, px1, py0, py1, random)) {
            float t = 0;
            ASSERT_FALSE(intersect_plane(plane, camera_ray(camera, q.x, q.y), camera.t_min, t))
                << "trial " << trial << ": the ray through (" << q.x << ", " << q.y << ") hits a plane said to be missed";
        }
    }
    EXPECT_GT(missed, 50);
}

TEST(CameraWindowTest, TheSceneIsMissedOnlyWhereEveryObjectIs) {
    // A unit sphere 5 ahead, a 64×64 image at 90°: it covers pixel points within about 6.5
    // pixels of the centre (32·tan(asin(1/5)) ≈ 6.5).
    SceneDesc desc;
    desc.camera = perspective({0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 90, 64, 64);
    desc.materials = {test::material({1, 0, 0})};
    desc.root = test::group({test::sphere({0, 0, 0}, 1)});
    Scene scene = test::build(desc);
    const Camera& camera = scene.camera;
    EXPECT_TRUE(window_misses_scene(scene, camera_window(camera, 0, 16, 0, 16)));
    EXPECT_TRUE(window_misses_scene(scene, camera_window(camera, 48, 64, 20, 44)));
    EXPECT_FALSE(window_misses_scene(scene, camera_window(camera, 24, 40, 24, 40)));
    EXPECT_FALSE(window_misses_scene(scene, camera_window(camera, 36, 52, 20, 44)));  // the sphere's right edge
    // A floor under it is seen from the lower half only.
    desc.root = test::group({test::sphere({0, 0, 0}, 1), test::plane({0, 1, 0}, -2)});
    scene = test::build(desc);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 48, 64)));
    EXPECT_FALSE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 0, 16)));
    // A mesh, untransformed (its BVH's boxes are walked) and transformed (its instance's box,
    // which the tracer tests only where the instance BVH has more than one leaf: two spheres
    // behind the camera make it so).
    desc.meshes.push_back({"cube.obj", test::cube_mesh()});
    desc.root = test::group({test::mesh_object(0)});
    scene = test::build(desc);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 0, 16)));
    EXPECT_FALSE(window_misses_scene(scene, camera_window(scene.camera, 24, 40, 24, 40)));
    const ObjectDesc moved = test::transform(Mat4::translate({0, 0, 1}), test::mesh_object(0));
    desc.root = test::group({moved});
    scene = test::build(desc);
    ASSERT_EQ(scene.instance_bvh.nodes.size(), 1u);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 0, 16)));
    // Alone, under a matrix far from orthogonal, its box is not trusted (see
    // RenderTest.WindowsThatSeeNothingHoldAtTheEdges)...
    Mat4 skewed;
    skewed.m[0][1] = skewed.m[1][0] = 0.7f;
    skewed.m[1][1] = 0.490001f;
    const ObjectDesc squashed = test::transform(skewed, test::mesh_object(0));
    desc.root = test::group({squashed});
    scene = test::build(desc);
    ASSERT_EQ(scene.instance_bvh.nodes.size(), 1u);
    EXPECT_FALSE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 0, 16)));
    // ... but with company, the tracer tests the leaves' boxes too.
    desc.root = test::group({squashed, test::sphere({0, 0, 20}, 1), test::sphere({0, 0, 40}, 1)});
    scene = test::build(desc);
    ASSERT_GT(scene.instance_bvh.nodes.size(), 1u);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 0, 8, 0, 8)));
    desc.root = test::group({moved, test::sphere({0, 0, 20}, 1), test::sphere({0, 0, 40}, 1)});
    scene = test::build(desc);
    ASSERT_GT(scene.instance_bvh.nodes.size(), 1u);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 0, 16, 0, 16)));
    EXPECT_FALSE(window_misses_scene(scene, camera_window(scene.camera, 24, 40, 24, 40)));
    // Nothing at all: every window misses it.
    desc.root = test::group({});
    scene = test::build(desc);
    EXPECT_TRUE(window_misses_scene(scene, camera_window(scene.camera, 24, 40, 24, 40)));
}

}  // namespace
}  // namespace raycast
