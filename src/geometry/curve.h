// The course's curves: a Bezier curve of any degree (n + 1 control points, Bernstein basis over
// [0, 1]) and the cubic B-spline with uniform knots t_i = i/(n + k + 1), drawn over
// [t_k, t_{n+1}]. Evaluated in double precision (de Casteljau, de Boor), and cut into Bezier
// pieces, the form the surface of revolution intersects (rev_surface.h).
// Entry points: Curve, eval_curve, curve_parameter_range, curve_bezier_pieces.
#pragma once

#include <cstdint>
#include <vector>

#include "math/vec.h"

namespace raycast {

enum class CurveType : uint8_t { Bezier, Bspline };

/// A curve as the scene file gives it: its type and its control points, in order.
struct Curve {
    CurveType type = CurveType::Bezier;
    std::vector<Vec3f> controls;
};

/// The degree of every B-spline in the course's format.
constexpr int kBsplineDegree = 3;

/// A point or vector in double precision, for curve arithmetic.
struct Vec3d {
    double x = 0, y = 0, z = 0;
};

inline Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator*(double s, Vec3d a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3d to_double(Vec3f a) { return {a.x, a.y, a.z}; }
/// (1 − s)·a + s·b, the step of de Casteljau's and de Boor's algorithms.
inline Vec3d lerp(Vec3d a, Vec3d b, double s) { return {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)}; }

/// n for a Bezier curve of n + 1 points, 3 for a B-spline.
int curve_degree(const Curve& curve);

/// The parameter interval the curve is drawn over.
struct ParameterRange {
    double begin = 0, end = 1;
};

/// [0, 1] for a Bezier curve; [t_k, t_{n+1}] = [k/(n+k+1), (n+1)/(n+k+1)] for a B-spline of
/// n + 1 points. The curve needs at least degree + 1 points (the parser checks it).
ParameterRange curve_parameter_range(const Curve& curve);

/// A point of the curve and its derivatives with respect to the curve's own parameter.
struct CurveSample {
    Vec3d position;
    Vec3d derivative;         ///< dC/dt
    Vec3d second_derivative;  ///< d²C/dt²
};

/// The curve at parameter t (inside curve_parameter_range; outside it the end piece's polynomial
/// is extended). Bezier: de Casteljau; B-spline: de Boor on the uniform knots.
CurveSample eval_curve(const Curve& curve, double t);

/// One polynomial piece of a curve in Bezier form: `points` (degree + 1 of them) over its own
/// parameter u ∈ [0, 1], which is the curve parameter t_begin + u·(t_end − t_begin).
struct BezierPiece {
    std::vector<Vec3d> points;
    double t_begin = 0, t_end = 1;
};

/// The curve as Bezier pieces in parameter order: one piece of degree n for a Bezier curve, one
/// cubic per knot interval (n − 2 pieces) for a B-spline. Consecutive pieces share their end point
/// bit for bit.
std::vector<BezierPiece> curve_bezier_pieces(const Curve& curve);

/// A Bezier curve (given by its points, any degree) at u ∈ [0, 1], with derivatives in u.
CurveSample eval_bezier(const std::vector<Vec3d>& points, double u);

}  // namespace raycast
