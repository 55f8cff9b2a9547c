// The sampler (render/sampler.h): every number depends only on (pixel, sample, index), so a pixel
// re-traced alone gets the same numbers; the pixel offsets are one per stratum; the numbers lie in
// [0, 1) and look uniform.
#include "render/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

namespace raycast {
namespace {

TEST(SamplerTest, OneSampleIsThePixelsOwnPoint) {
    const Vec2f offset = pixel_sample_offset(12345, 0, 1);
    EXPECT_EQ(offset.x, 0.5f);
    EXPECT_EQ(offset.y, 0.5f);
}

TEST(SamplerTest, SquareCountsPutOneSampleInEachCellOfTheGrid) {
    for (const int n : {2, 3, 4}) {
        const int spp = n * n;
        std::set<std::pair<int, int>> cells;
        for (int s = 0; s < spp; ++s) {
            const Vec2f o = pixel_sample_offset(77, s, spp);
            ASSERT_GE(o.x, 0.0f);
            ASSERT_LT(o.x, 1.0f);
            ASSERT_GE(o.y, 0.0f);
            ASSERT_LT(o.y, 1.0f);
            // Sample s is in column s mod n and row s / n.
            EXPECT_EQ(static_cast<int>(o.x * static_cast<float>(n)), s % n);
            EXPECT_EQ(static_cast<int>(o.y * static_cast<float>(n)), s / n);
            cells.insert({static_cast<int>(o.x * static_cast<float>(n)), static_cast<int>(o.y * static_cast<float>(n))});
        }
        EXPECT_EQ(cells.size(), static_cast<size_t>(spp));
    }
    // Other counts: a row of spp columns.
    for (int s = 0; s < 5; ++s) EXPECT_EQ(static_cast<int>(pixel_sample_offset(9, s, 5).x * 5), s);
}

TEST(SamplerTest, NumbersDependOnlyOnPixelSampleAndIndex) {
    Sampler a(1000, 3), b(1000, 3), other_pixel(1001, 3), other_sample(1000, 4);
    for (int i = 0; i < 100; ++i) {
        const float x = a.next_1d();
        EXPECT_EQ(x, b.next_1d());
        EXPECT_NE(x, other_pixel.next_1d());
        EXPECT_NE(x, other_sample.next_1d());
    }
    EXPECT_EQ(lens_sample(5, 2).x, lens_sample(5, 2).x);
    EXPECT_NE(lens_sample(5, 2).x, lens_sample(5, 3).x);
}

TEST(SamplerTest, NumbersAreInTheUnitIntervalAndSpreadEvenly) {
    // 64 000 numbers in 64 bins: each bin expects 1000; a uniform stream stays well within ±15%.
    std::vector<int> bins(64, 0);
    for (uint32_t pixel = 0; pixel < 1000; ++pixel) {
        Sampler sampler(pixel, 0);
        for (int i = 0; i < 64; ++i) {
            const float u = sampler.next_1d();
            ASSERT_GE(u, 0.0f);
            ASSERT_LT(u, 1.0f);
            ++bins[static_cast<size_t>(u * 64)];
        }
    }
    for (const int count : bins) {
        EXPECT_GT(count, 850);
        EXPECT_LT(count, 1150);
    }
}

TEST(SamplerTest, CosineHemisphereDirectionsAreUnitAboveTheNormalWithDensityCosThetaOverPi) {
    // With density cos θ/π, cos² θ is uniform on [0, 1): E[cos θ] = 2/3 and P(cos θ > c) = 1 − c².
    for (const Vec3f normal : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, Vec3f{1, 0, 0}, normalize(Vec3f{0.3f, -0.5f, 0.8f}),
                               normalize(Vec3f{-0.2f, 0.1f, -0.97f})}) {
        Sampler sampler(42, 0);
        const int n = 40000;
        double sum_cos = 0;
        int above_half = 0;
        for (int i = 0; i < n; ++i) {
            const Vec3f d = sample_cosine_hemisphere(normal, sampler.next_2d());
            ASSERT_NEAR(length(d), 1.0f, 1e-5f);
            const float c = dot(d, normal);
            ASSERT_GE(c, -1e-6f);
            sum_cos += c;
            above_half += c > 0.5f ? 1 : 0;
        }
        // Standard errors: 0.0012 for the mean, 0.0022 for the share; allow about 5 of them.
        EXPECT_NEAR(sum_cos / n, 2.0 / 3.0, 0.006);
        EXPECT_NEAR(static_cast<double>(above_half) / n, 0.75, 0.011);
    }
    // u = (0, ·) is straight along the normal.
    const Vec3f up = sample_cosine_hemisphere(normalize(Vec3f{1, 2, 3}), {0, 0.3f});
    EXPECT_NEAR(dot(up, normalize(Vec3f{1, 2, 3})), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace raycast
