#include "geometry/polygon.h"

#include <cmath>
#include <cstddef>
#include <vector>

namespace raycast {

namespace {

struct Point2 {
    double x, y;
};

// Twice the signed area of triangle a, b, c: positive when it turns left (counter-clockwise).
double turn(Point2 a, Point2 b, Point2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Whether p lies inside triangle a, b, c (counter-clockwise) or on its edges.
bool inside_or_on(Point2 p, Point2 a, Point2 b, Point2 c) {
    return turn(a, b, p) >= 0 && turn(b, c, p) >= 0 && turn(c, a, p) >= 0;
}

void write_fan(int count, uint32_t* triangles) {
    for (int i = 1; i + 1 < count; ++i) {
        *triangles++ = 0;
        *triangles++ = static_cast<uint32_t>(i);
        *triangles++ = static_cast<uint32_t>(i + 1);
    }
}

// Triangles (lo, mid, hi), then the same for the corners from lo to mid and from mid to hi, for
// every range of at least three corners: a convex polygon cut in halves and halves again, whose
// triangles get smaller towards its edge instead of all reaching one corner.
uint32_t* write_halves(int lo, int hi, uint32_t* triangles) {
    if (hi - lo < 2) return triangles;
    const int mid = lo + (hi - lo) / 2;
    *triangles++ = static_cast<uint32_t>(lo);
    *triangles++ = static_cast<uint32_t>(mid);
    *triangles++ = static_cast<uint32_t>(hi);
    return write_halves(mid, hi, write_halves(lo, mid, triangles));
}

// How a polygon is seen in its plane: whether every corner lies within a thousandth of its size
// of the plane of Newell's normal n (concave means nothing otherwise), and the axis along n's
// largest component, dropped to project the corners.
struct PolygonPlane {
    bool flat = false;
    int drop = 0;
    double sign = 1;  // -1 where n's dropped component is negative, which mirrors the projection
    double size = 0;  // the greatest distance of a corner from their centroid
};

PolygonPlane polygon_plane(const Vec3f* points, int count, double nx, double ny, double nz) {
    const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
    const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
    double cx = 0, cy = 0, cz = 0;
    for (int i = 0; i < count; ++i) {
        cx += points[i].x;
        cy += points[i].y;
        cz += points[i].z;
    }
    cx /= count;
    cy /= count;
    cz /= count;
    double size = 0, off_plane = 0;
    for (int i = 0; i < count; ++i) {
        const double dx = points[i].x - cx, dy = points[i].y - cy, dz = points[i].z - cz;
        size = std::fmax(size, std::sqrt(dx * dx + dy * dy + dz * dz));
        off_plane = std::fmax(off_plane, std::fabs(dx * nx + dy * ny + dz * nz) / length);
    }
    PolygonPlane plane;
    plane.size = size;
    plane.flat = off_plane <= 1e-3 * size;
    plane.drop = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    plane.sign = (plane.drop == 0 ? nx : plane.drop == 1 ? ny : nz) > 0 ? 1 : -1;
    return plane;
}

// Corner q in the plane: (y, z) for x dropped, (z, x) for y, (x, y) for z, each right-handed
// about its axis, so that the polygon runs counter-clockwise where n's component is positive.
Point2 projected(const Vec3f& q, const PolygonPlane& plane) {
    const double u = plane.drop == 0 ? q.y : (plane.drop == 1 ? q.z : q.x);
    const double v = plane.drop == 0 ? q.z : (plane.drop == 1 ? q.x : q.y);
    return {u, plane.sign * v};
}

// Whether every corner strictly between lo and hi lies right of the chord from p[lo] to p[hi]
// (outside it, for a polygon that runs counter-clockwise), or left of it by at most `tolerance`.
bool chain_right_of_chord(const std::vector<Point2>& p, int lo, int hi, double tolerance) {
    const double length = std::hypot(p[hi].x - p[lo].x, p[hi].y - p[lo].y);
    for (int k = lo + 1; k < hi; ++k)
        if (turn(p[lo], p[hi], p[k]) > tolerance * length) return false;
    return true;
}

// Whether write_halves' triangles for corners lo..hi tile that part of the polygon (up to slivers
// of `tolerance`), given that its chain lies right of the chord lo -> hi (the caller's test; for
// the whole polygon, 0..count - 1, that chord is the edge that closes it, reversed): then the
// triangle (lo, mid, hi) turns left, and where the chains lo..mid and mid..hi lie right of their
// own chords, no corner or edge of them enters the triangle, which the halves then tile in turn.
// Takes time n log n for n corners.
bool halves_tile(const std::vector<Point2>& p, int lo, int hi, double tolerance) {
    if (hi - lo < 2) return true;
    const int mid = lo + (hi - lo) / 2;
    return chain_right_of_chord(p, lo, mid, tolerance) && chain_right_of_chord(p, mid, hi, tolerance) &&
           halves_tile(p, lo, mid, tolerance) && halves_tile(p, mid, hi, tolerance);
}

}  // namespace

bool triangulate_polygon(const Vec3f* points, int count, uint32_t* triangles) {
    write_fan(count, triangles);
    if (count <= 3) return false;
    // The fan's triangles' area vectors, and their sum: the polygon's (Newell's normal). Where
    // none turns against the sum, the fan tiles the polygon (its triangles turn one way about the
    // first corner, so they do not overlap) and stays: every convex polygon, and most others.
    // Nearly every face comes here this way only (every quad of a mesh): a cross product a corner.
    const Vec3f& origin = points[0];
    const auto fan_area = [&](int i, double* f) {  // of fan triangle (0, i, i + 1)
        const double ux = double{points[i].x} - origin.x, uy = double{points[i].y} - origin.y,
                     uz = double{points[i].z} - origin.z;
        const double vx = double{points[i + 1].x} - origin.x, vy = double{points[i + 1].y} - origin.y,
                     vz = double{points[i + 1].z} - origin.z;
        f[0] = uy * vz - uz * vy;
        f[1] = uz * vx - ux * vz;
        f[2] = ux * vy - uy * vx;
    };
    double nx = 0, ny = 0, nz = 0;
    for (int i = 1; i + 1 < count; ++i) {
        double f[3];
        fan_area(i, f);
        nx += f[0];
        ny += f[1];
        nz += f[2];
    }
    const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
    if (!(ax + ay + az > 0)) return false;  // no area (or NaN): nothing to choose between
    if (count > kMaxEarClippedCorners) {
        // Too many corners to clip ears: a convex one is cut in halves (its fan's slivers all
        // reach corner 0, and so do their boxes), any other keeps the fan.
        // (Convex within the corners' rounding: a disc's cap of 100,000 corners, in floats, has
        // corners that turn right by a little; a millionth of its size and the floats' own
        // rounding are let pass.)
        const PolygonPlane plane = polygon_plane(points, count, nx, ny, nz);
        if (!plane.flat) return false;
        std::vector<Point2> p(static_cast<size_t>(count));
        double largest = 0;  // coordinate, for the floats' rounding
        for (int i = 0; i < count; ++i) {
            const Point2 q = projected(points[i], plane);
            p[static_cast<size_t>(i)] = q;
            largest = std::fmax(largest, std::fmax(std::fabs(q.x), std::fabs(q.y)));
        }
        const double tolerance = 1e-6 * plane.size + 4 * 5.96e-8 * largest;
        if (!chain_right_of_chord(p, 0, count - 1, tolerance) || !halves_tile(p, 0, count - 1, tolerance)) return false;
        write_halves(0, count - 1, triangles);
        return true;
    }
    bool fan_tiles = true;
    for (int i = 1; i + 1 < count && fan_tiles; ++i) {
        double f[3];
        fan_area(i, f);
        fan_tiles = f[0] * nx + f[1] * ny + f[2] * nz >= 0;
    }
    if (fan_tiles) return false;
    // Not flat (a corner off the polygon's plane by more than a thousandth of its size): concave
    // means nothing there, and the fan is what every reader makes of it.
    const PolygonPlane plane = polygon_plane(points, count, nx, ny, nz);
    if (!plane.flat) return false;
    Point2 p[kMaxEarClippedCorners];
    for (int i = 0; i < count; ++i) p[static_cast<size_t>(i)] = projected(points[i], plane);
    // Convex in the plane after all (a fan triangle turned back only by the corners' small
    // distances off it): the fan.
    bool convex = true;
    for (int i = 0; i < count && convex; ++i)
        convex = turn(p[static_cast<size_t>(i)], p[static_cast<size_t>((i + 1) % count)],
                      p[static_cast<size_t>((i + 2) % count)]) >= 0;
    if (convex) return false;
    // Ear clipping: cut off a corner that turns left and holds no other remaining corner in its
    // triangle, until three are left. Corners on a straight edge (n-gons often have them) are
    // cut too, as flat triangles that are never hit, once no corner that turns is an ear.
    int remaining[kMaxEarClippedCorners];
    size_t remaining_count = static_cast<size_t>(count);
    for (int i = 0; i < count; ++i) remaining[i] = i;
    uint32_t ears[3 * (kMaxEarClippedCorners - 2)];
    size_t ear_values = 0;
    const auto add_ear = [&](int a, int b, int c) {
        ears[ear_values++] = static_cast<uint32_t>(a);
        ears[ear_values++] = static_cast<uint32_t>(b);
        ears[ear_values++] = static_cast<uint32_t>(c);
    };
    size_t at = 0;
    size_t since_last_ear = 0;
    bool flat_ears = false;
    while (remaining_count > 3) {
        const size_t n = remaining_count;
        const int i0 = remaining[(at + n - 1) % n], i1 = remaining[at % n], i2 = remaining[(at + 1) % n];
        const Point2 a = p[static_cast<size_t>(i0)], b = p[static_cast<size_t>(i1)], c = p[static_cast<size_t>(i2)];
        const double corner_turn = turn(a, b, c);
        bool ear = corner_turn > 0 || (flat_ears && corner_turn == 0);
        for (size_t k = 0; ear && k < n; ++k) {
            const int other = remaining[k];
            if (other == i0 || other == i1 || other == i2) continue;
            ear = !inside_or_on(p[static_cast<size_t>(other)], a, b, c);
        }
        if (ear) {
            add_ear(i0, i1, i2);
            for (size_t k = at % n; k + 1 < n; ++k) remaining[k] = remaining[k + 1];
            --remaining_count;
            at = at % n;  // the corner after the ear now sits here
            since_last_ear = 0;
            flat_ears = false;
            continue;
        }
        at = (at + 1) % n;
        if (++since_last_ear > n) {
            if (flat_ears) return false;  // no ear at all: the polygon crosses itself; the fan stays
            flat_ears = true;
            since_last_ear = 0;
        }
    }
    add_ear(remaining[0], remaining[1], remaining[2]);
    for (size_t i = 0; i < ear_values; ++i) triangles[i] = ears[i];
    return true;
}

}  // namespace raycast
