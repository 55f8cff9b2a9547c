// Polynomials in Bernstein form on [0, 1] (coefficients c_0..c_n of Σ c_i·C(n,i)·u^i·(1 − u)^(n−i)),
// the basis in which curve pieces are given and in which rounding stays smallest: evaluation and
// subdivision by de Casteljau, products, and roots isolated by subdivision (the coefficients bound
// the polynomial, and their sign changes bound its number of roots: Descartes' rule in Bernstein
// form) then refined by bracketed Newton steps.
#pragma once

#include <vector>

namespace raycast {

/// The largest degree handled: products of two pieces of degree 30.
constexpr int kMaxBernsteinDegree = 60;

/// The value at u (de Casteljau), and the derivative in u if `derivative` is not null.
double eval_bernstein(const double* c, int degree, double u, double* derivative = nullptr);

/// The two halves over [0, u] and [u, 1], each as a polynomial over [0, 1] of the same degree.
/// `left` or `right` may be null. left[degree] == right[0], both the value at u.
void split_bernstein(const double* c, int degree, double u, double* left, double* right);

/// split_bernstein at u = ½ for a degree known at compile time: the subdivision step of root
/// isolation, unrolled by the compiler.
template <int kDegree>
inline void split_bernstein_half(const double* c, double* left, double* right) {
    double level[kDegree + 1];
    for (int i = 0; i <= kDegree; ++i) level[i] = c[i];
    for (int step = 0; step <= kDegree; ++step) {
        left[step] = level[0];
        right[kDegree - step] = level[kDegree - step];
        for (int i = 0; i < kDegree - step; ++i) level[i] = 0.5 * (level[i] + level[i + 1]);
    }
}

/// The weights C(m,i)·C(m,k−i)/C(2m,k) that make products of two degree-m polynomials:
/// (a·b)_k = Σ_i w[k][i]·a_i·b_{k−i}, stored as w[k·(m + 1) + i] (zero where k − i is out of range).
std::vector<double> bernstein_product_weights(int m);

/// a·b for a and b of degree m, with the weights above: 2m + 1 coefficients in `out`.
void multiply_bernstein(const double* a, const double* b, int m, const double* weights, double* out);

/// The number of sign changes along the coefficients, zeros skipped: at least the number of roots
/// in (0, 1), and of the same parity.
int sign_changes(const double* c, int degree);

/// What the coefficients tell about the roots strictly inside the interval.
enum class RootsInside {
    None,          ///< all of one sign (zeros allowed): every basis polynomial is positive inside
    OneBracketed,  ///< one sign change and neither end zero: exactly one root, between the ends
    Unknown,       ///< several sign changes, or one with a zero end: subdivide to know
};
RootsInside roots_inside(const double* c, int degree);

/// Where the control polygon (i/n, c_i) first crosses zero, in [0, 1]: for RootsInside::OneBracketed,
/// a good first guess of the root (the first step of Bezier clipping).
double control_polygon_crossing(const double* c, int degree);

/// The roots in [0, 1], ascending, at most `degree` of them (a root where the polynomial only
/// touches zero, or a cluster closer than about 1e-12, counts once). Returns how many were written.
/// A polynomial that is zero everywhere has none.
int bernstein_roots(const double* c, int degree, double* roots);

}  // namespace raycast
