// The documented limits of raycast (docs/limits.md): past any of them a clear error, never a crash.
#pragma once

#include <cstdint>

namespace raycast {

/// Largest image: 16384 pixels a side, 2^26 pixels in all (8192 × 8192).
constexpr int kMaxImageSide = 16384;
constexpr int64_t kMaxImagePixels = int64_t{1} << 26;

/// Groups and transforms nested deeper than this are refused (the parser and the scene builder
/// recurse once per level).
constexpr int kMaxNestingDepth = 1000;

/// A scene file stops being parsed after this many errors.
constexpr int kMaxReportedErrors = 20;

/// Objects must lie within ±1e18 of the origin (after their transforms): the intersection tests
/// multiply coordinate differences, and beyond this the products overflow single precision.
constexpr float kMaxCoordinate = 1e18f;

/// A BezierCurve has at most this many control points (degree 30): a ray meets a surface of
/// revolution where a polynomial of twice the curve's degree vanishes, and the intersection keeps
/// those in fixed-size arrays on the stack. Longer profiles are BsplineCurves, which have no limit.
constexpr int kMaxBezierControlPoints = 31;

/// Largest scene file read (meshes belong in OBJ files, which have no such limit).
constexpr int64_t kMaxSceneFileBytes = int64_t{256} << 20;

}  // namespace raycast
