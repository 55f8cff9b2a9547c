// Tests for the three primitive intersection routines (geometry/sphere.h, plane.h, triangle.h).
// Rays in object space are not unit length (a transform scales them), so every routine is checked
// with scaled directions: t must scale inversely, exactly so for a power of two. t_min must be
// respected (the far root of a sphere is taken from inside it), tangent and parallel rays must be
// handled, the plane's normal is not normalised, triangle barycentrics must be the documented
// weights, and the triangle test must be watertight: rays through shared edges and vertices of
// a mesh never slip through, and back faces are hit too.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/plane.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace raycast {
namespace {

// ---------------------------------------------------------------------------------------------
// Sphere

bool sphere_t(const Sphere& s, const Ray& ray, float t_min, float& t) { return intersect_sphere(s, ray, t_min, t); }

TEST(SphereTest, HitsTheNearSideWithAUnitDirection) {
    // Sphere at (0, 0, −5) with radius 1, seen from the origin along −z: the near side is at z = −4.
    const Sphere s{{0, 0, -5}, 1};
    float t = -1;
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 0, t));
    EXPECT_FLOAT_EQ(t, 4);
    // Off-centre: x = 0.6 meets the sphere where z = −5 + √(1 − 0.36) = −4.2.
    ASSERT_TRUE(sphere_t(s, {{0.6f, 0, 0}, {0, 0, -1}}, 0, t));
    EXPECT_FLOAT_EQ(t, 4.2f);
}

TEST(SphereTest, TScalesInverselyWithTheDirectionLength) {
    const Sphere s{{0, 0, -5}, 1};
    float t = 0;
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -2}}, 0, t));
    EXPECT_EQ(t, 2.0f);
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -0.5f}}, 0, t));
    EXPECT_EQ(t, 8.0f);
    ASSERT_TRUE(sphere_t(s, {{0.6f, 0, 0}, {0, 0, -4}}, 0, t));
    EXPECT_FLOAT_EQ(t, 4.2f / 4);

    // Random rays that hit: with direction·2 the parameter is exactly halved (every step of the
    // computation scales by a power of two), with direction·3 it is divided by 3 up to rounding.
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1, 1);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        const Sphere sphere{{u(rng) * 3, u(rng) * 3, u(rng) * 3 - 8}, 0.5f + std::fabs(u(rng))};
        const Vec3f origin{u(rng), u(rng), u(rng)};
        const Vec3f target = sphere.center + Vec3f{u(rng), u(rng), u(rng)} * (sphere.radius * 0.5f);
        const Vec3f d = (target - origin) * (0.1f + std::fabs(u(rng)));
        float t1 = 0, t2 = 0, t3 = 0;
        ASSERT_TRUE(sphere_t(sphere, {origin, d}, 0, t1));
        ASSERT_TRUE(sphere_t(sphere, {origin, d * 2}, 0, t2));
        ASSERT_TRUE(sphere_t(sphere, {origin, d * 3}, 0, t3));
        EXPECT_EQ(t2, t1 / 2);
        EXPECT_NEAR(t3, t1 / 3, 1e-5f * t1);
        // And the point is on the sphere.
        EXPECT_NEAR(length(origin + d * t1 - sphere.center), sphere.radius, 1e-4f);
        ++hits;
        if (HasFailure()) return;
    }
    EXPECT_EQ(hits, 2000);
}

// A sphere tested in the object space of a transform that shrinks it (or grows it) 1e10 times
// sees a ray direction 1e10 (or 1e-12) long: a = |d|² and the discriminant (about r²) multiply to
// 1e40 (or 1e-48), past float, and the hit came out black or vanished. root_of_product takes the
// roots apart there, and only there: the same t, 9, as the sphere at its own scale.
TEST(SphereTest, HitsWhereTheQuadraticsProductLeavesFloat) {
    for (const float scale : {1e10f, 1e-12f}) {
        SCOPED_TRACE(scale);
        const Sphere sphere{{0, 0, 0}, scale};
        float t = 0;
        ASSERT_TRUE(intersect_sphere(sphere, {{0, 0, 10 * scale}, {0, 0, -scale}}, 0, t));
        EXPECT_NEAR(t, 9, 1e-5f);
        ASSERT_TRUE(intersect_sphere(sphere, {{0.6f * scale, 0, 10 * scale}, {0, 0, -scale}}, 0, t));
        EXPECT_NEAR(t, 9.2f, 1e-5f);  // z = 0.8 on the unit sphere
    }
    // Where the product is ordinary, its own root, bit for bit.
    EXPECT_EQ(root_of_product(2.0f, 8.0f), std::sqrt(2.0f * 8.0f));
    EXPECT_EQ(root_of_product(3.0f, 0.0f), 0.0f);
    EXPECT_EQ(root_of_product(1e20f, 1e20f), 1e20f);
    EXPECT_EQ(root_of_product(1e-24f, 1e-24f), std::sqrt(1e-24f) * std::sqrt(1e-24f));
}

TEST(SphereTest, MatchesADoublePrecisionQuadratic) {
    // Reference: a·t² + 2b·t + c = 0 solved in double; the nearest root above t_min.
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1, 1);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Sphere s{{u(rng) * 2, u(rng) * 2, u(rng) * 2}, 0.3f + std::fabs(u(rng))};
        const Ray ray{{u(rng) * 3, u(rng) * 3, u(rng) * 3}, Vec3f{u(rng), u(rng), u(rng)} * (0.2f + 4 * std::fabs(u(rng)))};
        const double ox = ray.origin.x - s.center.x, oy = ray.origin.y - s.center.y, oz = ray.origin.z - s.center.z;
        const double a = double(ray.direction.x) * ray.direction.x + double(ray.direction.y) * ray.direction.y +
                         double(ray.direction.z) * ray.direction.z;
        const double b = ox * ray.direction.x + oy * ray.direction.y + oz * ray.direction.z;
        const double c = ox * ox + oy * oy + oz * oz - double(s.radius) * s.radius;
        const double disc = b * b - a * c;
        float t = 0;
        const bool hit = sphere_t(s, ray, 0, t);
        if (disc < -1e-6 * a) {
            EXPECT_FALSE(hit);
            continue;
        }
        if (disc < 1e-6 * a) continue;  // grazing: either answer is fine
        const double r0 = (-b - std::sqrt(disc)) / a, r1 = (-b + std::sqrt(disc)) / a;
        const double expected = r0 > 1e-4 ? r0 : (r1 > 1e-4 ? r1 : -1);
        if (std::fabs(r0) < 1e-4 || std::fabs(r1) < 1e-4) continue;  // origin on the surface
        if (expected < 0) {
            EXPECT_FALSE(hit);
        } else {
            ASSERT_TRUE(hit);
            EXPECT_NEAR(t, expected, 1e-4 * (1 + expected));
            ++hits;
        }
        if (HasFailure()) return;
    }
    EXPECT_GT(hits, 500);
}

TEST(SphereTest, HitsFromInsideAtTheFarRoot) {
    // From the centre of a sphere of radius 2 the only root ahead is t = r/|d|.
    const Sphere s{{1, 2, 3}, 2};
    float t = 0;
    ASSERT_TRUE(sphere_t(s, {{1, 2, 3}, {1, 0, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 2);
    ASSERT_TRUE(sphere_t(s, {{1, 2, 3}, {0, 0, -4}}, 0, t));
    EXPECT_FLOAT_EQ(t, 0.5f);
    // From (1, 2, 3) + (1, 0, 0) going +x: roots at −3 and +1.
    ASSERT_TRUE(sphere_t(s, {{2, 2, 3}, {1, 0, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 1);
    ASSERT_TRUE(sphere_t(s, {{2, 2, 3}, {-1, 0, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 3);
}

TEST(SphereTest, RespectsTMin) {
    // Roots at t = 4 and t = 6 from the origin along −z.
    const Sphere s{{0, 0, -5}, 1};
    float t = 0;
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 3.9f, t));
    EXPECT_FLOAT_EQ(t, 4);
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 4.5f, t));  // the near root is behind t_min
    EXPECT_FLOAT_EQ(t, 6);
    EXPECT_FALSE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 6.5f, t));
    // With direction ·2 the roots are 2 and 3.
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -2}}, 2.5f, t));
    EXPECT_FLOAT_EQ(t, 3);
    // A negative t_min (orthographic cameras that see behind) lets roots behind the origin count.
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, 1}}, -INFINITY, t));
    EXPECT_FLOAT_EQ(t, -6);
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, 1}}, -5, t));
    EXPECT_FLOAT_EQ(t, -4);
    // Strictly greater: a root exactly at t_min does not count.
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 4, t));
    EXPECT_FLOAT_EQ(t, 6);
}

TEST(SphereTest, MissesBesideAndBehind) {
    const Sphere s{{0, 0, -5}, 1};
    float t = 123;
    EXPECT_FALSE(sphere_t(s, {{0, 1.01f, 0}, {0, 0, -1}}, 0, t));
    EXPECT_FALSE(sphere_t(s, {{0, 0, 0}, {0, 0, 1}}, 0, t));  // the sphere is behind
    EXPECT_FALSE(sphere_t(s, {{0, 0, 0}, {1, 0, 0}}, 0, t));
    EXPECT_FALSE(sphere_t(s, {{2, 0, 0}, {0, 0, -3}}, 0, t));
    EXPECT_EQ(t, 123);  // untouched on a miss
}

TEST(SphereTest, TangentRayTouchesAtTheDoubleRoot) {
    // x = 1 grazes the unit sphere at (1, 0, −5): both roots are t = 5 (discriminant exactly 0).
    const Sphere s{{0, 0, -5}, 1};
    float t = 0;
    ASSERT_TRUE(sphere_t(s, {{1, 0, 0}, {0, 0, -1}}, 0, t));
    EXPECT_FLOAT_EQ(t, 5);
    EXPECT_FALSE(sphere_t(s, {{1.0001f, 0, 0}, {0, 0, -1}}, 0, t));
    ASSERT_TRUE(sphere_t(s, {{0.9999f, 0, 0}, {0, 0, -1}}, 0, t));
    EXPECT_NEAR(t, 5, 0.02f);
}

TEST(SphereTest, StaysAccurateFarFromTheSphere) {
    // 10⁴ units away the textbook b² − ac loses every digit; the careful form must not.
    const Sphere s{{0, 0, -10000}, 1};
    float t = 0;
    ASSERT_TRUE(sphere_t(s, {{0, 0, 0}, {0, 0, -1}}, 0, t));
    EXPECT_FLOAT_EQ(t, 9999);
    ASSERT_TRUE(sphere_t(s, {{0.5f, 0, 0}, {0, 0, -1}}, 0, t));
    // z = −10000 + √0.75 = −9999.134: t = 9999.134.
    EXPECT_NEAR(t, 10000 - std::sqrt(0.75f), 2e-3f);
    // An oblique ray aimed at a point 0.7 off the centre: the hit lies on the sphere.
    const Vec3f origin{3, -2, 1};
    const Vec3f d = normalize(Vec3f{0.7f, 0, -10000} - origin);
    ASSERT_TRUE(sphere_t(s, {origin, d}, 0, t));
    EXPECT_NEAR(length(origin + d * t - s.center), 1, 2e-3f);
}

// ---------------------------------------------------------------------------------------------
// Plane

TEST(PlaneTest, HitsWithUnitAndScaledDirections) {
    const Plane p{{0, 1, 0}, 2};  // y = 2
    float t = 0;
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {0, 1, 0}}, 0, t));
    EXPECT_EQ(t, 2);
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {0, 4, 0}}, 0, t));
    EXPECT_EQ(t, 0.5f);
    ASSERT_TRUE(intersect_plane(p, {{5, -1, 7}, {3, 1, 0}}, 0, t));  // y goes −1 → 2 at t = 3
    EXPECT_EQ(t, 3);
    // From above, looking down.
    ASSERT_TRUE(intersect_plane(p, {{0, 10, 0}, {0, -2, 0}}, 0, t));
    EXPECT_EQ(t, 4);
}

TEST(PlaneTest, NormalIsNotNormalised) {
    // n·P = offset with |n| ≠ 1: (0, 2, 0)·P = 4 is still y = 2.
    float t = 0;
    ASSERT_TRUE(intersect_plane({{0, 2, 0}, 4}, {{0, 0, 0}, {0, 1, 0}}, 0, t));
    EXPECT_EQ(t, 2);
    // 3x + 4y = 10: along +x from the origin x = 10/3; along +y, y = 2.5; along (1, 1, 0), 7t = 10.
    const Plane p{{3, 4, 0}, 10};
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {1, 0, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 10.0f / 3);
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {0, 1, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 2.5f);
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {1, 1, 0}}, 0, t));
    EXPECT_FLOAT_EQ(t, 10.0f / 7);
    // The hit point satisfies the plane equation.
    const Ray ray{{1, -2, 3}, {0.3f, 0.9f, -0.2f}};
    ASSERT_TRUE(intersect_plane(p, ray, 0, t));
    EXPECT_NEAR(dot(p.normal, ray.at(t)), 10, 1e-5f);
}

TEST(PlaneTest, ParallelRaysMiss) {
    const Plane p{{0, 1, 0}, 2};
    float t = 123;
    EXPECT_FALSE(intersect_plane(p, {{0, 0, 0}, {1, 0, 0}}, 0, t));
    EXPECT_FALSE(intersect_plane(p, {{0, 2, 0}, {1, 0, 1}}, 0, t));  // even lying in the plane
    EXPECT_FALSE(intersect_plane(p, {{0, 0, 0}, {1, 0, 0}}, -INFINITY, t));
    EXPECT_EQ(t, 123);
}

TEST(PlaneTest, RespectsTMin) {
    const Plane p{{0, 1, 0}, 2};
    float t = 0;
    EXPECT_FALSE(intersect_plane(p, {{0, 0, 0}, {0, -1, 0}}, 0, t));  // behind: t = −2
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {0, -1, 0}}, -INFINITY, t));
    EXPECT_EQ(t, -2);
    EXPECT_FALSE(intersect_plane(p, {{0, 0, 0}, {0, 1, 0}}, 2, t));  // exactly at t_min: not greater
    ASSERT_TRUE(intersect_plane(p, {{0, 0, 0}, {0, 1, 0}}, 1.999f, t));
    EXPECT_EQ(t, 2);
}

// ---------------------------------------------------------------------------------------------
// Triangle

bool tri(const Ray& ray, Vec3f p0, Vec3f p1, Vec3f p2, float t_min, TriangleHit& hit) {
    return intersect_triangle(make_watertight_ray(ray), p0, p1, p2, t_min, hit);
}

TEST(TriangleTest, BarycentricsAreTheWeightsOfP1AndP2) {
    // The point (0.25, 0.5) of the triangle (0,0,0), (1,0,0), (0,1,0) is
    // 0.25·p0 + 0.25·p1 + 0.5·p2, so u = 0.25 (weight of p1) and v = 0.5 (weight of p2). All the
    // arithmetic is exact here (the edge functions are 0.25, 0.25, 0.5 and det = 1).
    const Vec3f p0{0, 0, 0}, p1{1, 0, 0}, p2{0, 1, 0};
    TriangleHit h{};
    ASSERT_TRUE(tri({{0.25f, 0.5f, 1}, {0, 0, -1}}, p0, p1, p2, 0, h));
    EXPECT_EQ(h.t, 1);
    EXPECT_EQ(h.u, 0.25f);
    EXPECT_EQ(h.v, 0.5f);
    // Listing the vertices in another order permutes the weights with them.
    ASSERT_TRUE(tri({{0.25f, 0.5f, 1}, {0, 0, -1}}, p0, p2, p1, 0, h));
    EXPECT_EQ(h.u, 0.5f);
    EXPECT_EQ(h.v, 0.25f);
    ASSERT_TRUE(tri({{0.25f, 0.5f, 1}, {0, 0, -1}}, p1, p2, p0, 0, h));
    EXPECT_EQ(h.u, 0.5f);   // p2 is now second
    EXPECT_EQ(h.v, 0.25f);  // p0 is now third
    // At the vertices: (u, v) = (0, 0) at p0, (1, 0) at p1, (0, 1) at p2.
    ASSERT_TRUE(tri({{1, 0, 1}, {0, 0, -1}}, p0, p1, p2, 0, h));
    EXPECT_EQ(h.u, 1);
    EXPECT_EQ(h.v, 0);
    ASSERT_TRUE(tri({{0, 1, 1}, {0, 0, -1}}, p0, p1, p2, 0, h));
    EXPECT_EQ(h.u, 0);
    EXPECT_EQ(h.v, 1);
}

TEST(TriangleTest, ObliqueRayThroughTheCentroid) {
    // The triangle (1,0,0), (0,1,0), (0,0,1) lies in x + y + z = 1; the ray from the origin along
    // (1, 1, 1) meets it at the centroid (1/3, 1/3, 1/3): t = 1/3, u = v = 1/3.
    const Vec3f p0{1, 0, 0}, p1{0, 1, 0}, p2{0, 0, 1};
    TriangleHit h{};
    ASSERT_TRUE(tri({{0, 0, 0}, {1, 1, 1}}, p0, p1, p2, 0, h));
    EXPECT_NEAR(h.t, 1.0f / 3, 1e-7f);
    EXPECT_NEAR(h.u, 1.0f / 3, 1e-7f);
    EXPECT_NEAR(h.v, 1.0f / 3, 1e-7f);
    TriangleHit h2{};
    ASSERT_TRUE(tri({{0, 0, 0}, {2, 2, 2}}, p0, p1, p2, 0, h2));
    EXPECT_EQ(h2.t, h.t / 2);
    EXPECT_EQ(h2.u, h.u);
    EXPECT_EQ(h2.v, h.v);
}

TEST(TriangleTest, RandomPointsGiveTheirBarycentricsBackAndTScales) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u01(0, 1), u(-2, 2);
    for (int i = 0; i < 5000; ++i) {
        const Vec3f p0{u(rng), u(rng), u(rng)}, p1{u(rng), u(rng), u(rng)}, p2{u(rng), u(rng), u(rng)};
        const Vec3f n = cross(p1 - p0, p2 - p0);
        if (length(n) < 0.5f) continue;  // keep the triangles well shaped
        // Uniform in the triangle, kept 0.02 away from its edges.
        float bu = u01(rng), bv = u01(rng);
        if (bu + bv > 1) {
            bu = 1 - bu;
            bv = 1 - bv;
        }
        if (bu < 0.02f || bv < 0.02f || bu + bv > 0.98f) continue;
        const Vec3f target = p0 * (1 - bu - bv) + p1 * bu + p2 * bv;
        Vec3f origin{u(rng) * 3, u(rng) * 3, u(rng) * 3};
        if (std::fabs(dot(normalize(n), normalize(target - origin))) < 0.2f) continue;  // not too grazing
        const Vec3f d = target - origin;
        TriangleHit h{}, h2{}, h3{};
        ASSERT_TRUE(tri({origin, d}, p0, p1, p2, 0, h));
        EXPECT_NEAR(h.t, 1, 1e-4f);
        EXPECT_NEAR(h.u, bu, 1e-4f);
        EXPECT_NEAR(h.v, bv, 1e-4f);
        ASSERT_TRUE(tri({origin, d * 2}, p0, p1, p2, 0, h2));
        EXPECT_EQ(h2.t, h.t / 2);  // scaling by a power of two is exact at every step
        ASSERT_TRUE(tri({origin, d * 0.3f}, p0, p1, p2, 0, h3));
        EXPECT_NEAR(h3.t, h.t / 0.3f, 1e-5f * h3.t);
        EXPECT_NEAR(h3.u, h.u, 1e-5f);
        // Both windings are hit: the same triangle listed clockwise.
        TriangleHit back{};
        ASSERT_TRUE(tri({origin, d}, p0, p2, p1, 0, back));
        EXPECT_NEAR(back.t, h.t, 1e-6f);  // the sums run in another order: equal up to rounding
        EXPECT_NEAR(back.u, h.v, 1e-6f);
        if (HasFailure()) return;
    }
}

TEST(TriangleTest, BackFacesAreHit) {
    // triangle_normal of (0,0,0), (1,0,0), (0,1,0) is +z; a ray coming from below hits its back.
    const Vec3f p0{0, 0, 0}, p1{1, 0, 0}, p2{0, 1, 0};
    EXPECT_EQ(triangle_normal(p0, p1, p2), (Vec3f{0, 0, 1}));
    TriangleHit h{};
    ASSERT_TRUE(tri({{0.25f, 0.5f, -3}, {0, 0, 1}}, p0, p1, p2, 0, h));
    EXPECT_EQ(h.t, 3);
    EXPECT_EQ(h.u, 0.25f);
    EXPECT_EQ(h.v, 0.5f);
    ASSERT_TRUE(tri({{0.25f, 0.5f, -3}, {0, 0, 2}}, p0, p1, p2, 0, h));
    EXPECT_EQ(h.t, 1.5f);
}

TEST(TriangleTest, MissesOutsideBehindAndEdgeOn) {
    const Vec3f p0{0, 0, 0}, p1{1, 0, 0}, p2{0, 1, 0};
    TriangleHit h{};
    EXPECT_FALSE(tri({{0.75f, 0.75f, 1}, {0, 0, -1}}, p0, p1, p2, 0, h));   // beyond the hypotenuse
    EXPECT_FALSE(tri({{-0.1f, 0.5f, 1}, {0, 0, -1}}, p0, p1, p2, 0, h));   // left of x = 0
    EXPECT_FALSE(tri({{0.25f, 0.25f, 1}, {0, 0, 1}}, p0, p1, p2, 0, h));    // triangle behind the origin
    EXPECT_FALSE(tri({{0.25f, 0.25f, 1}, {0, 0, -1}}, p0, p1, p2, 1, h));   // t = 1 is not > t_min = 1
    EXPECT_FALSE(tri({{0.25f, 0.25f, 1}, {0, 0, -1}}, p0, p1, p2, 5, h));
    ASSERT_TRUE(tri({{0.25f, 0.25f, 1}, {0, 0, 1}}, p0, p1, p2, -INFINITY, h));
    EXPECT_EQ(h.t, -1);
    // A ray in the triangle's plane sees zero area: no hit, even through the inside.
    EXPECT_FALSE(tri({{-1, 0.25f, 0}, {1, 0, 0}}, p0, p1, p2, 0, h));
    // Degenerate triangles (collinear or repeated vertices) are never hit.
    EXPECT_FALSE(tri({{0.5f, 0, 1}, {0, 0, -1}}, p0, p1, {2, 0, 0}, 0, h));
    EXPECT_FALSE(tri({{0, 0, 1}, {0, 0, -1}}, p0, p0, p0, 0, h));
}

// A fan of triangles around a centre vertex, bent slightly out of its plane and turned to a
// random orientation, as a mesh stores it: each spoke (centre → ring vertex) is shared by two
// triangles, listed with opposite directions along it (consistent winding). Neighbouring spokes
// are at most 126 degrees apart and the bending is small, so that the fan stays a disk (does not
// fold over itself) in every projection the rays below use: every inner point is covered.
struct Fan {
    Vec3f centre;
    std::vector<Vec3f> ring;
    Vec3f normal;  // roughly the fan's normal

    Vec3f p(size_t i) const { return ring[i % ring.size()]; }
};

Fan random_fan(std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1, 1);
    // A random orthonormal frame.
    const Vec3f z = normalize(Vec3f{u(rng), u(rng), u(rng) + 0.01f});
    const Vec3f x = normalize(cross(z, std::fabs(z.x) < 0.9f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0}));
    const Vec3f y = cross(z, x);
    Fan fan;
    const Vec3f origin{u(rng) * 10, u(rng) * 10, u(rng) * 10};
    fan.centre = origin + z * (0.01f * u(rng));
    fan.normal = z;
    const int count = 4 + static_cast<int>(std::fabs(u(rng)) * 8);
    const float step = 6.2831853f / static_cast<float>(count);
    for (int i = 0; i < count; ++i) {
        const float angle = step * (static_cast<float>(i) + 0.2f * u(rng));
        const float radius = 1 + 0.5f * u(rng);
        fan.ring.push_back(origin + x * (radius * std::cos(angle)) + y * (radius * std::sin(angle)) + z * (0.01f * u(rng)));
    }
    return fan;
}

// The nearest hit among the fan's triangles, or t = inf.
float nearest_fan_hit(const Fan& fan, const Ray& ray, int* hits = nullptr) {
    const WatertightRay w = make_watertight_ray(ray);
    float best = INFINITY;
    if (hits) *hits = 0;
    for (size_t i = 0; i < fan.ring.size(); ++i) {
        TriangleHit h{};
        if (intersect_triangle(w, fan.centre, fan.p(i), fan.p(i + 1), 0, h)) {
            best = std::fmin(best, h.t);
            if (hits) ++*hits;
        }
    }
    return best;
}

TEST(TriangleTest, RaysThroughSharedEdgesAndVerticesOfAFanNeverSlipThrough) {
    // Rays aimed exactly at the shared centre vertex, and at points computed on the shared
    // spokes, from random origins on the fan's front or back side: at least one triangle is hit,
    // where the ray crosses the fan (t ≈ 1, since the direction is target − origin).
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> u(-1, 1), u01(0, 1);
    int rays = 0;
    for (int f = 0; f < 300; ++f) {
        const Fan fan = random_fan(rng);
        for (int r = 0; r < 60; ++r) {
            Vec3f target = fan.centre;
            if (r % 3 != 0) {
                const Vec3f tip = fan.p(static_cast<size_t>(r) % fan.ring.size());
                target = fan.centre + (tip - fan.centre) * (0.02f + 0.96f * u01(rng));
            }
            // An origin 1 to 20 units away on either side, not too grazing.
            Vec3f offset = normalize(Vec3f{u(rng), u(rng), u(rng)});
            float side = dot(offset, fan.normal);
            if (std::fabs(side) < 0.5f) offset = normalize(offset + fan.normal * (side < 0 ? -1.0f : 1.0f));
            const Vec3f origin = target + offset * (1 + 19 * u01(rng));
            const Ray ray{origin, target - origin};
            int hits = 0;
            const float t = nearest_fan_hit(fan, ray, &hits);
            ASSERT_GE(hits, 1) << "fan " << f << " ray " << r << " slipped through";
            EXPECT_NEAR(t, 1, 1e-3f);
            // Scaled directions see the same triangles.
            int hits_scaled = 0;
            nearest_fan_hit(fan, {origin, (target - origin) * 0.37f}, &hits_scaled);
            EXPECT_GE(hits_scaled, 1);
            ++rays;
        }
        if (HasFailure()) return;
    }
    EXPECT_EQ(rays, 300 * 60);
}

TEST(TriangleTest, RaysExactlyOnGridEdgesAndVerticesHit) {
    // A 4×4 grid in z = 0 with integer vertices, each square cut along one of its diagonals.
    // Rays straight down and oblique through every inner point of a 1/8 lattice: every inner
    // vertex, edge and diagonal point must be hit. For the first directions every step of the
    // test is exact (edge functions evaluate to exactly 0 on an edge, t to exactly 2); the last
    // one has an inexact shear (1/3), where only the watertight construction keeps the hits.
    struct Tri {
        Vec3f a, b, c;
    };
    std::vector<Tri> grid;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const float x = static_cast<float>(i), y = static_cast<float>(j);
            const Vec3f p00{x, y, 0}, p10{x + 1, y, 0}, p01{x, y + 1, 0}, p11{x + 1, y + 1, 0};
            if ((i + j) % 2 == 0) {
                grid.push_back({p00, p10, p11});
                grid.push_back({p00, p11, p01});
            } else {
                grid.push_back({p10, p11, p01});  // the other diagonal
                grid.push_back({p10, p01, p00});
            }
        }
    const Vec3f directions[] = {{0, 0, -1}, {0, 0, 1}, {0.25f, 0.125f, -1}, {-0.5f, 0.25f, 1}, {1, 1, -1}, {3, -1, 2}};
    for (const Vec3f& d : directions) {
        const bool exact = d.x != 3;
        for (int i = 1; i < 32; ++i)
            for (int j = 1; j < 32; ++j) {
                const Vec3f target{static_cast<float>(i) / 8, static_cast<float>(j) / 8, 0};
                const Ray ray{target - d * 2, d};  // exact: d·2 and the subtraction are exact here
                const WatertightRay w = make_watertight_ray(ray);
                int hits = 0;
                float nearest = INFINITY;
                for (const Tri& t : grid) {
                    TriangleHit h{};
                    if (intersect_triangle(w, t.a, t.b, t.c, 0, h)) {
                        ++hits;
                        nearest = std::fmin(nearest, h.t);
                    }
                }
                ASSERT_GE(hits, 1) << "(" << target.x << ", " << target.y << ") along (" << d.x << ", " << d.y << ", "
                                   << d.z << ")";
                if (exact) {
                    EXPECT_EQ(nearest, 2);
                } else {
                    EXPECT_NEAR(nearest, 2, 1e-5f);
                }
            }
    }
}

}  // namespace
}  // namespace raycast
