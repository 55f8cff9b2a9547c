#include "image/compare_images.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

namespace raycast {
namespace {

ImageRgb8 make_image(int width, int height, std::initializer_list<uint8_t> rgb) {
    ImageRgb8 image(width, height);
    image.rgb.assign(rgb);
    return image;
}

TEST(CompareImages, HandComputedTwoPixels) {
    // Channel differences 0 2 3 | 0 0 0: one pixel differs, by at most 3; mean 5/6; squared sum 13, so
    // MSE 13/6 and PSNR 10·log10(255² · 6/13) = 44.7729 dB.
    const ImageRgb8 a = make_image(2, 1, {10, 20, 30, 100, 100, 100});
    const ImageRgb8 b = make_image(2, 1, {10, 22, 27, 100, 100, 100});
    const ImageComparison c = compare_images(a, b);
    EXPECT_EQ(c.width, 2);
    EXPECT_EQ(c.height, 1);
    EXPECT_EQ(c.pixel_count, 2u);
    EXPECT_EQ(c.differing_pixels, 1u);
    EXPECT_EQ(c.max_error, 3);
    EXPECT_NEAR(c.mean_error, 5.0 / 6.0, 1e-12);
    EXPECT_NEAR(c.psnr, 44.77288258944717, 1e-9);
    EXPECT_EQ(c.max_channel_error, (std::vector<uint8_t>{3, 0}));
    EXPECT_EQ(c.pixels_beyond(0), 1u);
    EXPECT_EQ(c.pixels_beyond(2), 1u);
    EXPECT_EQ(c.pixels_beyond(3), 0u);
}

TEST(CompareImages, HandComputedFourPixelsBothSigns) {
    // Per-pixel largest differences 1, 0, 5, 255 (b above a, then a above b); channel sum 1 + 5 + 3·255 = 771
    // over 12 channels; squared sum 1 + 25 + 3·65025 = 195101, so PSNR 10·log10(65025 · 12/195101) = 6.0200 dB.
    const ImageRgb8 a = make_image(2, 2, {0, 0, 0, 9, 9, 9, 0, 5, 0, 255, 255, 255});
    const ImageRgb8 b = make_image(2, 2, {1, 0, 0, 9, 9, 9, 0, 0, 0, 0, 0, 0});
    const ImageComparison c = compare_images(a, b);
    EXPECT_EQ(c.pixel_count, 4u);
    EXPECT_EQ(c.differing_pixels, 3u);
    EXPECT_EQ(c.max_error, 255);
    EXPECT_NEAR(c.mean_error, 771.0 / 12.0, 1e-12);
    EXPECT_NEAR(c.psnr, 6.020021115170761, 1e-9);
    EXPECT_EQ(c.max_channel_error, (std::vector<uint8_t>{1, 0, 5, 255}));
    EXPECT_EQ(c.pixels_beyond(0), 3u);
    EXPECT_EQ(c.pixels_beyond(1), 2u);
    EXPECT_EQ(c.pixels_beyond(4), 2u);
    EXPECT_EQ(c.pixels_beyond(5), 1u);
    EXPECT_EQ(c.pixels_beyond(255), 0u);
    // Swapping the images changes nothing.
    const ImageComparison swapped = compare_images(b, a);
    EXPECT_EQ(swapped.max_channel_error, c.max_channel_error);
    EXPECT_EQ(swapped.psnr, c.psnr);
}

TEST(CompareImages, AMaskLeavesItsBlackPixelsOutOfEveryFigure) {
    // The four pixels above with the last (off by 255) black in the mask: left are per-pixel errors
    // 1, 0, 5 over 3 pixels; channel sum 1 + 5 = 6 over 9 channels; squared sum 1 + 25 = 26, so
    // PSNR 10·log10(255² · 9/26) = 43.5235 dB. Any colour but black keeps a pixel (here 1, 0, 0).
    const ImageRgb8 a = make_image(2, 2, {0, 0, 0, 9, 9, 9, 0, 5, 0, 255, 255, 255});
    const ImageRgb8 b = make_image(2, 2, {1, 0, 0, 9, 9, 9, 0, 0, 0, 0, 0, 0});
    const ImageRgb8 mask = make_image(2, 2, {255, 255, 255, 1, 0, 0, 0, 0, 1, 0, 0, 0});
    const ImageComparison c = compare_images(a, b, &mask);
    EXPECT_EQ(c.pixel_count, 3u);
    EXPECT_EQ(c.ignored_pixels, 1u);
    EXPECT_EQ(c.differing_pixels, 2u);
    EXPECT_EQ(c.max_error, 5);
    EXPECT_NEAR(c.mean_error, 6.0 / 9.0, 1e-12);
    EXPECT_NEAR(c.psnr, 43.52349522336417, 1e-9);
    EXPECT_EQ(c.max_channel_error, (std::vector<uint8_t>{1, 0, 5, 0}));
    // The heat map leaves the ignored pixel black, and the largest difference left (5) is white;
    // 1 of 5 is at 0.6 of the ramp's first third, from dark blue (0, 0, 160) to red: (153, 0, 64).
    EXPECT_EQ(difference_heat_map(a, b, &mask).rgb,
              (LargeVector<uint8_t>{153, 0, 64, 0, 0, 0, 255, 255, 255, 0, 0, 0}));
    const ImageRgb8 small_mask(1, 2);
    EXPECT_THROW(compare_images(a, b, &small_mask), std::invalid_argument);
}

// A comparison of 1000 pixels of which `beyond` differ by 5 levels and the rest not at all.
ImageComparison thousand_pixels(size_t beyond) {
    ImageComparison c;
    c.pixel_count = 1000;
    c.max_channel_error.assign(1000, 0);
    for (size_t i = 0; i < beyond; ++i) c.max_channel_error[i] = 5;
    return c;
}

TEST(ImageTolerance, AllowsTheFractionOfThePixelsRoundedDown) {
    const ImageTolerance course{1, 0.001};
    EXPECT_EQ(course.allowed_pixels(40000), 40u);
    EXPECT_EQ(course.allowed_pixels(39999), 39u);
    EXPECT_EQ(course.allowed_pixels(1000), 1u);
    EXPECT_EQ(course.allowed_pixels(999), 0u);
    // Decimal fractions whose binary products fall a hair short of the whole number.
    EXPECT_EQ((ImageTolerance{0, 0.003}).allowed_pixels(1000), 3u);
    EXPECT_EQ((ImageTolerance{0, 0.7}).allowed_pixels(10), 7u);
    EXPECT_EQ((ImageTolerance{0, 1}).allowed_pixels(12345), 12345u);
    EXPECT_EQ((ImageTolerance{0, 0}).allowed_pixels(12345), 0u);
}

TEST(ImageTolerance, SaysInOneLineHowFarTheImagesAreFromIt) {
    std::string why;
    EXPECT_FALSE(within_tolerance(thousand_pixels(2), ImageTolerance{1, 0.001}, &why));
    EXPECT_EQ(why, "2 of 1000 pixels (0.2%) differ by more than 1 level; at most 0.1% (1 pixel) may");
    EXPECT_TRUE(within_tolerance(thousand_pixels(1), ImageTolerance{1, 0.001}, &why));
    EXPECT_EQ(why, "1 of 1000 pixels (0.1%) differ by more than 1 level; at most 0.1% (1 pixel) may");
    EXPECT_TRUE(within_tolerance(thousand_pixels(2), ImageTolerance{5, 0}, &why));
    EXPECT_EQ(why, "0 of 1000 pixels (0%) differ by more than 5 levels; none may");
    EXPECT_FALSE(within_tolerance(thousand_pixels(2), ImageTolerance{4, 0}, &why));
    EXPECT_EQ(why, "2 of 1000 pixels (0.2%) differ by more than 4 levels; none may");
    EXPECT_FALSE(within_tolerance(thousand_pixels(52), ImageTolerance{1, 0.025}, &why));
    EXPECT_EQ(why, "52 of 1000 pixels (5.2%) differ by more than 1 level; at most 2.5% (25 pixels) may");
    EXPECT_FALSE(within_tolerance(thousand_pixels(2), ImageTolerance{1, 0.001}));  // without a why
}

TEST(CompareImages, IdenticalImagesHaveInfinitePsnr) {
    const ImageRgb8 a = make_image(3, 1, {1, 2, 3, 4, 5, 6, 7, 8, 9});
    const ImageComparison c = compare_images(a, a);
    EXPECT_EQ(c.pixel_count, 3u);
    EXPECT_EQ(c.differing_pixels, 0u);
    EXPECT_EQ(c.max_error, 0);
    EXPECT_EQ(c.mean_error, 0.0);
    EXPECT_TRUE(std::isinf(c.psnr) && c.psnr > 0);
    EXPECT_EQ(c.pixels_beyond(0), 0u);
}

TEST(CompareImages, DifferentSizesThrow) {
    EXPECT_THROW(compare_images(ImageRgb8(2, 3), ImageRgb8(3, 2)), std::invalid_argument);
    EXPECT_THROW(difference_heat_map(ImageRgb8(2, 2), ImageRgb8(2, 1)), std::invalid_argument);
    ImageRgb8 short_buffer(2, 2);
    short_buffer.rgb.pop_back();
    EXPECT_THROW(compare_images(short_buffer, ImageRgb8(2, 2)), std::invalid_argument);
}

TEST(DifferenceHeatMap, BlackWhereEqualWhiteAtTheLargest) {
    // Largest differences 0, 1, 2, 3 with the largest 3: black, then the ramp at 1/3 (red), 2/3 (yellow), 1 (white).
    const ImageRgb8 a = make_image(4, 1, {50, 50, 50, 50, 50, 50, 50, 50, 50, 50, 50, 50});
    const ImageRgb8 b = make_image(4, 1, {50, 50, 50, 50, 51, 50, 48, 50, 50, 50, 50, 53});
    const ImageRgb8 map = difference_heat_map(a, b);
    ASSERT_EQ(map.width, 4);
    ASSERT_EQ(map.height, 1);
    EXPECT_EQ(map.rgb, (LargeVector<uint8_t>{0, 0, 0, 255, 0, 0, 255, 255, 0, 255, 255, 255}));
}

TEST(DifferenceHeatMap, OneLevelStaysVisibleAndBrightnessGrows) {
    // Pixel x differs by x levels in red, 0..255.
    ImageRgb8 a(256, 1), b(256, 1);
    for (int x = 0; x < 256; ++x) b.at(x, 0)[0] = static_cast<uint8_t>(x);
    const ImageRgb8 map = difference_heat_map(a, b);
    auto brightness = [&](int x) { return map.at(x, 0)[0] + map.at(x, 0)[1] + map.at(x, 0)[2]; };
    EXPECT_EQ(brightness(0), 0);
    EXPECT_GE(brightness(1), 100) << "a 1-level difference must be visible";
    EXPECT_EQ(brightness(255), 765);
    for (int x = 2; x < 256; ++x) EXPECT_GE(brightness(x), brightness(x - 1)) << x;
}

TEST(DifferenceHeatMap, IdenticalImagesGiveBlack) {
    const ImageRgb8 a = make_image(2, 1, {1, 2, 3, 4, 5, 6});
    EXPECT_EQ(difference_heat_map(a, a).rgb, LargeVector<uint8_t>(6, 0));
}

}  // namespace
}  // namespace raycast
