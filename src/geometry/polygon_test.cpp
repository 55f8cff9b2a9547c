// triangulate_polygon (geometry/polygon.h): the fan for convex polygons, exactly as OBJ readers
// have always cut them (halves for those of very many corners); for concave ones, triangles that
// tile the polygon: their areas add up to its area, each turns the polygon's way, and none
// reaches outside it.
#include "geometry/polygon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace raycast {
namespace {

std::vector<uint32_t> fan(int count) {
    std::vector<uint32_t> out;
    for (int i = 1; i + 1 < count; ++i) out.insert(out.end(), {0u, static_cast<uint32_t>(i), static_cast<uint32_t>(i + 1)});
    return out;
}

std::vector<uint32_t> cut(const std::vector<Vec3f>& points, bool* changed = nullptr) {
    std::vector<uint32_t> triangles(3 * (points.size() - 2));
    const bool differs = triangulate_polygon(points.data(), static_cast<int>(points.size()), triangles.data());
    if (changed) *changed = differs;
    return triangles;
}

// The polygon's area vector (Newell), in double.
Vec3f area_vector(const std::vector<Vec3f>& p) {
    double x = 0, y = 0, z = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        const Vec3f a = p[i], b = p[(i + 1) % p.size()];
        x += (double{a.y} - b.y) * (double{a.z} + b.z);
        y += (double{a.z} - b.z) * (double{a.x} + b.x);
        z += (double{a.x} - b.x) * (double{a.y} + b.y);
    }
    return {static_cast<float>(x / 2), static_cast<float>(y / 2), static_cast<float>(z / 2)};
}

// Whether the triangles tile the polygon: every one turns the polygon's way (or is flat), their
// areas add up to the polygon's, and each triangle's centroid lies inside the polygon.
void expect_tiles(const std::vector<Vec3f>& p, const std::vector<uint32_t>& triangles) {
    const Vec3f polygon = area_vector(p);
    const Vec3f unit = normalize(polygon);
    double total = 0;
    for (size_t t = 0; t < triangles.size(); t += 3) {
        const Vec3f a = p[triangles[t]], b = p[triangles[t + 1]], c = p[triangles[t + 2]];
        const double area = 0.5 * dot(cross(b - a, c - a), unit);
        EXPECT_GE(area, -1e-6) << "triangle " << t / 3 << " turns the other way";
        total += area;
        // Centroid inside: a ray from it in the plane crosses the outline an odd number of times.
        const Vec3f centroid = (a + b + c) / 3.0f;
        if (area < 1e-6) continue;  // a flat triangle has its centroid on the outline
        const Vec3f along = normalize(cross(unit, Vec3f{0.3f, 0.5f, 0.7f}));
        int crossings = 0;
        for (size_t i = 0; i < p.size(); ++i) {
            const Vec3f e0 = p[i] - centroid, e1 = p[(i + 1) % p.size()] - centroid;
            // In the plane: coordinates along `along` and across it.
            const Vec3f across = cross(unit, along);
            const double y0 = dot(e0, across), y1 = dot(e1, across);
            if ((y0 > 0) == (y1 > 0)) continue;
            const double x0 = dot(e0, along), x1 = dot(e1, along);
            if (x0 + (x1 - x0) * (0 - y0) / (y1 - y0) > 0) ++crossings;
        }
        EXPECT_EQ(crossings % 2, 1) << "triangle " << t / 3 << " reaches outside the polygon";
    }
    EXPECT_NEAR(total, length(polygon), 1e-4 * (1 + length(polygon)));
}

TEST(PolygonTest, ConvexPolygonsKeepTheFan) {
    bool changed = true;
    const std::vector<Vec3f> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    EXPECT_EQ(cut(square, &changed), fan(4));
    EXPECT_FALSE(changed);
    std::vector<Vec3f> hexagon;
    for (int i = 0; i < 6; ++i) {
        const float angle = 1.0472f * static_cast<float>(i);
        hexagon.push_back({std::cos(angle), 0, std::sin(angle)});
    }
    EXPECT_EQ(cut(hexagon, &changed), fan(6));
    EXPECT_FALSE(changed);
    // A corner on a straight edge (n-gons often have them) leaves it convex.
    const std::vector<Vec3f> with_straight{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    EXPECT_EQ(cut(with_straight, &changed), fan(5));
    EXPECT_FALSE(changed);
    // Clockwise, and in another plane: the same.
    const std::vector<Vec3f> clockwise{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};
    EXPECT_EQ(cut(clockwise, &changed), fan(4));
    EXPECT_FALSE(changed);
}

TEST(PolygonTest, AConcavePolygonIsTiledWithoutCrossingItsNotch) {
    // The L of the report: fanned from corner 0, triangle (0, 3, 4) lay across the missing quarter.
    const std::vector<Vec3f> l_shape{{1, -1, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, -1, 0}};
    bool changed = false;
    const std::vector<uint32_t> triangles = cut(l_shape, &changed);
    EXPECT_TRUE(changed);
    expect_tiles(l_shape, triangles);
    // The same turned clockwise, and stood up in the other two planes.
    std::vector<Vec3f> reversed(l_shape.rbegin(), l_shape.rend());
    expect_tiles(reversed, cut(reversed));
    std::vector<Vec3f> in_yz, in_zx;
    for (const Vec3f& p : l_shape) {
        in_yz.push_back({0.2f, p.x, p.y});
        in_zx.push_back({p.y, -3, p.x});
    }
    expect_tiles(in_yz, cut(in_yz));
    expect_tiles(in_zx, cut(in_zx));
    // A concave quad (an arrowhead) whose fan's diagonal runs outside it; the loader's quick test
    // for quads says so, and passes a convex one and a concave one whose fan is right.
    const std::vector<Vec3f> arrow{{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {0.5f, 1, 0}};
    EXPECT_FALSE(quad_fan_tiles(arrow[0], arrow[1], arrow[2], arrow[3]));
    EXPECT_TRUE(quad_fan_tiles({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}));
    EXPECT_TRUE(quad_fan_tiles(arrow[3], arrow[0], arrow[1], arrow[2]));  // the notch at corner 0
    EXPECT_TRUE(triangulate_polygon(arrow.data(), 4, std::vector<uint32_t>(6).data()));
    expect_tiles(arrow, cut(arrow));
    // Concave with corners on straight edges.
    const std::vector<Vec3f> u_shape{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {3, 2, 0}, {2, 2, 0},
                                     {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 1, 0}};
    expect_tiles(u_shape, cut(u_shape));
}

TEST(PolygonTest, RandomStarShapedPolygonsAreTiled) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> radius(0.2f, 1.0f), tilt(-1, 1);
    for (int trial = 0; trial < 300; ++trial) {
        const int n = 4 + trial % 40;
        const Vec3f normal = normalize(Vec3f{tilt(rng), tilt(rng), tilt(rng)});
        const Vec3f u = normalize(cross(normal, Vec3f{0.1f, 0.7f, 0.3f})), v = cross(normal, u);
        std::vector<Vec3f> p;
        for (int i = 0; i < n; ++i) {
            const float angle = 6.2831853f * static_cast<float>(i) / static_cast<float>(n), r = radius(rng);
            p.push_back(Vec3f{1, 2, 3} + u * (r * std::cos(angle)) + v * (r * std::sin(angle)));
        }
        SCOPED_TRACE(trial);
        expect_tiles(p, cut(p));
    }
}

TEST(PolygonTest, ShapesThatCannotBeToldKeepTheFan) {
    bool changed = true;
    // Every corner on one line: no area.
    const std::vector<Vec3f> flat{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    EXPECT_EQ(cut(flat, &changed), fan(4));
    EXPECT_FALSE(changed);
    // A figure eight, which crosses itself: no triangles tile it.
    const std::vector<Vec3f> bow_tie{{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 2, 0}, {-1, 1, 0}};
    const std::vector<uint32_t> triangles = cut(bow_tie, &changed);
    EXPECT_EQ(triangles.size(), 9u);
    // Past kMaxEarClippedCorners a concave polygon keeps the fan (a convex one is cut in halves:
    // AConvexPolygonOfVeryManyCornersIsCutInHalves).
    std::vector<Vec3f> comb;
    for (int i = 0; i <= kMaxEarClippedCorners; ++i) comb.push_back({static_cast<float>(i), i % 2 == 0 ? 0.0f : 1.0f, 0});
    comb.push_back({static_cast<float>(kMaxEarClippedCorners), -1, 0});
    comb.push_back({0, -1, 0});
    EXPECT_EQ(cut(comb, &changed), fan(static_cast<int>(comb.size())));
    EXPECT_FALSE(changed);
    // Not flat: the L with one corner lifted off its plane by a tenth of its size.
    std::vector<Vec3f> lifted{{1, -1, 0}, {1, 0, 0}, {0, 0, 0.2f}, {0, 1, 0}, {-1, 1, 0}, {-1, -1, 0}};
    EXPECT_EQ(cut(lifted, &changed), fan(6));
    EXPECT_FALSE(changed);
    lifted[2].z = 1e-4f;  // within a thousandth: flat enough, cut around the notch
    EXPECT_TRUE(triangulate_polygon(lifted.data(), 6, std::vector<uint32_t>(12).data()));
}

// n corners about (0, 0, 0) in a tilted plane, `turns` times round (turns = 2: a star that
// winds twice, turning left at every corner like a convex polygon).
std::vector<Vec3f> circle(int n, int turns = 1) {
    std::vector<Vec3f> p;
    const Vec3f u = normalize(Vec3f{1, 0.2f, -0.3f}), v = normalize(cross(Vec3f{0.1f, 0.3f, 1}, u));
    for (int i = 0; i < n; ++i) {
        const double angle = 2 * M_PI * turns * i / n;
        p.push_back(u * static_cast<float>(std::cos(angle)) + v * static_cast<float>(std::sin(angle)));
    }
    return p;
}

// How many of the triangles hold corner 0 (all of a fan's).
int triangles_at_corner_0(const std::vector<uint32_t>& triangles) {
    int count = 0;
    for (size_t t = 0; t < triangles.size(); t += 3)
        count += triangles[t] == 0 || triangles[t + 1] == 0 || triangles[t + 2] == 0 ? 1 : 0;
    return count;
}

// Past kMaxEarClippedCorners a convex polygon is cut in halves, not fanned: its triangles tile it,
// each keeps its corners in the polygon's order, and corner 0 is in about log2(n) of them.
TEST(PolygonTest, AConvexPolygonOfVeryManyCornersIsCutInHalves) {
    const std::vector<Vec3f> disc = circle(1000);
    bool changed = false;
    const std::vector<uint32_t> triangles = cut(disc, &changed);
    EXPECT_TRUE(changed);
    ASSERT_EQ(triangles.size(), 3u * 998);
    expect_tiles(disc, triangles);
    for (size_t t = 0; t < triangles.size(); t += 3)
        EXPECT_TRUE(triangles[t] < triangles[t + 1] && triangles[t + 1] < triangles[t + 2]) << "triangle " << t / 3;
    EXPECT_EQ(triangles[0], 0u);  // the first cut: corners 0, 499 and 999
    EXPECT_EQ(triangles[1], 499u);
    EXPECT_EQ(triangles[2], 999u);
    EXPECT_LE(triangles_at_corner_0(triangles), 10);
    // A disc's cap of 100,000 corners in floats, whose rounding makes some corners turn right by
    // a little: cut in halves all the same.
    const std::vector<Vec3f> cap = circle(100000);
    const std::vector<uint32_t> cap_triangles = cut(cap, &changed);
    EXPECT_TRUE(changed);
    EXPECT_LE(triangles_at_corner_0(cap_triangles), 17);
    // One corner more than ear clipping takes is already cut so.
    const std::vector<Vec3f> just_past = circle(kMaxEarClippedCorners + 1);
    EXPECT_TRUE(triangulate_polygon(just_past.data(), kMaxEarClippedCorners + 1,
                                    std::vector<uint32_t>(3 * (kMaxEarClippedCorners - 1)).data()));
    // Up to kMaxEarClippedCorners a convex polygon keeps the fan, as every OBJ reader cuts it.
    const std::vector<Vec3f> at_limit = circle(kMaxEarClippedCorners);
    EXPECT_EQ(cut(at_limit, &changed), fan(kMaxEarClippedCorners));
    EXPECT_FALSE(changed);
}

// Past kMaxEarClippedCorners, what is not flat and convex keeps the fan: a star that winds twice
// round (every corner turns left), a polygon with a corner off its plane, and (above) a comb.
TEST(PolygonTest, ManyCornersThatAreNotConvexKeepTheFan) {
    bool changed = true;
    const std::vector<Vec3f> star = circle(1001, 2);
    EXPECT_EQ(cut(star, &changed), fan(1001));
    EXPECT_FALSE(changed);
    std::vector<Vec3f> lifted = circle(1000);
    lifted[300] = lifted[300] + normalize(area_vector(lifted)) * 0.1f;
    EXPECT_EQ(cut(lifted, &changed), fan(1000));
    EXPECT_FALSE(changed);
    // A crescent: half a circle out, and back along a flatter arc inside it. Every corner of the
    // inner arc turns right by little, the whole by much.
    std::vector<Vec3f> crescent;
    for (int i = 0; i <= 500; ++i) {
        const double angle = M_PI * i / 500;
        crescent.push_back({static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)), 0});
    }
    for (int i = 499; i >= 1; --i) {
        const double angle = M_PI * i / 500;
        crescent.push_back({static_cast<float>(std::cos(angle)), static_cast<float>(0.5 * std::sin(angle)), 0});
    }
    EXPECT_EQ(cut(crescent, &changed), fan(static_cast<int>(crescent.size())));
    EXPECT_FALSE(changed);
}

}  // namespace
}  // namespace raycast
