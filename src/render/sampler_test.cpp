// The sampler (render/sampler.h): every number depends only on (pixel, sample, index), so a pixel
// re-traced alone gets the same numbers; the pixel offsets are one per stratum; the numbers lie in
// [0, 1) and look uniform.
#include "render/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
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

// sincos_of_turns against the exact values (double precision) over the whole turn, at every
// quarter and eighth and between: within 1.5e-7, a float's rounding of values up to 1.
TEST(SamplerTest, SineAndCosineOfTurnsAreWithinARoundingOfTheExactValues) {
    std::vector<float> turns = {0.0f, 0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f, 0.99999994f};
    for (int i = 0; i < 100000; ++i) turns.push_back(static_cast<float>(i) / 100000);
    for (uint32_t bits = 0; bits < (1u << 24); bits += 4099) turns.push_back(unit_float(bits << 8));
    double worst = 0;
    for (const float t : turns) {
        float s, c;
        sincos_of_turns(t, s, c);
        const double angle = 6.283185307179586476925 * static_cast<double>(t);
        worst = std::max({worst, std::fabs(s - std::sin(angle)), std::fabs(c - std::cos(angle))});
        ASSERT_LE(std::fabs(s - std::sin(angle)), 1.5e-7) << "sin at " << t;
        ASSERT_LE(std::fabs(c - std::cos(angle)), 1.5e-7) << "cos at " << t;
    }
    EXPECT_GT(worst, 0.0);  // the comparison saw rounding, so it compared real values
    // The quarter turns are exact.
    float s, c;
    sincos_of_turns(0.25f, s, c);
    EXPECT_EQ(s, 1.0f);
    EXPECT_EQ(std::fabs(c), 0.0f);
    sincos_of_turns(0.5f, s, c);
    EXPECT_EQ(std::fabs(s), 0.0f);
    EXPECT_EQ(c, -1.0f);
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

// Malley's method in the basis of Duff et al., written out term by term in the order of
// sample_cosine_hemisphere's sums (and with std::fmax for the clamp): the directions' reference.
Vec3f cosine_hemisphere_by_the_formula(Vec3f n, Vec2f u) {
    const float r = std::sqrt(u.x);
    float sin_phi, cos_phi;
    sincos_of_turns(u.y, sin_phi, cos_phi);
    const float x = r * cos_phi, y = r * sin_phi;
    const float z = std::sqrt(std::fmax(0.0f, 1 - u.x));
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1 / (sign + n.z);
    const float b = n.x * n.y * a;
    const Vec3f tangent{1 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    const Vec3f bitangent{b, sign + n.y * n.y * a, -n.y};
    return tangent * x + bitangent * y + n * z;
}

// Ambient occlusion draws a packet's numbers and directions in loops over arrays (which the
// compiler vectorises): the same bits as one next_2d() a ray, and as the formula written out.
TEST(SamplerTest, NumbersAndDirectionsDrawnTogetherAreTheOnesDrawnOneByOne) {
    // A fresh sampler, and ones that have drawn already: next_2d_n looks up the indices' hashes
    // for its first 128 numbers from an even index (kSamplerIndexHashes), and hashes them past
    // that (112 drawn before, then 16 drawn together) and from an odd index (1, 127).
    for (const int before : {0, 1, 6, 96, 112, 127}) {
        for (const int count : {1, 3, 16}) {
            Sampler one_by_one(1234, 5), together(1234, 5);
            for (int i = 0; i < before; ++i) {
                one_by_one.next_1d();
                together.next_1d();
            }
            float u0[16], u1[16];
            together.next_2d_n(count, u0, u1);
            for (int i = 0; i < count; ++i) {
                const Vec2f u = one_by_one.next_2d();
                EXPECT_EQ(u0[i], u.x) << before << " drawn before, number " << i << " of " << count;
                EXPECT_EQ(u1[i], u.y) << before << " drawn before, number " << i << " of " << count;
            }
            // And on from there, the same numbers again.
            EXPECT_EQ(together.next_1d(), one_by_one.next_1d());
        }
    }
    Sampler sampler(7, 0);
    for (const Vec3f normal : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, Vec3f{1, 0, 0}, Vec3f{0, -1, 0},
                               normalize(Vec3f{0.3f, -0.5f, 0.8f}), normalize(Vec3f{-0.2f, 0.1f, -0.97f}),
                               normalize(Vec3f{1e-3f, -1, 1e-4f})}) {
        float u0[16], u1[16], x[16], y[16], z[16];
        for (int round = 0; round < 200; ++round) {
            sampler.next_2d_n(16, u0, u1);
            if (round == 0) u0[0] = 0;  // straight along the normal
            if (round == 0) u1[1] = 0.75f;  // a quarter turn exactly
            if (round == 0) u0[2] = 1.0f;   // 1 − u₀ = 0, and below it the clamp (outside [0, 1))
            if (round == 0) u0[3] = 1.5f;
            sample_cosine_hemisphere_n(HemisphereBasis(normal), 16, u0, u1, x, y, z);
            for (int i = 0; i < 16; ++i) {
                const Vec3f d = cosine_hemisphere_by_the_formula(normal, {u0[i], u1[i]});
                ASSERT_EQ(x[i], d.x) << "lane " << i << ", u (" << u0[i] << ", " << u1[i] << ")";
                ASSERT_EQ(y[i], d.y) << "lane " << i;
                ASSERT_EQ(z[i], d.z) << "lane " << i;
                const Vec3f one = sample_cosine_hemisphere(normal, {u0[i], u1[i]});  // a loop of one lane
                ASSERT_TRUE(one.x == d.x && one.y == d.y && one.z == d.z) << "lane " << i;
            }
        }
    }
}

// draw_cosine_directions is built for AVX-512 and AVX2 as well as the baseline
// (base/simd_clones.h); whichever copy this machine runs, its directions are the formula's, bit
// for bit, for every count a packet draws and from fresh and used samplers.
TEST(SamplerTest, DirectionsDrawnByEveryBuildAreTheFormulas) {
    const Vec3f normals[] = {Vec3f{0, 0, 1}, Vec3f{0, -1, 0}, normalize(Vec3f{0.3f, -0.5f, 0.8f}),
                             normalize(Vec3f{-0.2f, 0.1f, -0.97f})};
    for (const Vec3f normal : normals) {
        for (int count = 1; count <= kMaxDirectionsAtOnce; ++count) {
            for (uint32_t pixel = 0; pixel < 40; ++pixel) {
                Sampler drawing(pixel, 3), reference(pixel, 3);
                for (int round = 0; round < 3; ++round) {
                    float x[kMaxDirectionsAtOnce], y[kMaxDirectionsAtOnce], z[kMaxDirectionsAtOnce];
                    draw_cosine_directions(drawing, HemisphereBasis(normal), count, x, y, z);
                    for (int i = 0; i < count; ++i) {
                        const Vec3f d = cosine_hemisphere_by_the_formula(normal, reference.next_2d());
                        ASSERT_TRUE(x[i] == d.x && y[i] == d.y && z[i] == d.z)
                            << "count " << count << ", pixel " << pixel << ", round " << round << ", lane " << i;
                    }
                }
            }
        }
    }
}

}  // namespace
}  // namespace raycast
