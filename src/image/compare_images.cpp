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

bool is_ignored(const ImageRgb8* mask, size_t pixel) {
    return mask && mask->rgb[3 * pixel] == 0 && mask->rgb[3 * pixel + 1] == 0 && mask->rgb[3 * pixel + 2] == 0;
}

// Largest channel difference of each pixel; 0 for pixels the mask ignores.
std::vector<uint8_t> max_channel_errors(const ImageRgb8& a, const ImageRgb8& b, const ImageRgb8* mask) {
    std::vector<uint8_t> errors(a.rgb.size() / 3);
    for (size_t i = 0; i < errors.size(); ++i) {
        if (is_ignored(mask, i)) continue;
        int largest = 0;
        for (size_t c = 0; c < 3; ++c) largest = std::max(largest, std::abs(a.rgb[3 * i + c] - b.rgb[3 * i + c]));
        errors[i] = static_cast<uint8_t>(largest);
    }
    return errors;
}

// A percentage with three significant digits at most and no exponent: 0.13, 0.00751, 12.5, 100.
std::string format_percent(double percent) {
    int decimals = 0;
    if (percent > 0) decimals = std::clamp(2 - static_cast<int>(std::floor(std::log10(percent))), 0, 9);
    std::string text = string_printf("%.*f", decimals, percent);
    if (text.find('.') != std::string::npos) {
        while (text.back() == '0') text.pop_back();
        if (text.back() == '.') text.pop_back();
    }
    return text + "%";
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

ImageComparison compare_images(const ImageRgb8& a, const ImageRgb8& b, const ImageRgb8* mask) {
    check_same_size(a, b, "compare_images");
    if (mask) check_same_size(a, *mask, "compare_images (mask)");
    ImageComparison result;
    result.width = a.width;
    result.height = a.height;
    result.max_channel_error = max_channel_errors(a, b, mask);

    // Integer sums are exact: at most 3·2^26 channels of 255² each fit easily in 64 bits.
    uint64_t sum = 0, sum_of_squares = 0;
    for (size_t pixel = 0; pixel < result.max_channel_error.size(); ++pixel) {
        if (is_ignored(mask, pixel)) {
            ++result.ignored_pixels;
            continue;
        }
        for (size_t i = 3 * pixel; i < 3 * pixel + 3; ++i) {
            const auto d = static_cast<uint64_t>(std::abs(a.rgb[i] - b.rgb[i]));
            sum += d;
            sum_of_squares += d * d;
        }
    }
    result.pixel_count = result.max_channel_error.size() - result.ignored_pixels;
    for (uint8_t error : result.max_channel_error) {
        if (error > 0) ++result.differing_pixels;
        result.max_error = std::max(result.max_error, int{error});
    }
    const double channels = 3.0 * static_cast<double>(result.pixel_count);
    result.mean_error = result.pixel_count == 0 ? 0.0 : static_cast<double>(sum) / channels;
    if (sum_of_squares == 0) {
        result.psnr = std::numeric_limits<double>::infinity();
    } else {
        const double mse = static_cast<double>(sum_of_squares) / channels;
        result.psnr = 10.0 * std::log10(255.0 * 255.0 / mse);
    }
    return result;
}

size_t ImageTolerance::allowed_pixels(size_t compared) const {
    // The relative slack keeps a product such as 0.003 · 1000, a hair under 3 in binary, from
    // rounding down to 2; it is far below one pixel for any image raycast reads.
    return static_cast<size_t>(std::floor(max_fraction * static_cast<double>(compared) * (1 + 1e-12)));
}

bool within_tolerance(const ImageComparison& comparison, const ImageTolerance& tolerance, std::string* why) {
    const size_t beyond = comparison.pixels_beyond(tolerance.max_diff);
    const size_t allowed = tolerance.allowed_pixels(comparison.pixel_count);
    if (why) {
        const double share = comparison.pixel_count == 0
                                 ? 0.0
                                 : 100.0 * static_cast<double>(beyond) / static_cast<double>(comparison.pixel_count);
        *why = string_printf("%zu of %zu pixels (%s) differ by more than %d level%s; ", beyond, comparison.pixel_count,
                             format_percent(share).c_str(), tolerance.max_diff, tolerance.max_diff == 1 ? "" : "s");
        if (allowed == 0 && tolerance.max_fraction == 0)
            *why += "none may";
        else
            *why += string_printf("at most %s (%zu pixel%s) may", format_percent(100.0 * tolerance.max_fraction).c_str(),
                                  allowed, allowed == 1 ? "" : "s");
    }
    return beyond <= allowed;
}

ImageRgb8 difference_heat_map(const ImageRgb8& a, const ImageRgb8& b, const ImageRgb8* mask) {
    check_same_size(a, b, "difference_heat_map");
    if (mask) check_same_size(a, *mask, "difference_heat_map (mask)");
    const std::vector<uint8_t> errors = max_channel_errors(a, b, mask);
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
