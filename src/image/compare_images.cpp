#include "image/compare_images.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "base/error.h"

namespace raycast {

namespace {

void check_same_size(const ImageRgb8& a, const ImageRgb8& b, const char* function) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument(string_printf("%s: the images differ in size: %dx%d and %dx%d", function, a.width,
                                                  a.height, b.width, b.height));
    if (a.width < 0 || a.height < 0)
        throw std::invalid_argument(string_printf("%s: negative image size %dx%d", function, a.width, a.height));
    const size_t bytes = 3 * static_cast<size_t>(a.width) * static_cast<size_t>(a.height);
    if (a.rgb.size() != bytes || b.rgb.size() != bytes)
        throw std::invalid_argument(string_printf("%s: a %dx%d image needs %zu bytes, the images hold %zu and %zu",
                                                  function, a.width, a.height, bytes, a.rgb.size(), b.rgb.size()));
}

// Largest channel difference of each pixel.
std::vector<uint8_t> max_channel_errors(const ImageRgb8& a, const ImageRgb8& b) {
    std::vector<uint8_t> errors(a.rgb.size() / 3);
    for (size_t i = 0; i < errors.size(); ++i) {
        int largest = 0;
        for (size_t c = 0; c < 3; ++c) largest = std::max(largest, std::abs(a.rgb[3 * i + c] - b.rgb[3 * i + c]));
        errors[i] = static_cast<uint8_t>(largest);
    }
    return errors;
}

struct Rgb8 {
    uint8_t r, g, b;
};

// The heat map's ramp for s in (0, 1]: dark blue, red, yellow, white at s = 0, 1/3, 2/3, 1. It starts at
// dark blue rather than black so that a 1-level difference beside a 255-level one still shows.
Rgb8 heat_colour(double s) {
    static const double kStops[4][3] = {{0, 0, 160}, {255, 0, 0}, {255, 255, 0}, {255, 255, 255}};
    const double scaled = std::clamp(s, 0.0, 1.0) * 3.0;
    const int segment = std::min(2, static_cast<int>(scaled));
    const double t = scaled - segment;
    auto mix = [&](int channel) {
        const double value = kStops[segment][channel] + (kStops[segment + 1][channel] - kStops[segment][channel]) * t;
        return static_cast<uint8_t>(std::lround(value));
    };
    return {mix(0), mix(1), mix(2)};
}

}  // namespace

size_t ImageComparison::pixels_beyond(int tolerance) const {
    return static_cast<size_t>(std::count_if(max_channel_error.begin(), max_channel_error.end(),
                                             [tolerance](uint8_t error) { return error > tolerance; }));
}

ImageComparison compare_images(const ImageRgb8& a, const ImageRgb8& b) {
    check_same_size(a, b, "compare_images");
    ImageComparison result;
    result.width = a.width;
    result.height = a.height;
    result.max_channel_error = max_channel_errors(a, b);
    result.pixel_count = result.max_channel_error.size();

    // Integer sums are exact: at most 3·2^26 channels of 255² each fit easily in 64 bits.
    uint64_t sum = 0, sum_of_squares = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const auto d = static_cast<uint64_t>(std::abs(a.rgb[i] - b.rgb[i]));
        sum += d;
        sum_of_squares += d * d;
    }
    for (uint8_t error : result.max_channel_error) {
        if (error > 0) ++result.differing_pixels;
        result.max_error = std::max(result.max_error, int{error});
    }
    const double channels = static_cast<double>(a.rgb.size());
    result.mean_error = a.rgb.empty() ? 0.0 : static_cast<double>(sum) / channels;
    if (sum_of_squares == 0) {
        result.psnr = std::numeric_limits<double>::infinity();
    } else {
        const double mse = static_cast<double>(sum_of_squares) / channels;
        result.psnr = 10.0 * std::log10(255.0 * 255.0 / mse);
    }
    return result;
}

ImageRgb8 difference_heat_map(const ImageRgb8& a, const ImageRgb8& b) {
    check_same_size(a, b, "difference_heat_map");
    const std::vector<uint8_t> errors = max_channel_errors(a, b);
    const uint8_t largest = errors.empty() ? 0 : *std::max_element(errors.begin(), errors.end());
    ImageRgb8 map(a.width, a.height);
    for (size_t i = 0; i < errors.size(); ++i) {
        if (errors[i] == 0) continue;  // equal pixels stay black
        const Rgb8 colour = heat_colour(static_cast<double>(errors[i]) / largest);
        map.rgb[3 * i + 0] = colour.r;
        map.rgb[3 * i + 1] = colour.g;
        map.rgb[3 * i + 2] = colour.b;
    }
    return map;
}

}  // namespace raycast
