#include "math/mat4.h"

#include <cmath>

namespace raycast {

namespace {

constexpr double kPi = 3.14159265358979323846;

double radians(float degrees) { return static_cast<double>(degrees) * kPi / 180.0; }

}  // namespace

Mat4 Mat4::translate(Vec3f offset) {
    Mat4 t;
    t.m[0][3] = offset.x;
    t.m[1][3] = offset.y;
    t.m[2][3] = offset.z;
    return t;
}

Mat4 Mat4::scale(Vec3f factors) {
    Mat4 s;
    s.m[0][0] = factors.x;
    s.m[1][1] = factors.y;
    s.m[2][2] = factors.z;
    return s;
}

Mat4 Mat4::rotate_x(float degrees) { return rotate({1, 0, 0}, degrees); }
Mat4 Mat4::rotate_y(float degrees) { return rotate({0, 1, 0}, degrees); }
Mat4 Mat4::rotate_z(float degrees) { return rotate({0, 0, 1}, degrees); }

Mat4 Mat4::rotate(Vec3f axis, float degrees) {
    // Rodrigues' formula, evaluated in double so that rotations by multiples of 90 degrees
    // come out with clean zeros and ones.
    const double len = std::sqrt(double(axis.x) * axis.x + double(axis.y) * axis.y + double(axis.z) * axis.z);
    const double x = axis.x / len, y = axis.y / len, z = axis.z / len;
    double c = std::cos(radians(degrees)), s = std::sin(radians(degrees));
    // cos(pi/2) is 6e-17 in double, not 0: a wall turned by 90 degrees would then lean a little,
    // and a ray parallel to it would hit it far away. Multiples of 90 degrees get exact values.
    const double turns = double(degrees) / 90;
    if (turns == std::floor(turns) && std::fabs(turns) < 1e9) {
        const int quarter = static_cast<int>(std::fmod(turns, 4.0) + 4) % 4;
        const double exact_cos[4] = {1, 0, -1, 0}, exact_sin[4] = {0, 1, 0, -1};
        c = exact_cos[quarter];
        s = exact_sin[quarter];
    }
    const double k = 1 - c;
    const double r[3][3] = {{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                            {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                            {z * x * k - y * s, z * y * k + x * s, c + z * z * k}};
    Mat4 result;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) result.m[i][j] = static_cast<float>(r[i][j]);
    return result;
}

Mat4 Mat4::from_rows(const float values[16]) {
    Mat4 result;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) result.m[i][j] = values[i * 4 + j];
    return result;
}

Mat4 Mat4::from_columns(const float values[16]) { return transpose(from_rows(values)); }

bool Mat4::operator==(const Mat4& other) const {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (m[i][j] != other.m[i][j]) return false;
    return true;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
    Mat4 result;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double sum = 0;
            for (int k = 0; k < 4; ++k) sum += double(a.m[i][k]) * double(b.m[k][j]);
            result.m[i][j] = static_cast<float>(sum);
        }
    return result;
}

Mat4 transpose(const Mat4& a) {
    Mat4 result;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) result.m[i][j] = a.m[j][i];
    return result;
}

namespace {

// Determinant of the 3x3 minor of `a` without row `row` and column `col`.
double minor3(const double a[4][4], int row, int col) {
    double sub[3][3];
    for (int i = 0, si = 0; i < 4; ++i) {
        if (i == row) continue;
        for (int j = 0, sj = 0; j < 4; ++j) {
            if (j == col) continue;
            sub[si][sj++] = a[i][j];
        }
        ++si;
    }
    return sub[0][0] * (sub[1][1] * sub[2][2] - sub[1][2] * sub[2][1]) -
           sub[0][1] * (sub[1][0] * sub[2][2] - sub[1][2] * sub[2][0]) +
           sub[0][2] * (sub[1][0] * sub[2][1] - sub[1][1] * sub[2][0]);
}

void to_double(const Mat4& a, double out[4][4]) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out[i][j] = a.m[i][j];
}

}  // namespace

double determinant(const Mat4& a) {
    double d[4][4];
    to_double(a, d);
    double det = 0;
    for (int j = 0; j < 4; ++j) det += ((j % 2) ? -1.0 : 1.0) * d[0][j] * minor3(d, 0, j);
    return det;
}

Mat4 inverse(const Mat4& a, bool* ok) {
    double d[4][4];
    to_double(a, d);
    const double det = determinant(a);
    Mat4 result;
    bool finite = det != 0 && std::isfinite(det);
    if (finite) {
        // inverse = adjugate / det; the adjugate is the transposed cofactor matrix.
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                const double cofactor = (((i + j) % 2) ? -1.0 : 1.0) * minor3(d, i, j);
                const double value = cofactor / det;
                result.m[j][i] = static_cast<float>(value);
                finite = finite && std::isfinite(result.m[j][i]);
            }
    }
    if (!finite) result = Mat4{};
    if (ok) *ok = finite;
    return result;
}

}  // namespace raycast
