// The camera (scene/camera.h) against directions worked out by hand from the course's formula
// (course-format.md §b): dir = normalize(((x − cx)/fx)·horizontal + ((y − cy)/fy)·up + direction),
// horizontal = normalize(direction × up), up re-derived as horizontal × direction, y = 0 the
// bottom row. Also the conventions that change it (square or stretched pixels, MIT's pixel
// centres), the orthographic camera and the thin lens. Every primary ray of every image starts
// here, so an error in a sign or a half pixel shifts whole images.
#include "scene/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "scene_builders.h"

namespace raycast {
namespace {

using test::perspective;

constexpr float kTol = 1e-6f;

void expect_vec_near(Vec3f actual, Vec3f expected, float tolerance = kTol) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << "x";
    EXPECT_NEAR(actual.y, expected.y, tolerance) << "y";
    EXPECT_NEAR(actual.z, expected.z, tolerance) << "z";
}

Vec3f unit(float x, float y, float z) {
    const double len = std::sqrt(double{x} * x + double{y} * y + double{z} * z);
    return {static_cast<float>(x / len), static_cast<float>(y / len), static_cast<float>(z / len)};
}

// A 4×2 camera at (1, 2, 3) looking down −z with a non-unit direction (0, 0, −2) and a tilted,
// non-unit up (0, 2, 2). By hand: direction (0, 0, −1); direction × up = (0·2 − (−2)·2, …) ∝ (1, 0, 0),
// so horizontal (1, 0, 0); up = horizontal × direction = (1, 0, 0) × (0, 0, −1) = (0, 1, 0).
// angle 90°: tan 45° = 1, so fy = (h/2)/1 = 1, and with square pixels fx = fy = 1; cx = 2, cy = 1.
Camera small_camera(FovAxis axis = FovAxis::Vertical) {
    Conventions conventions;
    conventions.fov_axis = axis;
    return make_camera(perspective({1, 2, 3}, {0, 0, -2}, {0, 2, 2}, 90, 4, 2), 4, 2, conventions);
}

// camera_rays_at makes many rays at once in vectorised loops; each must be camera_ray_at's bit
// for bit, for any count (a chunk of 16, a part of one, several), on a tilted camera.
TEST(CameraTest, RaysMadeTogetherAreEachRayMadeAloneBitForBit) {
    const Camera camera = make_camera(perspective({1, 2, 3}, {0.3f, -0.2f, -2}, {0.1f, 2, 2}, 50, 37, 23), 37, 23,
                                      Conventions{});
    float a[40], b[40];
    for (int i = 0; i < 40; ++i) {
        a[i] = camera_plane_x(camera, static_cast<float>(i) * 0.93f);
        b[i] = camera_plane_y(camera, static_cast<float>(i % 23) + 0.25f);
    }
    for (const int count : {1, 7, 16, 17, 40}) {
        Ray rays[40];
        camera_rays_at(camera, a, b, count, rays);
        for (int i = 0; i < count; ++i) {
            const Ray alone = camera_ray_at(camera, a[i], b[i]);
            EXPECT_EQ(std::memcmp(&rays[i], &alone, sizeof alone), 0) << "count " << count << " ray " << i;
        }
    }
}

TEST(CameraTest, BasisIsNormalizedAndUpIsRederivedFromATiltedUp) {
    const Camera camera = small_camera();
    EXPECT_EQ(camera.projection, Camera::Projection::Perspective);
    expect_vec_near(camera.center, {1, 2, 3});
    expect_vec_near(camera.direction, {0, 0, -1});
    expect_vec_near(camera.horizontal, {1, 0, 0});
    expect_vec_near(camera.up, {0, 1, 0});
    EXPECT_EQ(camera.width, 4);
    EXPECT_EQ(camera.height, 2);
    EXPECT_FLOAT_EQ(camera.cx, 2);
    EXPECT_FLOAT_EQ(camera.cy, 1);
    EXPECT_NEAR(camera.fx, 1, kTol);
    EXPECT_NEAR(camera.fy, 1, kTol);
    EXPECT_EQ(camera.pixel_offset, 0);
    EXPECT_EQ(camera.t_min, 0);
    EXPECT_EQ(camera.lens_radius, 0);
}

TEST(CameraTest, PixelDirectionsOfCornersAndCentreMatchHandValues) {
    const Camera camera = small_camera();
    // (0, 0): a = (0 − 2)/1 = −2, b = (0 − 1)/1 = −1: normalize(−2·(1,0,0) − (0,1,0) + (0,0,−1)).
    Ray ray = camera_ray(camera, 0, 0);
    expect_vec_near(ray.origin, {1, 2, 3});
    expect_vec_near(ray.direction, unit(-2, -1, -1));
    // (w/2, h/2) = (2, 1): the view direction itself.
    ray = camera_ray(camera, 2, 1);
    expect_vec_near(ray.origin, {1, 2, 3});
    expect_vec_near(ray.direction, {0, 0, -1});
    // (w − 1, h − 1) = (3, 1): a = 1, b = 0.
    ray = camera_ray(camera, 3, 1);
    expect_vec_near(ray.direction, unit(1, 0, -1));
}

TEST(CameraTest, RowZeroIsTheBottomRowAndColumnZeroTheLeft) {
    const Camera camera = small_camera();
    // Column 2 is the centre column: row 0 looks down (−up), row 1 (the centre) straight ahead.
    EXPECT_LT(camera_ray(camera, 2, 0).direction.y, -0.5f);
    EXPECT_NEAR(camera_ray(camera, 2, 1).direction.y, 0, kTol);
    // Larger x looks towards +horizontal (+x here), smaller x towards −x.
    EXPECT_LT(camera_ray(camera, 0, 1).direction.x, -0.5f);
    EXPECT_GT(camera_ray(camera, 3, 1).direction.x, 0.5f);
}

TEST(CameraTest, TiltedViewUsesNormalizedHorizontalAndRederivedUp) {
    // scene02's camera: direction (−0.5, −0.5, −1), up (0, 1, 0), angle 30, 200×200.
    // By hand, with d = (−0.5, −0.5, −1): d × up = (1, 0, −0.5), normalised (1, 0, −0.5)/√1.25.
    // up = horizontal × direction = (1, 0, −0.5) × (−0.5, −0.5, −1) / (√1.25·√1.5)
    //    = (−0.25, 1.25, −0.5)/√1.875 (already unit: 0.0625 + 1.5625 + 0.25 = 1.875).
    const Camera camera = make_camera(perspective({5, 5, 10}, {-0.5f, -0.5f, -1}, {0, 1, 0}, 30, 200, 200), 200,
                                      200, Conventions::course());
    const Vec3f d = unit(-0.5f, -0.5f, -1);
    const Vec3f h = unit(1, 0, -0.5f);
    const Vec3f u = unit(-0.25f, 1.25f, -0.5f);
    expect_vec_near(camera.direction, d);
    expect_vec_near(camera.horizontal, h);
    expect_vec_near(camera.up, u);
    EXPECT_NEAR(length(camera.horizontal), 1, kTol);  // not sin θ ≈ 0.913 (the 2020 starter)
    EXPECT_NEAR(dot(camera.horizontal, camera.up), 0, kTol);
    EXPECT_NEAR(dot(camera.direction, camera.up), 0, kTol);
    // fx = fy = 100 / tan 15° = 100 / 0.2679491924 = 373.2050808.
    const double f = 100 / std::tan(15 * 3.14159265358979 / 180);
    EXPECT_NEAR(camera.fx, f, 1e-3);
    EXPECT_NEAR(camera.fy, f, 1e-3);
    // Pixel (0, 0): a = b = −100/f = −tan 15°; pixel (199, 199): a = b = 99/f.
    const float t15 = static_cast<float>(100 / f), t99 = static_cast<float>(99 / f);
    expect_vec_near(camera_ray(camera, 0, 0).direction, normalize(-t15 * h - t15 * u + d), 2e-6f);
    expect_vec_near(camera_ray(camera, 100, 100).direction, d);
    expect_vec_near(camera_ray(camera, 199, 199).direction, normalize(t99 * h + t99 * u + d), 2e-6f);
    expect_vec_near(camera_ray(camera, 0, 0).origin, {5, 5, 10});
}

TEST(CameraTest, AngleIsTheFullVerticalFieldOfView) {
    // The ray through the middle of the bottom edge, (w/2, 0), is angle/2 below the view direction,
    // and the one through the middle of the top edge, (w/2, h), angle/2 above it.
    for (float angle : {20.0f, 30.0f, 60.0f, 120.0f}) {
        const Camera camera = make_camera(perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, angle, 64, 48), 64, 48,
                                          Conventions::course());
        const double half = angle / 2 * 3.14159265358979 / 180;
        const Vec3f bottom = camera_ray(camera, 32, 0).direction;
        const Vec3f top = camera_ray(camera, 32, 48).direction;
        EXPECT_NEAR(bottom.y, -std::sin(half), 1e-6) << angle;
        EXPECT_NEAR(top.y, std::sin(half), 1e-6) << angle;
        EXPECT_NEAR(std::acos(static_cast<double>(dot(bottom, camera.direction))), half, 1e-4) << angle;
    }
}

TEST(CameraTest, NonSquareImagesGetSquarePixelsByDefault) {
    // 4×2 at 90°: fx = fy = (h/2)/tan 45° = 1, so one pixel step is the same angle-space step
    // horizontally and vertically; the horizontal field of view is wider than 90°.
    const Camera camera = small_camera(FovAxis::Vertical);
    EXPECT_FLOAT_EQ(camera.fx, camera.fy);
    // Left edge (x = 0): a = −2, i.e. 2 units across per unit ahead: 2·atan(2) ≈ 126.9° horizontally.
    expect_vec_near(camera_ray(camera, 0, 1).direction, unit(-2, 0, -1));
    // One pixel right of centre and one pixel up from centre are the same angle off axis.
    const Vec3f right = camera_ray(camera, 3, 1).direction;
    const Vec3f above = camera_ray(camera, 2, 2).direction;
    EXPECT_NEAR(right.x, above.y, kTol);
}

TEST(CameraTest, FovAxisBothStretchesPixelsSoBothAxesSpanTheAngle) {
    // FovAxis::Both: fx = (w/2)/tan 45° = 2, fy = (h/2)/tan 45° = 1.
    const Camera camera = small_camera(FovAxis::Both);
    EXPECT_NEAR(camera.fx, 2, kTol);
    EXPECT_NEAR(camera.fy, 1, kTol);
    // (0, 0): a = −2/2 = −1, b = −1.
    expect_vec_near(camera_ray(camera, 0, 0).direction, unit(-1, -1, -1));
    // (3, 1): a = 1/2, b = 0.
    expect_vec_near(camera_ray(camera, 3, 1).direction, unit(0.5f, 0, -1));
    // The left edge is now exactly 45° off axis, like the bottom edge.
    expect_vec_near(camera_ray(camera, 0, 1).direction, unit(-1, 0, -1));
    // A square image is the same either way.
    Conventions both;
    both.fov_axis = FovAxis::Both;
    const CameraDesc square = perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 40, 50, 50);
    EXPECT_FLOAT_EQ(make_camera(square, 50, 50, both).fx, make_camera(square, 50, 50, Conventions::course()).fx);
}

TEST(CameraTest, ImageSizeComesFromTheArgumentsNotTheDescription) {
    // The description says 4×2; a build with --size 8×8 passes 8, 8.
    const Camera camera =
        make_camera(perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 4, 2), 8, 8, Conventions::course());
    EXPECT_EQ(camera.width, 8);
    EXPECT_EQ(camera.height, 8);
    EXPECT_FLOAT_EQ(camera.cx, 4);
    EXPECT_FLOAT_EQ(camera.cy, 4);
    EXPECT_NEAR(camera.fy, 4, 1e-5);  // 4 / tan 45°
}

TEST(CameraTest, MitConventionsUsePixelCentres) {
    const CameraDesc desc = perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 2, 2);
    const Camera course = make_camera(desc, 2, 2, Conventions::course());
    const Camera mit = make_camera(desc, 2, 2, Conventions::mit6837());
    EXPECT_EQ(course.pixel_offset, 0.0f);
    EXPECT_EQ(mit.pixel_offset, 0.5f);
    // The renderer asks for pixel (x, y) at (x + offset, y + offset). fx = fy = 1/tan 45° = 1, cx = cy = 1.
    // MIT: pixel (0, 0) at (0.5, 0.5): a = b = −0.5; pixel (1, 1) at (1.5, 1.5): a = b = +0.5, a mirror image.
    const Vec3f mit00 = camera_ray(mit, 0 + mit.pixel_offset, 0 + mit.pixel_offset).direction;
    const Vec3f mit11 = camera_ray(mit, 1 + mit.pixel_offset, 1 + mit.pixel_offset).direction;
    expect_vec_near(mit00, unit(-0.5f, -0.5f, -1));
    expect_vec_near(mit11, unit(0.5f, 0.5f, -1));
    // Course: pixel (0, 0) at (0, 0): a = b = −1; pixel (1, 1) at (1, 1): the axis itself.
    expect_vec_near(camera_ray(course, 0, 0).direction, unit(-1, -1, -1));
    expect_vec_near(camera_ray(course, 1, 1).direction, {0, 0, -1});
}

CameraDesc orthographic(float size, int w, int h) {
    CameraDesc desc;
    desc.kind = CameraDesc::Kind::Orthographic;
    desc.center = {1, 2, 3};
    desc.direction = {0, 0, -5};
    desc.up = {0, 3, 0};
    desc.size = size;
    desc.width = w;
    desc.height = h;
    return desc;
}

TEST(CameraTest, OrthographicRaysAreParallelWithOriginsSpreadOverSize) {
    // size 2 on a 4×4 image: fx = fy = 4/2 = 2 pixels per unit, cx = cy = 2.
    const Camera camera = make_camera(orthographic(2, 4, 4), 4, 4, Conventions::course());
    EXPECT_EQ(camera.projection, Camera::Projection::Orthographic);
    EXPECT_NEAR(camera.fx, 2, kTol);
    EXPECT_NEAR(camera.fy, 2, kTol);
    EXPECT_EQ(camera.t_min, 0);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const Ray ray = camera_ray(camera, static_cast<float>(x), static_cast<float>(y));
            expect_vec_near(ray.direction, {0, 0, -1});
            // Origin: center + ((x − 2)/2)·(1, 0, 0) + ((y − 2)/2)·(0, 1, 0).
            expect_vec_near(ray.origin, {1 + (static_cast<float>(x) - 2) / 2, 2 + (static_cast<float>(y) - 2) / 2, 3});
        }
    // The image plane from its left edge (px = 0) to its right edge (px = w) is `size` wide.
    EXPECT_NEAR(camera_ray(camera, 4, 0).origin.x - camera_ray(camera, 0, 0).origin.x, 2, kTol);
    EXPECT_NEAR(camera_ray(camera, 0, 4).origin.y - camera_ray(camera, 0, 0).origin.y, 2, kTol);
}

TEST(CameraTest, OrthographicSizeSpansTheHeightWithSquarePixelsOrBothWhenStretched) {
    // 8×4, size 2: square pixels: 4/2 = 2 pixels per unit both ways, so the width spans 4 units.
    Conventions vertical;
    vertical.fov_axis = FovAxis::Vertical;
    const Camera square = make_camera(orthographic(2, 8, 4), 8, 4, vertical);
    EXPECT_NEAR(square.fx, 2, kTol);
    EXPECT_NEAR(square.fy, 2, kTol);
    EXPECT_NEAR(camera_ray(square, 8, 0).origin.x - camera_ray(square, 0, 0).origin.x, 4, kTol);
    // Stretched (the course's default): the width spans the size too, 8/2 = 4 pixels per unit.
    const Camera stretched = make_camera(orthographic(2, 8, 4), 8, 4, Conventions::course());
    EXPECT_NEAR(stretched.fx, 4, kTol);
    EXPECT_NEAR(camera_ray(stretched, 8, 0).origin.x - camera_ray(stretched, 0, 0).origin.x, 2, kTol);
}

TEST(CameraTest, TheCourseReadsAngleAsSpanningBothAxesAndMitAsTheVerticalOne) {
    // The course's handout: f_x = (w/2)/tan(angle/2), f_y = (h/2)/tan(angle/2). MIT 6.837's images
    // (all square) are made with angle as the vertical field of view.
    EXPECT_EQ(Conventions::course().fov_axis, FovAxis::Both);
    EXPECT_EQ(Conventions::mit6837().fov_axis, FovAxis::Vertical);
    EXPECT_EQ(Conventions{}.fov_axis, FovAxis::Both);
    // 4×2 at 90°: tan 45° = 1, so f_x = 2 and f_y = 1 under the course's reading.
    const Camera course = make_camera(perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 4, 2), 4, 2,
                                      Conventions::course());
    EXPECT_NEAR(course.fx, 2, kTol);
    EXPECT_NEAR(course.fy, 1, kTol);
}

TEST(CameraTest, MitOrthographicCameraSeesBehindItsCenter) {
    const Camera mit = make_camera(orthographic(2, 4, 4), 4, 4, Conventions::mit6837());
    EXPECT_TRUE(std::isinf(mit.t_min) && mit.t_min < 0);
    // A perspective camera never does.
    const Camera persp = make_camera(perspective({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 45, 4, 4), 4, 4,
                                     Conventions::mit6837());
    EXPECT_EQ(persp.t_min, 0);
}

Camera lens_camera() {
    Camera camera = make_camera(perspective({1, 2, 3}, {0, 0, -1}, {0, 1, 0}, 40, 64, 48), 64, 48,
                                Conventions::course());
    camera.lens_radius = 0.25f;
    camera.focus_distance = 7;
    return camera;
}

TEST(CameraTest, ThinLensCentreSampleIsThePinholeRay) {
    // The lens sample (0.5, 0.5) is the centre of the aperture (the concentric map sends the centre of
    // the unit square to the centre of the disk): that ray is the pinhole ray.
    const Camera camera = lens_camera();
    for (const Vec2f p : {Vec2f{0, 0}, Vec2f{13.25f, 40}, Vec2f{63, 47}}) {
        const Ray pinhole = camera_ray(camera, p.x, p.y);
        const Ray lens = camera_ray(camera, p.x, p.y, 0.5f, 0.5f);
        expect_vec_near(lens.origin, pinhole.origin);
        expect_vec_near(lens.direction, pinhole.direction);
    }
    // A pinhole camera (radius 0) ignores the lens sample altogether.
    Camera pinhole_camera = camera;
    pinhole_camera.lens_radius = 0;
    const Ray a = camera_ray(pinhole_camera, 5, 6, 0.1f, 0.9f);
    const Ray b = camera_ray(pinhole_camera, 5, 6);
    expect_vec_near(a.origin, b.origin, 0);
    expect_vec_near(a.direction, b.direction, 0);
}

TEST(CameraTest, ThinLensRaysOfOnePixelMeetAtTheFocusDistance) {
    const Camera camera = lens_camera();
    for (const Vec2f p : {Vec2f{0, 0}, Vec2f{32, 24}, Vec2f{50.5f, 7}}) {
        // Where the pinhole ray crosses the plane 7 units ahead (along the view direction −z): z = 3 − 7 = −4.
        const Ray pinhole = camera_ray(camera, p.x, p.y);
        const float t_focus = 7 / -pinhole.direction.z;
        const Vec3f focus = pinhole.at(t_focus);
        EXPECT_NEAR(focus.z, -4, 1e-5);
        int off_centre = 0;
        for (float u : {0.0f, 0.1f, 0.5f, 0.75f, 0.999f})
            for (float v : {0.0f, 0.3f, 0.5f, 0.9f}) {
                const Ray ray = camera_ray(camera, p.x, p.y, u, v);
                // The origin lies on the aperture disk: in the lens plane, within the radius.
                EXPECT_NEAR(dot(ray.origin - camera.center, camera.direction), 0, 1e-6);
                EXPECT_LE(length(ray.origin - camera.center), 0.25f + 1e-6f);
                if (length(ray.origin - camera.center) > 0.01f) ++off_centre;
                EXPECT_NEAR(length(ray.direction), 1, 1e-6);
                // Follow it to the focus plane: the same point for every lens sample.
                const float t = (-4 - ray.origin.z) / ray.direction.z;
                expect_vec_near(ray.at(t), focus, 2e-5f);
            }
        EXPECT_GT(off_centre, 10);  // the samples really spread over the lens
    }
    // A corner of the unit square maps to the rim of the disk.
    const Ray corner = camera_ray(camera, 10, 10, 0, 0);
    EXPECT_NEAR(length(corner.origin - camera.center), 0.25f, 1e-6);
}

TEST(CameraTest, ThinLensIsIgnoredByTheOrthographicCamera) {
    Camera camera = make_camera(orthographic(2, 4, 4), 4, 4, Conventions::course());
    camera.lens_radius = 0.5f;
    const Ray a = camera_ray(camera, 1, 2, 0.1f, 0.8f);
    const Ray b = camera_ray(camera, 1, 2);
    expect_vec_near(a.origin, b.origin, 0);
    expect_vec_near(a.direction, b.direction, 0);
}

}  // namespace
}  // namespace raycast
