// Tests for the Bernstein-form routines (geometry/bernstein.h): evaluation against the power form,
// subdivision, products, and root isolation on polynomials whose roots are known by construction
// (simple, double, clustered, at the ends, none), including every root of random products of
// linear factors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "geometry/bernstein.h"

namespace raycast {
namespace {

// The Bernstein coefficients of Π (u − r_i), built by multiplying linear factors (u − r) =
// (−r)·B0 + (1 − r)·B1 with the product routine.
std::vector<double> from_roots(const std::vector<double>& roots, double scale = 1) {
    std::vector<double> c = {scale};
    for (double r : roots) {
        const int m = static_cast<int>(c.size()) - 1;
        // Raise the factor to the current degree m by multiplying degree-1 factors one at a time:
        // (c of degree m)·(linear) = degree m + 1. Done in the power-free way: c·(u − r) with
        // c_k' = (k/(m+1))·c_{k−1}·(1 − r) + ((m+1−k)/(m+1))·c_k·(−r).
        std::vector<double> next(static_cast<size_t>(m) + 2, 0.0);
        for (int k = 0; k <= m + 1; ++k) {
            double value = 0;
            if (k > 0) value += static_cast<double>(k) / (m + 1) * c[static_cast<size_t>(k) - 1] * (1 - r);
            if (k <= m) value += static_cast<double>(m + 1 - k) / (m + 1) * c[static_cast<size_t>(k)] * (-r);
            next[static_cast<size_t>(k)] = value;
        }
        c = next;
    }
    return c;
}

double product_of_factors(const std::vector<double>& roots, double u) {
    double p = 1;
    for (double r : roots) p *= u - r;
    return p;
}

std::vector<double> roots_of(const std::vector<double>& c) {
    std::vector<double> roots(c.size());
    roots.resize(static_cast<size_t>(bernstein_roots(c.data(), static_cast<int>(c.size()) - 1, roots.data())));
    return roots;
}

TEST(BernsteinTest, EvaluatesAsThePowerForm) {
    // u² − u + 0.21 = (u − 0.3)(u − 0.7): Bernstein coefficients p(0) = 0.21, p(0) + p'(0)/2 = −0.29,
    // p(1) = 0.21.
    const double c[] = {0.21, -0.29, 0.21};
    for (double u : {0.0, 0.25, 0.3, 0.5, 0.9, 1.0}) {
        double slope = 0;
        EXPECT_NEAR(eval_bernstein(c, 2, u, &slope), u * u - u + 0.21, 1e-15) << u;
        EXPECT_NEAR(slope, 2 * u - 1, 1e-15) << u;
    }
    EXPECT_EQ(from_roots({0.3, 0.7}).size(), 3u);
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(from_roots({0.3, 0.7})[i], c[i], 1e-15);
}

TEST(BernsteinTest, SplittingKeepsThePolynomial) {
    const std::vector<double> c = from_roots({0.1, 0.45, 0.8, 1.3}, 2.5);
    double left[5], right[5];
    split_bernstein(c.data(), 4, 0.3, left, right);
    EXPECT_EQ(left[4], right[0]);
    for (double s : {0.0, 0.2, 0.5, 0.77, 1.0}) {
        EXPECT_NEAR(eval_bernstein(left, 4, s), eval_bernstein(c.data(), 4, 0.3 * s), 1e-14) << s;
        EXPECT_NEAR(eval_bernstein(right, 4, s), eval_bernstein(c.data(), 4, 0.3 + 0.7 * s), 1e-14) << s;
    }
}

TEST(BernsteinTest, ProductsMultiplyValues) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coefficient(-2, 2);
    for (int m : {1, 3, 6}) {
        std::vector<double> a(static_cast<size_t>(m) + 1), b(static_cast<size_t>(m) + 1), ab(2 * static_cast<size_t>(m) + 1);
        for (double& v : a) v = coefficient(rng);
        for (double& v : b) v = coefficient(rng);
        const std::vector<double> weights = bernstein_product_weights(m);
        multiply_bernstein(a.data(), b.data(), m, weights.data(), ab.data());
        for (double u : {0.0, 0.13, 0.5, 0.71, 1.0})
            EXPECT_NEAR(eval_bernstein(ab.data(), 2 * m, u), eval_bernstein(a.data(), m, u) * eval_bernstein(b.data(), m, u),
                        1e-13)
                << "m " << m << " u " << u;
    }
}

TEST(BernsteinTest, SignChangesSkipZeros) {
    const double c[] = {1, 0, -2, 0, 0, 3, -1};
    EXPECT_EQ(sign_changes(c, 6), 3);
    const double d[] = {0, 0, 1};
    EXPECT_EQ(sign_changes(d, 2), 0);
}

TEST(BernsteinTest, TellsWhatTheCoefficientsSayAboutRoots) {
    const double positive[] = {1, 0, 2, 0.5};
    EXPECT_EQ(roots_inside(positive, 3), RootsInside::None);
    const double one[] = {-1, -0.5, 2, 3};
    EXPECT_EQ(roots_inside(one, 3), RootsInside::OneBracketed);
    // The control polygon (0, −1), (⅓, −0.5), (⅔, 2), (1, 3) crosses zero on its middle edge,
    // at ⅓ + ⅓·0.5/2.5 = 0.4.
    EXPECT_NEAR(control_polygon_crossing(one, 3), 0.4, 1e-15);
    const double two[] = {1, -1, 1};
    EXPECT_EQ(roots_inside(two, 2), RootsInside::Unknown);
    const double zero_end[] = {0, -1, 1};
    EXPECT_EQ(roots_inside(zero_end, 2), RootsInside::Unknown);
}

TEST(BernsteinTest, FindsSimpleRoots) {
    const std::vector<double> roots = roots_of(from_roots({0.1, 0.5, 0.9}));
    ASSERT_EQ(roots.size(), 3u);
    EXPECT_NEAR(roots[0], 0.1, 1e-15);
    EXPECT_NEAR(roots[1], 0.5, 1e-15);
    EXPECT_NEAR(roots[2], 0.9, 1e-15);
    // Roots outside [0, 1] are not reported.
    const std::vector<double> inside = roots_of(from_roots({-0.5, 0.25, 1.5}));
    ASSERT_EQ(inside.size(), 1u);
    EXPECT_NEAR(inside[0], 0.25, 1e-15);
}

TEST(BernsteinTest, FindsRootsAtTheEnds) {
    const std::vector<double> roots = roots_of(from_roots({0, 0.6, 1}));
    ASSERT_EQ(roots.size(), 3u);
    EXPECT_EQ(roots[0], 0);
    EXPECT_NEAR(roots[1], 0.6, 1e-15);
    EXPECT_EQ(roots[2], 1);
}

TEST(BernsteinTest, ADoubleRootCountsOnceAndCloseRootsApart) {
    // (u − ½)²: subdivision lands on the root, found once, exactly.
    const std::vector<double> touching = roots_of(from_roots({0.5, 0.5}));
    ASSERT_EQ(touching.size(), 1u);
    EXPECT_EQ(touching[0], 0.5);
    // (u − 0.4)² only touches zero: rounding decides whether it dips below (a double root is
    // defined to about √ε), so at most one root, there.
    const std::vector<double> grazing = roots_of(from_roots({0.4, 0.4}));
    ASSERT_LE(grazing.size(), 1u);
    for (double root : grazing) EXPECT_NEAR(root, 0.4, 1e-7);
    // Roots 1e-6 apart are told apart; each is found to about ε/|p'| ≈ 1e-16/1e-7.
    const std::vector<double> close = roots_of(from_roots({0.4, 0.4 + 1e-6, 0.9}));
    ASSERT_EQ(close.size(), 3u);
    EXPECT_NEAR(close[0], 0.4, 1e-10);
    EXPECT_NEAR(close[1], 0.4 + 1e-6, 1e-10);
}

TEST(BernsteinTest, NoRootsWhereThereAreNone) {
    EXPECT_TRUE(roots_of(from_roots({-0.2, 1.7})).empty());
    EXPECT_TRUE(roots_of({1, -0.4, 1}).empty());  // 1 − 2.8u + 2.8u²: discriminant 7.84 − 11.2 < 0
    EXPECT_TRUE(roots_of({0, 0, 0, 0}).empty());
}

TEST(BernsteinTest, FindsEveryRootOfRandomProducts) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> where(-0.3, 1.3);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<double> factors(static_cast<size_t>(1 + trial % 8));
        for (double& r : factors) r = where(rng);
        std::vector<double> expected;
        for (double r : factors)
            if (r >= 0 && r <= 1) expected.push_back(r);
        std::sort(expected.begin(), expected.end());
        // Roots closer than 1e-4 make the test about clusters, which the test above covers.
        bool separated = true;
        for (size_t i = 1; i < expected.size(); ++i) separated &= expected[i] - expected[i - 1] > 1e-4;
        if (!separated) continue;
        const std::vector<double> found = roots_of(from_roots(factors));
        ASSERT_EQ(found.size(), expected.size()) << "trial " << trial;
        for (size_t i = 0; i < found.size(); ++i) {
            EXPECT_NEAR(found[i], expected[i], 1e-10) << "trial " << trial;
            EXPECT_NEAR(product_of_factors(factors, found[i]), 0, 1e-12) << "trial " << trial;
        }
    }
}

}  // namespace
}  // namespace raycast
