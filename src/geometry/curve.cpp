#include "geometry/curve.h"

#include <algorithm>

namespace raycast {

namespace {

double knot(int i, int point_count) { return static_cast<double>(i) / static_cast<double>(point_count + kBsplineDegree); }

// De Boor's algorithm: the spline of degree p with `count` control points over `knots` (count + p
// + 1 of them) at t. The knot span is clamped to the valid ones, so the end pieces extend.
Vec3d de_boor(const std::vector<Vec3d>& control, int p, const std::vector<double>& knots, double t) {
    const int count = static_cast<int>(control.size());
    // The span [t_s, t_{s+1}) that holds t, among the valid ones s = p … count − 1.
    const auto first_above = std::upper_bound(knots.begin() + p + 1, knots.begin() + count, t);
    const int span = static_cast<int>(first_above - knots.begin()) - 1;
    Vec3d d[kBsplineDegree + 1];
    for (int i = 0; i <= p; ++i) d[i] = control[static_cast<size_t>(span - p + i)];
    for (int r = 1; r <= p; ++r)
        for (int i = p; i >= r; --i) {
            const double left = knots[static_cast<size_t>(i + span - p)];
            const double right = knots[static_cast<size_t>(i + 1 + span - r)];
            d[i] = lerp(d[i - 1], d[i], (t - left) / (right - left));
        }
    return d[p];
}

// The control points of a B-spline's derivative, k·(P_{i+1} − P_i)/(t_{i+k+1} − t_{i+1}); its knots
// are the original ones without the first and the last.
std::vector<Vec3d> derivative_controls(const std::vector<Vec3d>& control, int p, const std::vector<double>& knots) {
    std::vector<Vec3d> result;
    for (size_t i = 0; i + 1 < control.size(); ++i) {
        const double span = knots[i + static_cast<size_t>(p) + 1] - knots[i + 1];
        result.push_back((p / span) * (control[i + 1] - control[i]));
    }
    return result;
}

// (a + 4b + c)/6: a uniform cubic B-spline at a knot. Both pieces meeting at that knot use this
// one expression, so they share the point exactly.
Vec3d knot_point(Vec3d a, Vec3d b, Vec3d c) { return (1.0 / 6) * (a + 4.0 * b + c); }

}  // namespace

int curve_degree(const Curve& curve) {
    return curve.type == CurveType::Bezier ? static_cast<int>(curve.controls.size()) - 1 : kBsplineDegree;
}

ParameterRange curve_parameter_range(const Curve& curve) {
    if (curve.type == CurveType::Bezier) return {0, 1};
    const int count = static_cast<int>(curve.controls.size());
    return {knot(kBsplineDegree, count), knot(count, count)};
}

CurveSample eval_bezier(const std::vector<Vec3d>& points, double u) {
    const int degree = static_cast<int>(points.size()) - 1;
    std::vector<Vec3d> level(points);
    CurveSample sample;
    // Each round of de Casteljau leaves one point fewer; the last three and two points give the
    // second and first derivatives as differences.
    for (int size = degree + 1; size > 1; --size) {
        if (size == 3)
            sample.second_derivative = static_cast<double>(degree * (degree - 1)) * (level[2] - 2.0 * level[1] + level[0]);
        if (size == 2) sample.derivative = static_cast<double>(degree) * (level[1] - level[0]);
        for (int i = 0; i + 1 < size; ++i) level[static_cast<size_t>(i)] = lerp(level[static_cast<size_t>(i)], level[static_cast<size_t>(i) + 1], u);
    }
    sample.position = level[0];
    return sample;
}

CurveSample eval_curve(const Curve& curve, double t) {
    std::vector<Vec3d> control;
    for (const Vec3f& p : curve.controls) control.push_back(to_double(p));
    if (curve.type == CurveType::Bezier) return eval_bezier(control, t);
    const int count = static_cast<int>(control.size());
    std::vector<double> knots;
    for (int i = 0; i <= count + kBsplineDegree; ++i) knots.push_back(knot(i, count));
    CurveSample sample;
    sample.position = de_boor(control, kBsplineDegree, knots, t);
    // The derivative is a spline of one degree less over the inner knots, and so on.
    const std::vector<Vec3d> first = derivative_controls(control, kBsplineDegree, knots);
    const std::vector<double> inner(knots.begin() + 1, knots.end() - 1);
    sample.derivative = de_boor(first, kBsplineDegree - 1, inner, t);
    const std::vector<Vec3d> second = derivative_controls(first, kBsplineDegree - 1, inner);
    const std::vector<double> innermost(inner.begin() + 1, inner.end() - 1);
    sample.second_derivative = de_boor(second, kBsplineDegree - 2, innermost, t);
    return sample;
}

std::vector<BezierPiece> curve_bezier_pieces(const Curve& curve) {
    std::vector<Vec3d> p;
    for (const Vec3f& c : curve.controls) p.push_back(to_double(c));
    std::vector<BezierPiece> pieces;
    if (curve.type == CurveType::Bezier) {
        pieces.push_back({p, 0, 1});
        return pieces;
    }
    // Uniform cubic B-spline to Bezier: the segment over [t_{k+j}, t_{k+j+1}] is driven by
    // P_j..P_{j+3}; its Bezier points sit at the knot points and at the thirds of P_{j+1}P_{j+2}.
    const int count = static_cast<int>(p.size());
    for (int j = 0; j + kBsplineDegree < count; ++j) {
        const Vec3d& a = p[static_cast<size_t>(j)];
        const Vec3d& b = p[static_cast<size_t>(j) + 1];
        const Vec3d& c = p[static_cast<size_t>(j) + 2];
        const Vec3d& d = p[static_cast<size_t>(j) + 3];
        BezierPiece piece;
        piece.points = {knot_point(a, b, c), (1.0 / 6) * (4.0 * b + 2.0 * c), (1.0 / 6) * (2.0 * b + 4.0 * c),
                        knot_point(b, c, d)};
        piece.t_begin = knot(kBsplineDegree + j, count);
        piece.t_end = knot(kBsplineDegree + j + 1, count);
        pieces.push_back(std::move(piece));
    }
    return pieces;
}

}  // namespace raycast
