#include "geometry/bernstein.h"

#include <cmath>

namespace raycast {

namespace {

// Subdivision stops at intervals this narrow (2^-45, about 3e-14), or after this many intervals:
// a root cluster narrower than that is reported once, at its interval's middle.
constexpr int kMaxSubdivisionDepth = 45;
constexpr int kMaxIntervals = 4096;

double binomial(int n, int k) {
    double result = 1;
    for (int i = 1; i <= k; ++i) result = result * (n - k + i) / i;
    return result;
}

struct RootList {
    double* roots;
    int capacity;
    int count = 0;
    int intervals = 0;

    void add(double u) {
        if (count > 0 && std::fabs(u - roots[count - 1]) < 1e-12) return;
        if (count < capacity) roots[count++] = u;
    }
};

// The root of the polynomial `c` (over [0, 1]) inside [lo, hi], where it changes sign once (its
// sign at lo is `sign_lo`): Newton steps from `u`, replaced by bisection whenever they leave the
// bracket.
double refine_root(const double* c, int degree, double lo, double hi, double u, double sign_lo) {
    for (int iteration = 0; iteration < 100; ++iteration) {
        double slope = 0;
        const double value = eval_bernstein(c, degree, u, &slope);
        if (value == 0) return u;
        if ((value > 0) == (sign_lo > 0))
            lo = u;
        else
            hi = u;
        const double newton = u - value / slope;
        const double next = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
        if (std::fabs(next - u) <= 1e-16 || hi - lo <= 1e-16) return next;
        u = next;
    }
    return u;
}

void isolate(const double* original, int degree, const double* c, double start, double width, int depth,
             RootList& out) {
    if (++out.intervals > kMaxIntervals) return;
    const RootsInside roots = roots_inside(c, degree);
    if (roots == RootsInside::None) return;
    if (roots == RootsInside::OneBracketed) {
        out.add(refine_root(original, degree, start, start + width,
                            start + width * control_polygon_crossing(c, degree), c[0]));
        return;
    }
    if (depth == kMaxSubdivisionDepth) {
        out.add(start + 0.5 * width);
        return;
    }
    double left[kMaxBernsteinDegree + 1], right[kMaxBernsteinDegree + 1];
    split_bernstein(c, degree, 0.5, left, right);
    isolate(original, degree, left, start, 0.5 * width, depth + 1, out);
    if (right[0] == 0) out.add(start + 0.5 * width);
    isolate(original, degree, right, start + 0.5 * width, 0.5 * width, depth + 1, out);
}

}  // namespace

double eval_bernstein(const double* c, int degree, double u, double* derivative) {
    double level[kMaxBernsteinDegree + 1];
    for (int i = 0; i <= degree; ++i) level[i] = c[i];
    for (int size = degree + 1; size > 1; --size) {
        if (size == 2 && derivative) *derivative = degree * (level[1] - level[0]);
        for (int i = 0; i + 1 < size; ++i) level[i] += u * (level[i + 1] - level[i]);
    }
    if (degree == 0 && derivative) *derivative = 0;
    return level[0];
}

void split_bernstein(const double* c, int degree, double u, double* left, double* right) {
    double level[kMaxBernsteinDegree + 1];
    for (int i = 0; i <= degree; ++i) level[i] = c[i];
    for (int step = 0; step <= degree; ++step) {
        if (left) left[step] = level[0];
        if (right) right[degree - step] = level[degree - step];
        for (int i = 0; i < degree - step; ++i) level[i] += u * (level[i + 1] - level[i]);
    }
}

std::vector<double> bernstein_product_weights(int m) {
    std::vector<double> weights(static_cast<size_t>((2 * m + 1) * (m + 1)), 0.0);
    for (int k = 0; k <= 2 * m; ++k)
        for (int i = 0; i <= m; ++i)
            if (k - i >= 0 && k - i <= m)
                weights[static_cast<size_t>(k * (m + 1) + i)] = binomial(m, i) * binomial(m, k - i) / binomial(2 * m, k);
    return weights;
}

void multiply_bernstein(const double* a, const double* b, int m, const double* weights, double* out) {
    for (int k = 0; k <= 2 * m; ++k) {
        const int first = k > m ? k - m : 0, last = k < m ? k : m;
        double sum = 0;
        for (int i = first; i <= last; ++i) sum += weights[k * (m + 1) + i] * a[i] * b[k - i];
        out[k] = sum;
    }
}

int sign_changes(const double* c, int degree) {
    int changes = 0;
    double previous = 0;
    for (int i = 0; i <= degree; ++i) {
        if (c[i] == 0) continue;
        if (previous != 0 && (c[i] > 0) != (previous > 0)) ++changes;
        previous = c[i];
    }
    return changes;
}

RootsInside roots_inside(const double* c, int degree) {
    bool positive = false, negative = false;
    for (int i = 0; i <= degree; ++i) {
        positive |= c[i] > 0;
        negative |= c[i] < 0;
    }
    if (!positive || !negative) return RootsInside::None;
    if (sign_changes(c, degree) == 1 && c[0] != 0 && c[degree] != 0) return RootsInside::OneBracketed;
    return RootsInside::Unknown;
}

double control_polygon_crossing(const double* c, int degree) {
    int k = 0;
    while (k + 1 < degree && (c[k + 1] > 0) == (c[0] > 0)) ++k;
    if (c[k] == c[k + 1]) return 0.5;
    return (k + c[k] / (c[k] - c[k + 1])) / degree;
}

int bernstein_roots(const double* c, int degree, double* roots) {
    bool all_zero = true;
    for (int i = 0; i <= degree; ++i) all_zero &= c[i] == 0;
    if (all_zero || degree < 1) return 0;
    RootList out{roots, degree};
    if (c[0] == 0) out.add(0);
    isolate(c, degree, c, 0, 1, 0, out);
    if (c[degree] == 0) out.add(1);
    return out.count;
}

}  // namespace raycast
