// Tests for curve evaluation (geometry/curve.h): values and derivatives of a cubic Bezier curve
// and of a uniform cubic B-spline worked out by hand from their basis functions, derivatives
// against central differences on curves of several degrees, and the Bezier pieces, which must
// trace exactly the curve that de Casteljau and de Boor evaluate, with shared end points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/curve.h"

namespace raycast {
namespace {

Curve make_curve(CurveType type, std::vector<Vec3f> controls) { return Curve{type, std::move(controls)}; }

void expect_near(Vec3d actual, Vec3d expected, double tolerance, const char* what) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << what;
    EXPECT_NEAR(actual.y, expected.y, tolerance) << what;
    EXPECT_NEAR(actual.z, expected.z, tolerance) << what;
}

TEST(CurveTest, CubicBezierAtHalfIsTheBernsteinSum) {
    // P = (0,0), (1,2), (3,2), (4,0). At t = 1/2 the weights are 1/8, 3/8, 3/8, 1/8:
    // C = (0 + 3 + 9 + 4, 0 + 6 + 6 + 0)/8 = (2, 1.5).
    // C' = 3·[(1−t)²(P1−P0) + 2t(1−t)(P2−P1) + t²(P3−P2)] = 3·(¼(1,2) + ½(2,0) + ¼(1,−2)) = (4.5, 0).
    // C'' = 6·[(1−t)(P2 − 2P1 + P0) + t(P3 − 2P2 + P1)] = 6·(½(1,−2) + ½(−1,−2)) = (0, −12).
    const Curve c = make_curve(CurveType::Bezier, {{0, 0, 0}, {1, 2, 0}, {3, 2, 0}, {4, 0, 0}});
    EXPECT_EQ(curve_degree(c), 3);
    const CurveSample s = eval_curve(c, 0.5);
    expect_near(s.position, {2, 1.5, 0}, 1e-15, "position");
    expect_near(s.derivative, {4.5, 0, 0}, 1e-14, "derivative");
    expect_near(s.second_derivative, {0, -12, 0}, 1e-13, "second derivative");
    // The ends are the end points, and the end tangents point along the control polygon.
    expect_near(eval_curve(c, 0).position, {0, 0, 0}, 0, "start");
    expect_near(eval_curve(c, 1).position, {4, 0, 0}, 0, "end");
    expect_near(eval_curve(c, 0).derivative, {3, 6, 0}, 1e-15, "start tangent 3·(P1 − P0)");
    expect_near(eval_curve(c, 1).derivative, {3, -6, 0}, 1e-15, "end tangent 3·(P3 − P2)");
}

TEST(CurveTest, UniformCubicBsplineFollowsTheCoursesKnots) {
    // Four points, n = 3, k = 3: knots i/7, drawn over [t_3, t_4] = [3/7, 4/7], one segment whose
    // local parameter is u = 7t − 3. The uniform cubic basis at u = 0 is (1, 4, 1, 0)/6 and at
    // u = ½ it is (1, 23, 23, 1)/48; its u-derivative at ½ is (−1, −5, 5, 1)/8, so dC/dt is 7 times it.
    const Curve c = make_curve(CurveType::Bspline, {{0, 0, 0}, {6, 12, 0}, {12, 0, 0}, {48, 48, 0}});
    EXPECT_EQ(curve_degree(c), 3);
    const ParameterRange range = curve_parameter_range(c);
    EXPECT_DOUBLE_EQ(range.begin, 3.0 / 7);
    EXPECT_DOUBLE_EQ(range.end, 4.0 / 7);
    expect_near(eval_curve(c, 3.0 / 7).position, {(0 + 24 + 12) / 6.0, (0 + 48 + 0) / 6.0, 0}, 1e-13, "start");
    expect_near(eval_curve(c, 4.0 / 7).position, {(6 + 48 + 48) / 6.0, (12 + 0 + 48) / 6.0, 0}, 1e-13, "end");
    const CurveSample mid = eval_curve(c, 3.5 / 7);
    expect_near(mid.position, {(0 + 23 * 6 + 23 * 12 + 48) / 48.0, (0 + 23 * 12 + 0 + 48) / 48.0, 0}, 1e-13, "middle");
    expect_near(mid.derivative, {7 * (0 - 30 + 60 + 48) / 8.0, 7 * (0 - 60 + 0 + 48) / 8.0, 0}, 1e-12,
                "derivative");
}

TEST(CurveTest, AnyBsplineIsDrawnOverTkToTnPlusOne) {
    // 26 points: n = 25, knots i/29, range [3/29, 26/29].
    std::vector<Vec3f> points(26);
    for (size_t i = 0; i < points.size(); ++i) points[i] = {static_cast<float>(i), 0, 0};
    const ParameterRange range = curve_parameter_range(make_curve(CurveType::Bspline, points));
    EXPECT_DOUBLE_EQ(range.begin, 3.0 / 29);
    EXPECT_DOUBLE_EQ(range.end, 26.0 / 29);
    // Equally spaced points on a line are reproduced linearly: the curve at a knot t_j is point j − 2.
    const Curve line = make_curve(CurveType::Bspline, points);
    for (int j = 3; j <= 26; ++j) EXPECT_NEAR(eval_curve(line, j / 29.0).position.x, j - 2, 1e-12) << j;
}

// Derivatives against central differences of the curve itself, at random parameters.
void check_derivatives(const Curve& c, uint32_t seed) {
    std::mt19937 rng(seed);
    const ParameterRange range = curve_parameter_range(c);
    std::uniform_real_distribution<double> pick(range.begin + 1e-3, range.end - 1e-3);
    const double h = 1e-6 * (range.end - range.begin);
    for (int i = 0; i < 200; ++i) {
        const double t = pick(rng);
        const CurveSample s = eval_curve(c, t), before = eval_curve(c, t - h), after = eval_curve(c, t + h);
        const Vec3d first = (0.5 / h) * (after.position - before.position);
        const Vec3d second = (0.5 / h) * (after.derivative - before.derivative);
        const double scale1 = 1 + std::fabs(s.derivative.x) + std::fabs(s.derivative.y) + std::fabs(s.derivative.z);
        const double scale2 = 1 + std::fabs(s.second_derivative.x) + std::fabs(s.second_derivative.y) +
                              std::fabs(s.second_derivative.z);
        SCOPED_TRACE(testing::Message() << "seed " << seed << " t " << t);
        expect_near(s.derivative, first, 1e-6 * scale1, "first derivative");
        expect_near(s.second_derivative, second, 1e-5 * scale2, "second derivative");
    }
}

std::vector<Vec3f> random_points(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(-3, 3);
    std::vector<Vec3f> points;
    for (int i = 0; i < count; ++i) points.push_back({u(rng), u(rng), u(rng)});
    return points;
}

TEST(CurveTest, DerivativesMatchFiniteDifferences) {
    std::mt19937 rng(7);
    check_derivatives(make_curve(CurveType::Bezier, random_points(rng, 4)), 1);
    check_derivatives(make_curve(CurveType::Bezier, random_points(rng, 7)), 2);
    check_derivatives(make_curve(CurveType::Bezier, random_points(rng, 13)), 3);
    check_derivatives(make_curve(CurveType::Bspline, random_points(rng, 4)), 4);
    check_derivatives(make_curve(CurveType::Bspline, random_points(rng, 9)), 5);
    check_derivatives(make_curve(CurveType::Bspline, random_points(rng, 26)), 6);
}

// The pieces trace the same curve as eval_curve (de Casteljau on the whole Bezier curve, de Boor
// on the B-spline's knots): a different computation, so agreement checks both.
void check_pieces(const Curve& c) {
    const std::vector<BezierPiece> pieces = curve_bezier_pieces(c);
    const ParameterRange range = curve_parameter_range(c);
    ASSERT_FALSE(pieces.empty());
    EXPECT_DOUBLE_EQ(pieces.front().t_begin, range.begin);
    EXPECT_NEAR(pieces.back().t_end, range.end, 1e-15);
    for (size_t i = 0; i < pieces.size(); ++i) {
        const BezierPiece& piece = pieces[i];
        EXPECT_EQ(static_cast<int>(piece.points.size()), curve_degree(c) + 1);
        if (i > 0) {
            const Vec3d& end = pieces[i - 1].points.back();
            const Vec3d& start = piece.points.front();
            EXPECT_TRUE(end.x == start.x && end.y == start.y && end.z == start.z) << "pieces " << i - 1 << " and " << i
                                                                                  << " must share their end point exactly";
            EXPECT_DOUBLE_EQ(pieces[i - 1].t_end, piece.t_begin);
        }
        const double span = piece.t_end - piece.t_begin;
        for (double u : {0.0, 0.1, 0.37, 0.5, 0.81, 1.0}) {
            const CurveSample local = eval_bezier(piece.points, u);
            const CurveSample whole = eval_curve(c, piece.t_begin + u * span);
            SCOPED_TRACE(testing::Message() << "piece " << i << " u " << u);
            expect_near(local.position, whole.position, 1e-12, "position");
            expect_near((1 / span) * local.derivative, whole.derivative, 1e-9, "derivative");
        }
    }
}

TEST(CurveTest, BezierPiecesTraceTheCurve) {
    std::mt19937 rng(11);
    check_pieces(make_curve(CurveType::Bezier, random_points(rng, 4)));
    check_pieces(make_curve(CurveType::Bezier, random_points(rng, 10)));
    check_pieces(make_curve(CurveType::Bspline, random_points(rng, 4)));
    check_pieces(make_curve(CurveType::Bspline, random_points(rng, 12)));
    EXPECT_EQ(curve_bezier_pieces(make_curve(CurveType::Bspline, random_points(rng, 26))).size(), 23u);
}

TEST(CurveTest, RepeatedBsplinePointsPinTheEnd) {
    // Three equal first points make the curve start on them (the basis at u = 0 is (1, 4, 1)/6).
    const Curve c = make_curve(CurveType::Bspline, {{0, -1, 0}, {0, -1, 0}, {0, -1, 0}, {2, 0, 0}, {1, 2, 0}});
    expect_near(eval_curve(c, curve_parameter_range(c).begin).position, {0, -1, 0}, 1e-15, "start");
}

}  // namespace
}  // namespace raycast
