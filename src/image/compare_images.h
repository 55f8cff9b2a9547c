// Comparing two 8-bit images: error statistics for image regression tests, and a heat map of where
// they differ. Entry points: compare_images, difference_heat_map.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "image/image.h"

namespace raycast {

/// How far two images of the same size are apart; channel differences are absolute, in 8-bit levels.
struct ImageComparison {
    int width = 0, height = 0;
    size_t pixel_count = 0;
    size_t differing_pixels = 0;  ///< pixels where any channel differs
    int max_error = 0;            ///< largest channel difference, in levels
    double mean_error = 0;        ///< mean absolute channel difference over all channels, in levels
    double psnr = 0;              ///< dB over all channels, peak 255; +infinity when identical

    /// Pixels whose largest channel difference exceeds `tolerance` levels.
    size_t pixels_beyond(int tolerance) const;

    std::vector<uint8_t> max_channel_error;  ///< per pixel (index y·width + x), for pixels_beyond and the heat map
};

/// Compares two images of the same size; throws std::invalid_argument if sizes differ (callers check
/// first and report nicely).
ImageComparison compare_images(const ImageRgb8& a, const ImageRgb8& b);

/// A heat map of the per-pixel largest channel difference: black where equal, otherwise a ramp from
/// dark blue through red and yellow to white, scaled so that the largest difference is white. Even a
/// difference of 1 level shows as dark blue. Throws std::invalid_argument if sizes differ.
ImageRgb8 difference_heat_map(const ImageRgb8& a, const ImageRgb8& b);

}  // namespace raycast
