// Tests for the surface of revolution (geometry/rev_surface.h).
//  - Hits and normals on a cylinder and a cone worked out by hand, for rays of every kind the
//    intersection treats apart: sloped, horizontal (d_y = 0), vertical, along the axis, non-unit.
//  - Against brute force on many random rays: the profile sampled densely with eval_curve (not the
//    Bezier pieces, not the Bernstein polynomials, not the hierarchy) and turned into a chain of
//    thin cone frustums, each intersected exactly. Every hit must be genuine (on the profile's
//    circle at its height), no clear crossing may be missed, and the nearest must be returned. Rays
//    include horizontal, vertical and near-horizontal ones, rays through the axis and rays aimed at
//    the profile's ends and turning points.
//  - Newton's method on (u, t): it converges, fast, and reports the grazing case it cannot solve.
//  - Bounds: the box of a transformed surface holds every point of a dense tessellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "geometry/rev_surface.h"

namespace raycast {
namespace {

constexpr double kTwoPi = 6.283185307179586;

Curve line_profile(Vec2f from, Vec2f to) {
    // Equally spaced collinear points: a cubic Bezier that is the straight segment, at uniform speed.
    Curve c{CurveType::Bezier, {}};
    for (int i = 0; i <= 3; ++i) {
        const float s = static_cast<float>(i) / 3;
        c.controls.push_back({from.x + s * (to.x - from.x), from.y + s * (to.y - from.y), 0});
    }
    return c;
}

bool hit_of(const RevSurface& s, const Ray& ray, RevSurfaceHit& hit, float t_min = 0) {
    return intersect_rev_surface(s, ray, t_min, INFINITY, false, hit);
}

Vec3f normal_of(const RevSurface& s, const Ray& ray, const RevSurfaceHit& hit) {
    return rev_surface_normal(s, hit.piece, hit.u, ray.at(hit.t));
}

void expect_vec_near(Vec3f a, Vec3f b, float tolerance) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(RevSurfaceTest, CylinderHitsWorkedOutByHand) {
    // x = 1, y from −1 to 1: the open cylinder of radius 1. The profile goes up, so the starter's
    // normal T × (0, 0, 1) = (T_y, −T_x, 0) points away from the axis.
    const RevSurface s = make_rev_surface(line_profile({1, -1}, {1, 1}));
    RevSurfaceHit hit;
    // Horizontal ray (d_y = 0) from z = 5: it meets z = 1 at t = 4.
    ASSERT_TRUE(hit_of(s, {{0, 0, 5}, {0, 0, -1}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 4);
    expect_vec_near(normal_of(s, {{0, 0, 5}, {0, 0, -1}}, hit), {0, 0, 1}, 1e-6f);
    // A sloped ray from (0, −3, 5) along (0, 3, −4) reaches z = 1 at t = 1, at height 0.
    ASSERT_TRUE(hit_of(s, {{0, -3, 5}, {0, 3, -4}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 1);
    EXPECT_NEAR(hit.u, 0.5f, 1e-6f);
    // Whatever the slope, the wall at z = 1 is at t = 4 to float precision: either side of the
    // slopes below which the intersection treats a ray as horizontal (1e-5) or polishes its root
    // with Newton's method on (u, t) (1e-3).
    for (float slope : {1e-9f, 1e-6f, 9e-6f, 1.2e-5f, 1e-4f, 9e-4f, 1.1e-3f, 0.01f, -0.2f}) {
        ASSERT_TRUE(hit_of(s, {{0, 0, 5}, {0, slope, -1}}, hit)) << slope;
        EXPECT_FLOAT_EQ(hit.t, 4) << slope;
    }
    // The direction is not normalised: twice as long, half the t.
    ASSERT_TRUE(hit_of(s, {{0, 0, 5}, {0, 0, -2}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 2);
    // From inside, along +x: the wall at x = 1, whose normal points the way the ray goes.
    ASSERT_TRUE(hit_of(s, {{0, 0.5f, 0}, {1, 0, 0}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 1);
    expect_vec_near(normal_of(s, {{0, 0.5f, 0}, {1, 0, 0}}, hit), {1, 0, 0}, 1e-6f);
    // t_min beyond the near wall: the far wall at z = −1, t = 6.
    ASSERT_TRUE(hit_of(s, {{0, 0, 5}, {0, 0, -1}}, hit, 4.5f));
    EXPECT_FLOAT_EQ(hit.t, 6);
    // Misses: down the open middle, beside the cylinder, above it, and away from it.
    EXPECT_FALSE(hit_of(s, {{0.5f, 5, 0}, {0, -1, 0}}, hit));
    EXPECT_FALSE(hit_of(s, {{3, 5, 0}, {0, -1, 0}}, hit));
    EXPECT_FALSE(hit_of(s, {{0, 1.5f, 5}, {0, 0, -1}}, hit));
    EXPECT_FALSE(hit_of(s, {{0, 0, 5}, {0, 0, 1}}, hit));
}

TEST(RevSurfaceTest, ConeHitsWorkedOutByHand) {
    // From the apex (0, 1) down to (1, 0): radius 1 − y. T = (1, −1)/√2, so the normal
    // (T_y cos θ, −T_x, T_y sin θ) = (−cos θ, −1, −sin θ)/√2 points down and in.
    const RevSurface s = make_rev_surface(line_profile({0, 1}, {1, 0}));
    RevSurfaceHit hit;
    // Straight down the axis onto the apex (a root at the piece's end, where x = 0).
    ASSERT_TRUE(hit_of(s, {{0, 5, 0}, {0, -1, 0}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 4);
    // Straight down at x = 0.5: the cone is there at y = 0.5.
    const Ray down{{0.5f, 5, 0}, {0, -1, 0}};
    ASSERT_TRUE(hit_of(s, down, hit));
    EXPECT_FLOAT_EQ(hit.t, 4.5f);
    const float r = 1 / std::sqrt(2.0f);
    expect_vec_near(normal_of(s, down, hit), {-r, -r, 0}, 1e-6f);
    // The same at θ = 90°, on the z axis.
    const Ray down_z{{0, 5, 0.5f}, {0, -1, 0}};
    ASSERT_TRUE(hit_of(s, down_z, hit));
    expect_vec_near(normal_of(s, down_z, hit), {0, -r, -r}, 1e-6f);
    // Horizontal at y = 0.25, where the radius is 0.75.
    ASSERT_TRUE(hit_of(s, {{5, 0.25f, 0}, {-1, 0, 0}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 4.25f);
    // Up the axis from below: the base is open, so the inside of the apex, at t = 6.
    ASSERT_TRUE(hit_of(s, {{0, -5, 0}, {0, 1, 0}}, hit));
    EXPECT_FLOAT_EQ(hit.t, 6);
}

// A profile on the axis turns into a segment of it: no area, so never hit, not even by a ray
// exactly through the axis (which used to find it: a dotted line down the image). Of a B-spline
// whose middle lies on the axis, the pieces off it stay.
TEST(RevSurfaceTest, PiecesOnTheAxisAreNeverHit) {
    const RevSurface on_axis = make_rev_surface(line_profile({0, -1}, {0, 1}));
    EXPECT_TRUE(on_axis.nodes.empty());
    RevSurfaceHit hit;
    EXPECT_FALSE(hit_of(on_axis, {{0, 0, 5}, {0, 0, -1}}, hit));
    EXPECT_FALSE(hit_of(on_axis, {{0, 5, 0}, {0, -1, 0}}, hit));
    // Five cubic B-spline pieces, over y from -2 to about 2.17: in to the axis, up it, and out
    // again. The middle piece (control points 2..5, all at x = 0) spans y 0..1 on the axis.
    const Curve bent{CurveType::Bspline, {{1, -3, 0}, {1, -2, 0}, {0, -1, 0}, {0, 0, 0}, {0, 1, 0}, {0, 2, 0},
                                          {1, 2, 0}, {1, 3, 0}}};
    const RevSurface surface = make_rev_surface(bent);
    ASSERT_EQ(surface.piece_count() > 0, true);
    EXPECT_FALSE(hit_of(surface, {{0, 0.5f, 5}, {0, 0, -1}}, hit));  // through the axis, where the middle lies
    EXPECT_TRUE(hit_of(surface, {{0, -1.8f, 5}, {0, 0, -1}}, hit));  // the lowest piece, off the axis
    EXPECT_GT(hit.t, 4);
    EXPECT_LT(hit.t, 5);
    EXPECT_TRUE(hit_of(surface, {{0, 1.9f, 5}, {0, 0, -1}}, hit));   // the highest
    EXPECT_GT(hit.t, 4);
    EXPECT_LT(hit.t, 5);
}

// ---------------------------------------------------------------------------------------------
// Brute force

// The profile sampled densely with eval_curve: consecutive samples, joined by straight chords,
// turn into thin cone frustums, each met by a ray exactly (a quadratic). Nothing of the code under
// test is used, and the reference is as good for horizontal and vertical rays as for any other.
struct DenseProfile {
    std::vector<double> x, y;
};

DenseProfile sample_profile(const Curve& curve, int count) {
    DenseProfile p;
    const ParameterRange range = curve_parameter_range(curve);
    for (int i = 0; i <= count; ++i) {
        const CurveSample c = eval_curve(curve, range.begin + (range.end - range.begin) * i / count);
        p.x.push_back(c.position.x);
        p.y.push_back(c.position.y);
    }
    return p;
}

struct ReferenceHit {
    double t = INFINITY;
    double cosine = 0;  ///< |cos| of the angle between the ray and the frustum's normal there
};

// The nearest t > t_min where the ray meets the chain of frustums.
ReferenceHit brute_force(const DenseProfile& p, const Ray& ray, double t_min) {
    const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z}, d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    const double a = d[0] * d[0] + d[2] * d[2], b = o[0] * d[0] + o[2] * d[2], c = o[0] * o[0] + o[2] * o[2];
    const double length = std::sqrt(a + d[1] * d[1]);
    ReferenceHit best;
    auto consider = [&](double t, double x0, double y0, double x1, double y1) {
        if (!(t > t_min && t < best.t)) return;
        // The chord's normal in the profile plane, (Δy, −Δx), turned to the hit's angle.
        const double px = o[0] + t * d[0], pz = o[2] + t * d[2], r = std::hypot(px, pz);
        const double cx = r > 0 ? px / r : 1, cz = r > 0 ? pz / r : 0;
        const double nx = (y1 - y0) * cx, ny = -(x1 - x0), nz = (y1 - y0) * cz;
        best.t = t;
        best.cosine = std::fabs(nx * d[0] + ny * d[1] + nz * d[2]) / (length * std::sqrt(nx * nx + ny * ny + nz * nz));
    };
    for (size_t i = 0; i + 1 < p.x.size(); ++i) {
        const double x0 = p.x[i], y0 = p.y[i], x1 = p.x[i + 1], y1 = p.y[i + 1];
        if (y1 == y0) {  // a flat ring: the ray crosses its plane once
            if (d[1] == 0) continue;
            const double t = (y0 - o[1]) / d[1];
            const double r2 = c + 2 * b * t + a * t * t;
            const double lo = std::min(x0 * x0, x1 * x1), hi = std::max(x0 * x0, x1 * x1);
            if ((x0 < 0) != (x1 < 0) ? r2 <= hi : (r2 >= lo && r2 <= hi)) consider(t, x0, y0, x1, y1);
            continue;
        }
        // Along the chord x = α + β·t at the ray's height; the hit solves (α + βt)² = a t² + 2b t + c.
        const double slope = (x1 - x0) / (y1 - y0);
        const double alpha = x0 + slope * (o[1] - y0), beta = slope * d[1];
        const double qa = beta * beta - a, qb = alpha * beta - b, qc = alpha * alpha - c;
        double roots[2];
        int count = 0;
        if (std::fabs(qa) < 1e-14 * (beta * beta + a)) {
            if (qb != 0) roots[count++] = -qc / (2 * qb);
        } else {
            const double discriminant = qb * qb - qa * qc;
            if (discriminant < 0) continue;
            const double q = -(qb + std::copysign(std::sqrt(discriminant), qb));
            roots[count++] = q / qa;
            if (q != 0) roots[count++] = qc / q;
        }
        for (int k = 0; k < count; ++k) {
            const double lambda = (o[1] + roots[k] * d[1] - y0) / (y1 - y0);
            if (lambda >= 0 && lambda <= 1) consider(roots[k], x0, y0, x1, y1);
        }
    }
    return best;
}

// A hit is genuine when its point is on the profile's circle at the profile's height, at the
// curve parameter the piece and u stand for (evaluated with eval_curve).
void expect_genuine(const RevSurface& s, const Curve& profile, const Ray& ray, const RevSurfaceHit& hit, int index) {
    const double param = s.t_begin[hit.piece] + double(hit.u) * (s.t_end[hit.piece] - s.t_begin[hit.piece]);
    const CurveSample c = eval_curve(profile, param);
    const double t = hit.t;
    const double px = ray.origin.x + t * ray.direction.x, py = ray.origin.y + t * ray.direction.y,
                 pz = ray.origin.z + t * ray.direction.z;
    const double tolerance = 2e-5 * s.scale;
    EXPECT_NEAR(std::hypot(px, pz), std::fabs(c.position.x), tolerance) << "ray " << index;
    EXPECT_NEAR(py, c.position.y, tolerance) << "ray " << index;
}

struct Outcome {
    int rays = 0, hits = 0, grazing_disagreements = 0;
};

// Every hit must be genuine. Where the reference crosses the surface clearly (not within a few
// degrees of grazing, where a chord and the curve may disagree about touching), the hit must be
// found, and nothing nearer than it may be missed. Grazing disagreements are counted.
void check_ray(const RevSurface& s, const Curve& profile, const DenseProfile& dense, const Ray& ray, int index,
               Outcome& outcome) {
    ++outcome.rays;
    RevSurfaceHit hit;
    const bool found = hit_of(s, ray, hit);
    const ReferenceHit expected = brute_force(dense, ray, 0);
    if (found) {
        ++outcome.hits;
        expect_genuine(s, profile, ray, hit, index);
    }
    const double tolerance = 1e-4 * (1 + std::fabs(expected.t));
    const bool agree = found ? std::fabs(hit.t - expected.t) <= tolerance : !std::isfinite(expected.t);
    if (agree) return;
    char ray_text[200];
    std::snprintf(ray_text, sizeof ray_text, "ray %d from (%.9g, %.9g, %.9g) along (%.9g, %.9g, %.9g)", index,
                  double(ray.origin.x), double(ray.origin.y), double(ray.origin.z), double(ray.direction.x),
                  double(ray.direction.y), double(ray.direction.z));
    if (std::isfinite(expected.t) && expected.cosine > 0.05) {  // a clear crossing
        EXPECT_TRUE(found) << "missed a hit at t = " << expected.t << ", " << ray_text;
        EXPECT_TRUE(!found || hit.t <= expected.t + tolerance) << "not the nearest hit: " << hit.t << " instead of "
                                                               << expected.t << ", " << ray_text;
    }
    ++outcome.grazing_disagreements;
}

struct Profiles {
    std::vector<Curve> curves;
    std::vector<const char*> names;
};

Profiles test_profiles() {
    Profiles p;
    // A vase: one cubic Bezier, bulging out and in, never near the axis.
    p.curves.push_back({CurveType::Bezier, {{1.5f, 2, 0}, {3.5f, 0.5f, 0}, {0.2f, -0.5f, 0}, {1.8f, -2, 0}}});
    p.names.push_back("vase");
    // A goblet: a B-spline from the axis (three equal points) up the outside of a cup, down its
    // inside, a stem and a foot back to the axis.
    p.curves.push_back({CurveType::Bspline,
                        {{0, -1.6f, 0}, {0, -1.6f, 0}, {0, -1.6f, 0}, {1.1f, -1.6f, 0}, {1.2f, -1.45f, 0},
                         {0.25f, -1.3f, 0}, {0.12f, -0.6f, 0}, {0.2f, -0.1f, 0}, {1.2f, 0.2f, 0}, {1.3f, 1.3f, 0},
                         {1.1f, 1.9f, 0}, {1.15f, 1.95f, 0}, {1.0f, 1.7f, 0}, {0.9f, 0.6f, 0}, {0, 0.3f, 0},
                         {0, 0.3f, 0}, {0, 0.3f, 0}}});
    p.names.push_back("goblet");
    // Degree 6, crossing the axis and turning in y.
    p.curves.push_back({CurveType::Bezier,
                        {{-1, -2, 0}, {2, -1.5f, 0}, {-0.5f, 1, 0}, {1.5f, -0.5f, 0}, {0.5f, 0.8f, 0}, {2, 1.5f, 0},
                         {0.5f, 0.2f, 0}}});
    p.names.push_back("degree 6 across the axis");
    // A closed loop: a torus-like profile (a ray may meet it four times).
    Curve loop{CurveType::Bspline, {}};
    for (int i = 0; i < 11; ++i) {
        const double angle = kTwoPi * (i % 8) / 8;
        loop.controls.push_back({static_cast<float>(2 + std::cos(angle)), static_cast<float>(std::sin(angle)), 0});
    }
    p.curves.push_back(loop);
    p.names.push_back("torus");
    return p;
}

// A point of the surface at curve parameter s and angle θ.
Vec3f surface_point(const Curve& profile, double s, double theta) {
    const Vec3d c = eval_curve(profile, s).position;
    return {static_cast<float>(c.x * std::cos(theta)), static_cast<float>(c.y), static_cast<float>(c.x * std::sin(theta))};
}

TEST(RevSurfaceTest, AgreesWithBruteForceOnRandomRays) {
    const Profiles profiles = test_profiles();
    for (size_t k = 0; k < profiles.curves.size(); ++k) {
        SCOPED_TRACE(profiles.names[k]);
        const Curve& profile = profiles.curves[k];
        const RevSurface s = make_rev_surface(profile);
        const DenseProfile dense = sample_profile(profile, 4000);
        const ParameterRange range = curve_parameter_range(profile);
        std::mt19937 rng(static_cast<uint32_t>(100 + k));
        std::uniform_real_distribution<float> unit(-1, 1);
        std::uniform_real_distribution<double> param(range.begin, range.end), angle(0, kTwoPi);
        const float reach = 3 * static_cast<float>(s.scale);
        auto random_origin = [&] { return Vec3f{unit(rng) * reach, unit(rng) * reach, unit(rng) * reach}; };
        Outcome outcome;
        int index = 0;
        for (int i = 0; i < 300; ++i, ++index) {  // anywhere, anyhow
            const Vec3f d{unit(rng), unit(rng), unit(rng)};
            if (is_zero(d)) continue;
            check_ray(s, profile, dense, {random_origin(), d}, index, outcome);
        }
        for (int i = 0; i < 500; ++i, ++index) {  // aimed at the surface, with non-unit directions
            const Vec3f origin = random_origin();
            const Vec3f target = surface_point(profile, param(rng), angle(rng));
            check_ray(s, profile, dense, {origin, (target - origin) * (0.3f + std::fabs(unit(rng)))}, index, outcome);
        }
        for (int i = 0; i < 180; ++i, ++index) {  // horizontal, exactly and nearly
            Vec3f origin = random_origin();
            const Vec3f target = surface_point(profile, param(rng), angle(rng));
            origin.y = target.y;
            Vec3f d = target - origin;
            // Exactly horizontal, then either side of the 1e-5 below which the intersection treats
            // a ray as horizontal and of the 1e-3 below which it polishes with Newton on (u, t).
            const float tilt[] = {0, 1e-9f, 1e-6f, 9e-6f, 1.2e-5f, 2e-4f, 9e-4f, 1.1e-3f, 3e-3f};
            d.y = tilt[i % 9] * length(d) * (unit(rng) > 0 ? 1 : -1);
            check_ray(s, profile, dense, {origin, d}, index, outcome);
        }
        for (int i = 0; i < 100; ++i, ++index) {  // vertical, some exactly on the axis
            const Vec3f target = surface_point(profile, param(rng), angle(rng));
            const Vec3f foot = i % 10 == 0 ? Vec3f{0, 0, 0} : Vec3f{target.x, 0, target.z};
            const float from = unit(rng) > 0 ? reach : -reach;
            check_ray(s, profile, dense, {{foot.x, from, foot.z}, {0, from > 0 ? -1.0f : 1.0f, 0}}, index, outcome);
        }
        // The profile's ends and the points where it turns, from many sides.
        std::vector<double> special = {range.begin, range.end};
        for (size_t p = 0; p < s.t_begin.size(); ++p) special.push_back(s.t_begin[p]);
        for (double at : special)
            for (int i = 0; i < 8; ++i, ++index) {
                const Vec3f origin = random_origin();
                check_ray(s, profile, dense, {origin, surface_point(profile, at, angle(rng)) - origin}, index, outcome);
            }
        // Chords and the curve disagree only about grazing rays: rare.
        EXPECT_LE(outcome.grazing_disagreements, outcome.rays / 100) << outcome.hits << " hits in " << outcome.rays;
        EXPECT_GE(outcome.hits, outcome.rays / 2);
    }
}

// ---------------------------------------------------------------------------------------------
// Newton's method

TEST(RevSurfaceTest, NewtonConvergesQuadratically) {
    // The cylinder x = 1, y ∈ [−1.5, 1.5] (control points exact in float, so u = (y + 1.5)/3
    // exactly), and a ray from (0, 0, 5) climbing about 1e-3 per unit: it meets z = 1 at t = 4.
    const RevSurface s = make_rev_surface(line_profile({1, -1.5f}, {1, 1.5f}));
    const Ray ray{{0, 0, 5}, {0, 1e-3f, -1}};
    const double t_exact = 4, u_exact = (4 * double(1e-3f) + 1.5) / 3;
    int previous = 100;
    for (double offset : {3e-2, 1e-4, 1e-8}) {
        double u = u_exact + offset, t = t_exact - 10 * offset;
        int steps = 0;
        ASSERT_TRUE(polish_rev_surface_hit(s, 0, ray, u, t, steps)) << offset;
        EXPECT_NEAR(u, u_exact, 1e-14) << offset;
        EXPECT_NEAR(t, t_exact, 1e-12) << offset;
        // Quadratic convergence: the error squares each step, so a start a million times nearer
        // saves steps, and from 1e-8 one step reaches 1e-16 (plus one to see it).
        EXPECT_LE(steps, previous) << offset;
        EXPECT_LE(steps, 6) << offset;
        previous = steps;
    }
    EXPECT_LE(previous, 2);
}

TEST(RevSurfaceTest, NewtonReportsAGrazingRayAndLeavesTheStart) {
    // A ray along x = 1 touches the cylinder at z = 0 without crossing it: a double root, where the
    // Jacobian is singular and Newton's method cannot settle within its few steps.
    const RevSurface s = make_rev_surface(line_profile({1, -1}, {1, 1}));
    const Ray ray{{1, 0, 5}, {0, 1e-4f, -1}};
    double u = 0.53, t = 4.7;
    int steps = 0;
    EXPECT_FALSE(polish_rev_surface_hit(s, 0, ray, u, t, steps));
    EXPECT_EQ(u, 0.53);
    EXPECT_EQ(t, 4.7);
    EXPECT_GT(steps, 0);
}

TEST(RevSurfaceTest, CountsTestsAndNewtonSteps) {
    const RevSurface s = make_rev_surface(line_profile({1, -1}, {1, 1}));
    take_rev_surface_counters();
    RevSurfaceHit hit;
    hit_of(s, {{0, -3, 5}, {0, 3, -4}}, hit);
    hit_of(s, {{0, 0, 5}, {0, 1e-4f, -1}}, hit);  // near-horizontal: polished by Newton's method
    const RevSurfaceCounters counted = take_rev_surface_counters();
    EXPECT_EQ(counted.tests, 2u);
    EXPECT_GE(counted.newton_iterations, 2u);
    EXPECT_EQ(counted.newton_failures, 0u);
    EXPECT_EQ(take_rev_surface_counters().tests, 0u);
}

// ---------------------------------------------------------------------------------------------
// Normals, bounds, tessellation

TEST(RevSurfaceTest, NormalsAreAnalyticAndOrientedAsTheStarters) {
    const Profiles profiles = test_profiles();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> angle(0, kTwoPi), unit(0, 1);
    for (size_t k = 0; k < profiles.curves.size(); ++k) {
        SCOPED_TRACE(profiles.names[k]);
        const Curve& profile = profiles.curves[k];
        const RevSurface s = make_rev_surface(profile);
        const ParameterRange range = curve_parameter_range(profile);
        int checked = 0;
        for (int i = 0; i < 100; ++i) {
            const double param = range.begin + (range.end - range.begin) * (0.01 + 0.98 * unit(rng));
            const double theta = angle(rng);
            const CurveSample c = eval_curve(profile, param);
            if (std::fabs(c.position.x) < 1e-3) continue;  // the angle is undefined on the axis
            // Aim at the point from nearby, and keep the hits that land there.
            const Vec3f target = surface_point(profile, param, theta);
            const Vec3f radial{static_cast<float>(std::cos(theta)), 0, static_cast<float>(std::sin(theta))};
            const Ray ray{target + Vec3f{0.01f, 0.02f, 0.015f}, Vec3f{-0.01f, -0.02f, -0.015f}};
            RevSurfaceHit hit;
            if (!intersect_rev_surface(s, ray, 0.5f, 1.5f, false, hit) || length(ray.at(hit.t) - target) > 1e-4f) continue;
            ++checked;
            const Vec3f n = rev_surface_normal(s, hit.piece, hit.u, ray.at(hit.t));
            // Perpendicular to both surface tangents: along the profile and around the axis.
            const Vec3f along{static_cast<float>(c.derivative.x) * radial.x, static_cast<float>(c.derivative.y),
                              static_cast<float>(c.derivative.x) * radial.z};
            const Vec3f around{-radial.z, 0, radial.x};
            EXPECT_NEAR(dot(n, normalize(along)), 0, 1e-3) << i;
            EXPECT_NEAR(dot(n, around), 0, 1e-3) << i;
            // The starter's orientation: T × (0, 0, 1) = (T_y, −T_x, 0) in the profile's plane,
            // turned by the θ that carries (x, y, 0) to the point (whatever the sign of x).
            const Vec3f starter{static_cast<float>(c.derivative.y) * radial.x, static_cast<float>(-c.derivative.x),
                                static_cast<float>(c.derivative.y) * radial.z};
            EXPECT_GT(dot(n, normalize(starter)), 0.999f) << i;
        }
        EXPECT_GE(checked, 50);
    }
}

TEST(RevSurfaceTest, BoundsHoldTheTransformedSurface) {
    const Profiles profiles = test_profiles();
    Mat4 m = Mat4::translate({1, -2, 0.5f}) * Mat4::rotate({1, 2, 3}, 37) * Mat4::scale({1.5f, 0.5f, 2});
    m.m[0][1] = 0.4f;  // a shear as well
    for (size_t k = 0; k < profiles.curves.size(); ++k) {
        SCOPED_TRACE(profiles.names[k]);
        const RevSurface s = make_rev_surface(profiles.curves[k]);
        const TriangleMesh mesh = tessellate_rev_surface(profiles.curves[k], 400, 180);
        for (const Mat4& transform : {Mat4::identity(), m}) {
            const Bounds3f bounds = rev_surface_bounds(s, transform);
            Bounds3f corners;  // the box of the transformed object-space box: never tighter
            for (int c = 0; c < 8; ++c)
                corners.grow(transform_point(transform, {(c & 1) ? s.bounds.upper.x : s.bounds.lower.x,
                                                         (c & 2) ? s.bounds.upper.y : s.bounds.lower.y,
                                                         (c & 4) ? s.bounds.upper.z : s.bounds.lower.z}));
            for (const Vec3f& p : mesh.positions) {
                const Vec3f q = transform_point(transform, p);
                for (int axis = 0; axis < 3; ++axis) {
                    const float slack = 1e-5f * (1 + std::fabs(q[axis]));
                    ASSERT_GE(q[axis], bounds.lower[axis] - slack);
                    ASSERT_LE(q[axis], bounds.upper[axis] + slack);
                }
            }
            for (int axis = 0; axis < 3; ++axis) {
                EXPECT_GE(bounds.lower[axis], corners.lower[axis] - 1e-4f);
                EXPECT_LE(bounds.upper[axis], corners.upper[axis] + 1e-4f);
            }
        }
    }
}

TEST(RevSurfaceTest, TessellationFollowsTheProfile) {
    const Curve profile = test_profiles().curves[0];
    const TriangleMesh mesh = tessellate_rev_surface(profile, 10, 8);
    EXPECT_EQ(mesh.positions.size(), 11u * 8u);
    EXPECT_EQ(mesh.triangle_count(), 10u * 8u * 2u);
    ASSERT_TRUE(mesh.has_normals());
    // The first ring is the profile's first point turned about the axis: (1.5 cos θ, 2, 1.5 sin θ).
    for (int j = 0; j < 8; ++j) {
        const double theta = kTwoPi * j / 8;
        expect_vec_near(mesh.positions[static_cast<size_t>(j)],
                        {static_cast<float>(1.5 * std::cos(theta)), 2, static_cast<float>(1.5 * std::sin(theta))}, 1e-6f);
    }
}

}  // namespace
}  // namespace raycast
