// Tests for Mat4 (math/mat4.h), which carries every Transform of a scene: the elementary matrices
// on points whose images are worked out by hand, the order of composition (A·B applies B first),
// the two 16-number layouts (MIT rows, course columns), determinant and inverse (random
// well-conditioned matrices, singular ones reported), and the three ways of mapping points,
// directions and normals (normals by the inverse transpose, so they stay perpendicular).
#include "math/mat4.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <initializer_list>
#include <random>
#include <string>

namespace raycast {
namespace {

constexpr float kTol = 1e-6f;

void expect_near(Vec3f actual, Vec3f expected, float tolerance = kTol) {
    EXPECT_NEAR(actual.x, expected.x, tolerance) << "x";
    EXPECT_NEAR(actual.y, expected.y, tolerance) << "y";
    EXPECT_NEAR(actual.z, expected.z, tolerance) << "z";
}

void expect_near(const Mat4& actual, const Mat4& expected, float tolerance) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            EXPECT_NEAR(actual.m[i][j], expected.m[i][j], tolerance) << "entry [" << i << "][" << j << "]";
}

Mat4 rows(std::initializer_list<float> values) {
    float v[16];
    int i = 0;
    for (float x : values) v[i++] = x;
    return Mat4::from_rows(v);
}

TEST(Mat4Test, DefaultIsTheIdentity) {
    const Mat4 m;
    EXPECT_TRUE(m.is_identity());
    EXPECT_TRUE(Mat4::identity().is_identity());
    EXPECT_EQ(transform_point(m, {1, 2, 3}), (Vec3f{1, 2, 3}));
    Mat4 changed;
    changed.m[3][2] = 1e-30f;
    EXPECT_FALSE(changed.is_identity());
    EXPECT_FALSE(changed == m);
}

TEST(Mat4Test, TranslateMovesPointsButNotVectors) {
    const Mat4 t = Mat4::translate({1, -2, 3});
    EXPECT_EQ(transform_point(t, {10, 20, 30}), (Vec3f{11, 18, 33}));
    EXPECT_EQ(transform_vector(t, {10, 20, 30}), (Vec3f{10, 20, 30}));
}

TEST(Mat4Test, ScaleMultipliesEachAxis) {
    const Mat4 s = Mat4::scale({2, 3, -4});
    EXPECT_EQ(transform_point(s, {1, 1, 1}), (Vec3f{2, 3, -4}));
    EXPECT_EQ(transform_vector(s, {0.5f, 2, 0.25f}), (Vec3f{1, 6, -1}));
}

TEST(Mat4Test, RotationsAboutTheAxesAreRightHanded) {
    // Counter-clockwise seen from the axis tip: x→y about z, y→z about x, z→x about y.
    expect_near(transform_point(Mat4::rotate_z(90), {1, 0, 0}), {0, 1, 0});
    expect_near(transform_point(Mat4::rotate_z(90), {0, 1, 0}), {-1, 0, 0});
    expect_near(transform_point(Mat4::rotate_x(90), {0, 1, 0}), {0, 0, 1});
    expect_near(transform_point(Mat4::rotate_x(90), {0, 0, 1}), {0, -1, 0});
    expect_near(transform_point(Mat4::rotate_y(90), {0, 0, 1}), {1, 0, 0});
    expect_near(transform_point(Mat4::rotate_y(90), {1, 0, 0}), {0, 0, -1});
    expect_near(transform_point(Mat4::rotate_z(-90), {1, 0, 0}), {0, -1, 0});
    expect_near(transform_point(Mat4::rotate_x(180), {0, 1, 2}), {0, -1, -2});
    // 30 degrees about z: (cos 30, sin 30, 0) = (√3/2, 1/2, 0).
    expect_near(transform_point(Mat4::rotate_z(30), {2, 0, 5}), {std::sqrt(3.0f), 1, 5});
    // 45 degrees about x takes (0, 1, 1) to (0, 0, √2).
    expect_near(transform_point(Mat4::rotate_x(45), {0, 1, 1}), {0, 0, std::sqrt(2.0f)});
    // The axis itself does not move.
    expect_near(transform_point(Mat4::rotate_y(37), {0, 4, 0}), {0, 4, 0});
    // A full turn is (close to) the identity.
    expect_near(Mat4::rotate_x(360), Mat4{}, 1e-6f);
}

TEST(Mat4Test, RotateAboutAnArbitraryAxis) {
    // About (1, 1, 1) by 120 degrees the axes cycle x→y→z→x.
    const Mat4 r = Mat4::rotate({1, 1, 1}, 120);
    expect_near(transform_point(r, {1, 0, 0}), {0, 1, 0});
    expect_near(transform_point(r, {0, 1, 0}), {0, 0, 1});
    expect_near(transform_point(r, {0, 0, 1}), {1, 0, 0});
    // 180 degrees about a = (1, 1, 0)/√2 maps v to 2(a·v)a − v: (1, 0, 0) → (0, 1, 0).
    expect_near(transform_point(Mat4::rotate({1, 1, 0}, 180), {1, 0, 0}), {0, 1, 0});
    // The axis need not be unit length, and its direction matters, not its length.
    expect_near(Mat4::rotate({0, 0, 5}, 90), Mat4::rotate_z(90), 1e-7f);
    expect_near(Mat4::rotate({0.001f, 0, 0}, 33), Mat4::rotate_x(33), 1e-7f);
    expect_near(Mat4::rotate({0, -2, 0}, 30), Mat4::rotate_y(-30), 1e-7f);
}

TEST(Mat4Test, RandomRotationsAreOrthonormalWithDeterminantOne) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1, 1);
    for (int i = 0; i < 200; ++i) {
        Vec3f axis{u(rng), u(rng), u(rng)};
        if (length(axis) < 0.1f) continue;
        const float degrees = 360 * u(rng);
        const Mat4 r = Mat4::rotate(axis, degrees);
        expect_near(r * transpose(r), Mat4{}, 1e-6f);
        EXPECT_NEAR(determinant(r), 1.0, 1e-6);
        // The axis is fixed; the rotation by −θ undoes it.
        expect_near(transform_vector(r, axis), axis, 1e-6f);
        expect_near(Mat4::rotate(axis, -degrees) * r, Mat4{}, 1e-6f);
        if (HasFailure()) return;
    }
}

// mat4.cpp evaluates Rodrigues' formula in double "so that rotations by multiples of 90 degrees
// come out with clean zeros and ones". cos(π/2) in double is 6.1e-17, not 0, and it survives the
// conversion to float, so rotate_z(90) has 6.1e-17 where 0 belongs: points on an axis pick up
// tiny off-axis components (an axis-aligned box rotated by 90 degrees is no longer axis-aligned).
TEST(Mat4Test, RotationsByMultiplesOfNinetyDegreesAreExact) {
    const Mat4 z90 = rows({0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    EXPECT_EQ(Mat4::rotate_z(90), z90);
    EXPECT_EQ(transform_point(Mat4::rotate_z(90), {1, 0, 0}), (Vec3f{0, 1, 0}));
    EXPECT_EQ(transform_point(Mat4::rotate_x(180), {0, 1, 0}), (Vec3f{0, -1, 0}));
    EXPECT_EQ(transform_point(Mat4::rotate_y(270), {1, 0, 0}), (Vec3f{0, 0, 1}));
    EXPECT_EQ(transform_point(Mat4::rotate_y(-90), {1, 0, 0}), (Vec3f{0, 0, 1}));
}

TEST(Mat4Test, ProductAppliesTheRightFactorFirst) {
    const Mat4 t = Mat4::translate({1, 2, 3});
    const Mat4 s = Mat4::scale({2, 2, 2});
    // (T·S)p = T(Sp) = 2p + (1, 2, 3); (S·T)p = S(Tp) = 2(p + (1, 2, 3)).
    EXPECT_EQ(transform_point(t * s, {1, 1, 1}), (Vec3f{3, 4, 5}));
    EXPECT_EQ(transform_point(s * t, {1, 1, 1}), (Vec3f{4, 6, 8}));
    // Rotate then translate vs translate then rotate.
    expect_near(transform_point(t * Mat4::rotate_z(90), {1, 0, 0}), {1, 3, 3});
    expect_near(transform_point(Mat4::rotate_z(90) * t, {1, 0, 0}), {-2, 2, 3});
}

TEST(Mat4Test, ProductMatchesHandComputedEntries) {
    // A = rows 1..16. (A·A)[0][0] = 1·1 + 2·5 + 3·9 + 4·13 = 90; [0][1] = 2 + 12 + 30 + 56 = 100;
    // [3][3] = 13·4 + 14·8 + 15·12 + 16·16 = 600; [2][1] = 9·2 + 10·6 + 11·10 + 12·14 = 356.
    const Mat4 a = rows({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16});
    const Mat4 p = a * a;
    EXPECT_EQ(p.m[0][0], 90);
    EXPECT_EQ(p.m[0][1], 100);
    EXPECT_EQ(p.m[3][3], 600);
    EXPECT_EQ(p.m[2][1], 356);
    EXPECT_EQ(a * Mat4{}, a);
    EXPECT_EQ(Mat4{} * a, a);
}

TEST(Mat4Test, FromRowsAndFromColumnsAreTransposes) {
    const float v[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    const Mat4 r = Mat4::from_rows(v);
    const Mat4 c = Mat4::from_columns(v);
    EXPECT_EQ(r.m[0][1], 2);   // row 0 is 1 2 3 4
    EXPECT_EQ(r.m[1][0], 5);
    EXPECT_EQ(c.m[0][1], 5);   // column 0 is 1 2 3 4
    EXPECT_EQ(c.m[1][0], 2);
    EXPECT_EQ(c.m[3][0], 4);
    EXPECT_EQ(c, transpose(r));
    EXPECT_EQ(transpose(transpose(r)), r);
    // A translation by (7, 8, 9) as MIT writes it (rows: last column) and as the course's
    // column-major Matrix4f stores it (translation in values 12..14).
    const float mit[16] = {1, 0, 0, 7, 0, 1, 0, 8, 0, 0, 1, 9, 0, 0, 0, 1};
    const float course[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 8, 9, 1};
    EXPECT_EQ(Mat4::from_rows(mit), Mat4::translate({7, 8, 9}));
    EXPECT_EQ(Mat4::from_columns(course), Mat4::translate({7, 8, 9}));
}

TEST(Mat4Test, DeterminantOfHandPickedMatrices) {
    EXPECT_EQ(determinant(Mat4{}), 1.0);
    EXPECT_EQ(determinant(Mat4::scale({2, 3, 4})), 24.0);
    EXPECT_EQ(determinant(Mat4::translate({5, 6, 7})), 1.0);
    // Lower triangular: the product of the diagonal, 2·3·4·1.
    EXPECT_EQ(determinant(rows({2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 4, 0, 1, 2, 3, 1})), 24.0);
    // Swapping two rows of the identity flips the sign.
    EXPECT_EQ(determinant(rows({0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1})), -1.0);
    // Rows 1..16 are in arithmetic progression (row2 − row1 = row3 − row2): rank 2.
    EXPECT_EQ(determinant(rows({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16})), 0.0);
    // A full matrix by cofactors along row 0 (done by hand):
    // | 2 0 1 0 |
    // | 1 3 0 0 |  = 2·|3 0 0; 0 1 1; 0 0 2| + 1·|1 3 0; 0 0 1; 1 0 2| = 2·6 + 1·(1·(0−0) − 3·(0−1) + 0) = 15
    // | 0 0 1 1 |
    // | 1 0 0 2 |
    EXPECT_EQ(determinant(rows({2, 0, 1, 0, 1, 3, 0, 0, 0, 0, 1, 1, 1, 0, 0, 2})), 15.0);
}

Mat4 random_well_conditioned(std::mt19937& rng) {
    // Diagonally dominant (|diagonal| ≥ 3 > sum of the other |entries| ≤ 3·0.9), so far from
    // singular; sometimes an affine transform (last row 0 0 0 1), sometimes a full matrix.
    std::uniform_real_distribution<float> off(-0.9f, 0.9f), diag(3, 6), coin(0, 1);
    Mat4 m;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) m.m[i][j] = i == j ? (coin(rng) < 0.5f ? -diag(rng) : diag(rng)) : off(rng);
    if (coin(rng) < 0.5f) {
        m.m[3][0] = m.m[3][1] = m.m[3][2] = 0;
        m.m[3][3] = 1;
    }
    return m;
}

TEST(Mat4Test, InverseTimesMatrixIsTheIdentity) {
    std::mt19937 rng(11);
    for (int i = 0; i < 500; ++i) {
        const Mat4 m = random_well_conditioned(rng);
        bool ok = false;
        const Mat4 inv = inverse(m, &ok);
        ASSERT_TRUE(ok);
        expect_near(inv * m, Mat4{}, 2e-6f);
        expect_near(m * inv, Mat4{}, 2e-6f);
        // det(M⁻¹) = 1/det(M); det(A·B) = det(A)·det(B).
        EXPECT_NEAR(determinant(inv) * determinant(m), 1.0, 1e-5);
        const Mat4 other = random_well_conditioned(rng);
        const double expected = determinant(m) * determinant(other);
        EXPECT_NEAR(determinant(m * other), expected, 1e-5 * std::fabs(expected));
        if (HasFailure()) return;
    }
}

TEST(Mat4Test, InverseOfElementaryTransforms) {
    // Exact in float: the negated translation, the reciprocal power-of-two scale.
    EXPECT_EQ(inverse(Mat4::translate({1, -2, 3})), Mat4::translate({-1, 2, -3}));
    EXPECT_EQ(inverse(Mat4::scale({2, 4, -8})), Mat4::scale({0.5f, 0.25f, -0.125f}));
    expect_near(inverse(Mat4::rotate_x(30)), Mat4::rotate_x(-30), 1e-7f);
    // (T·R·S)⁻¹ = S⁻¹·R⁻¹·T⁻¹.
    const Mat4 t = Mat4::translate({3, 1, 2}), r = Mat4::rotate({1, 2, 3}, 40), s = Mat4::scale({2, 0.5f, 4});
    expect_near(inverse(t * r * s), inverse(s) * inverse(r) * inverse(t), 1e-6f);
    bool ok = false;
    inverse(Mat4{}, &ok);
    EXPECT_TRUE(ok);
}

TEST(Mat4Test, SingularMatricesAreReportedAndGiveTheIdentity) {
    const float nan = std::nanf("");
    for (const Mat4& m : {Mat4::scale({1, 0, 1}), rows({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16}),
                          Mat4{} * Mat4::scale({0, 0, 0}), rows({1, 2, 0, 0, 2, 4, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}),
                          Mat4::scale({nan, 1, 1}), Mat4::scale({INFINITY, 1, 1}),
                          // Invertible in exact arithmetic, but the inverse 1e39 is beyond FLT_MAX.
                          Mat4::scale({1e-39f, 1, 1})}) {
        bool ok = true;
        const Mat4 inv = inverse(m, &ok);
        EXPECT_FALSE(ok);
        EXPECT_TRUE(inv.is_identity());
    }
    // A tiny but representable scale is not singular.
    bool ok = false;
    const Mat4 inv = inverse(Mat4::scale({1e-20f, 1, 1}), &ok);
    EXPECT_TRUE(ok);
    EXPECT_NEAR(inv.m[0][0], 1e20f, 1e14f);
}

TEST(Mat4Test, NormalsTransformByTheInverseTransposeAndStayPerpendicular) {
    // The plane x + y = 0 has normal n = (1, 1, 0)/√2 and tangents (1, −1, 0), (0, 0, 1). Under
    // M = scale(2, 1, 1) the tangents become (2, −1, 0) and (0, 0, 1); M⁻ᵀn ∝ (1/2, 1, 0), i.e.
    // the unit normal (1, 2, 0)/√5, which is perpendicular to both.
    const Mat4 m = Mat4::scale({2, 1, 1});
    const Vec3f n = normalize(Vec3f{1, 1, 0});
    const Vec3f world_normal = transform_normal(inverse(m), n);
    expect_near(world_normal, Vec3f{1, 2, 0} / std::sqrt(5.0f));
    EXPECT_NEAR(dot(world_normal, transform_vector(m, {1, -1, 0})), 0, kTol);
    // Mapping the normal like a direction would not be perpendicular: (2, 1, 0)·(2, −1, 0) = 3.
    EXPECT_NEAR(dot(transform_vector(m, {1, 1, 0}), transform_vector(m, {1, -1, 0})), 3, kTol);
    // Translation does not affect normals.
    expect_near(transform_normal(inverse(Mat4::translate({5, 6, 7}) * m), n), Vec3f{1, 2, 0} / std::sqrt(5.0f));

    // Random affine transforms and random planes: the transformed normal is unit length and
    // perpendicular to the transformed tangents.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1, 1), positive(0.2f, 3);
    for (int i = 0; i < 200; ++i) {
        const Mat4 a = Mat4::translate({u(rng), u(rng), u(rng)}) * Mat4::rotate({u(rng), u(rng), u(rng) + 2}, 180 * u(rng)) *
                       Mat4::scale({positive(rng), positive(rng), positive(rng)}) *
                       Mat4::rotate({u(rng) + 2, u(rng), u(rng)}, 180 * u(rng));
        const Vec3f normal = normalize(Vec3f{u(rng), u(rng), u(rng) + 1.5f});
        const Vec3f t1 = normalize(cross(normal, Vec3f{1, 0, 0}));
        const Vec3f t2 = cross(normal, t1);
        const Vec3f transformed = transform_normal(inverse(a), normal);
        EXPECT_NEAR(length(transformed), 1, 1e-5f);
        EXPECT_NEAR(dot(transformed, normalize(transform_vector(a, t1))), 0, 2e-5f);
        EXPECT_NEAR(dot(transformed, normalize(transform_vector(a, t2))), 0, 2e-5f);
        if (HasFailure()) return;
    }
}

TEST(Mat4Test, TransformPointUsesTheLastColumnAndIgnoresTheLastRow) {
    // M·(p, 1) keeps the first three rows; this matrix's last row (projective part) is ignored,
    // as it is for every affine transform the scene format can write.
    const Mat4 m = rows({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 0, 0, 0, 1});
    // Row 0: 1·1 + 2·2 + 3·3 + 4 = 18; row 1: 5 + 12 + 21 + 8 = 46; row 2: 9 + 20 + 33 + 12 = 74.
    EXPECT_EQ(transform_point(m, {1, 2, 3}), (Vec3f{18, 46, 74}));
    EXPECT_EQ(transform_vector(m, {1, 2, 3}), (Vec3f{14, 38, 62}));
}

}  // namespace
}  // namespace raycast
