// Polygons (an OBJ face of more than three corners) cut into triangles. OBJ readers have always
// cut them as a fan from the first corner, which is right for a convex polygon only: Blender
// writes n-gons, and a concave one (an L-shaped floor) fanned gets a triangle across its notch.
// Entry point: triangulate_polygon.
#pragma once

#include <cstdint>

#include "math/vec.h"

namespace raycast {

/// Polygons with more corners are not ear-clipped: that takes time that grows with the square of
/// the corners. A face of so many corners is nearly always convex (a disc's cap).
constexpr int kMaxEarClippedCorners = 256;

/// The count − 2 triangles of the polygon points[0..count) (count >= 3), as indices into it, in
/// `triangles` (3 · (count − 2) of them), each wound as the polygon is. Up to
/// kMaxEarClippedCorners corners: the fan (0, i, i + 1) wherever it tiles the polygon (every
/// convex one, and a concave one whose fan triangles all turn its way), or when its shape cannot
/// be told (no area, corners off its plane by more than a thousandth of its size, a polygon that
/// crosses itself); otherwise the triangles of ear clipping, in the plane of Newell's normal.
/// With more corners: a flat convex polygon is cut in halves and halves again (triangle
/// (0, m, count − 1) with m the middle corner, then each half the same way), whose triangles
/// shrink towards its edge, where a fan's slivers would all reach corner 0 and every ray near it
/// would test them all; any other keeps the fan. Returns whether the triangles differ from the
/// fan.
bool triangulate_polygon(const Vec3f* points, int count, uint32_t* triangles);

/// Whether the fan (0, 1, 2), (0, 2, 3) tiles the quad a, b, c, d: its two triangles turn the same
/// way. Inline and in float, for the many quads of a mesh, which triangulate_polygon then need
/// not see; where this says no, triangulate_polygon decides (in double).
inline bool quad_fan_tiles(Vec3f a, Vec3f b, Vec3f c, Vec3f d) {
    const Vec3f diagonal = c - a;
    return dot(cross(b - a, diagonal), cross(diagonal, d - a)) > 0;
}

}  // namespace raycast
