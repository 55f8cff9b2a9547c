// Comparing two 8-bit images: error statistics for image regression tests, a grader's pass/fail
// tolerance, and a heat map of where they differ. Entry points: compare_images, within_tolerance,
// difference_heat_map.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "image/image.h"

namespace raycast {

/// How far two images of the same size are apart; channel differences are absolute, in 8-bit levels.
struct ImageComparison {
    int width = 0, height = 0;
    size_t pixel_count = 0;       ///< pixels compared: all of them, less those the mask ignores
    size_t ignored_pixels = 0;    ///< pixels the mask left out of every figure here
    size_t differing_pixels = 0;  ///< pixels where any channel differs
    int max_error = 0;            ///< largest channel difference, in levels
    double mean_error = 0;        ///< mean absolute channel difference over all channels, in levels
    double psnr = 0;              ///< dB over all channels, peak 255; +infinity when identical

    /// Pixels whose largest channel difference exceeds `tolerance` levels.
    size_t pixels_beyond(int tolerance) const;

    /// Per pixel (index y·width + x), for pixels_beyond and the heat map; 0 where the mask ignores it.
    std::vector<uint8_t> max_channel_error;
};

/// Compares two images of the same size. With `mask`, an image of that size too, the pixels that
/// are black (0, 0, 0) in the mask are ignored: left out of every count, error and the PSNR (the
/// convention of OpenCV's and ImageMagick's masks: zero leaves a pixel out). Throws
/// std::invalid_argument if sizes differ (callers check first and report nicely).
ImageComparison compare_images(const ImageRgb8& a, const ImageRgb8& b, const ImageRgb8* mask = nullptr);

/// A grader's tolerance: at most `max_fraction` of the compared pixels may differ by more than
/// `max_diff` levels in some channel. The course's PA1 reference images are matched with {1, 0.001}:
/// at least 99.9% of the pixels within one level.
struct ImageTolerance {
    int max_diff = 0;         ///< levels, 0 to 255
    double max_fraction = 0;  ///< 0 to 1

    /// How many of `compared` pixels may differ by more than max_diff: max_fraction · compared,
    /// rounded down (0.001 of 40,000 pixels allows 40).
    size_t allowed_pixels(size_t compared) const;
};

/// Whether the comparison is within the tolerance. `why`, if given, gets one line that says how
/// far the images are from it, e.g. "52 of 40000 pixels (0.13%) differ by more than 1 level; at
/// most 0.1% (40 pixels) may".
bool within_tolerance(const ImageComparison& comparison, const ImageTolerance& tolerance, std::string* why = nullptr);

/// A heat map of the per-pixel largest channel difference: black where equal, otherwise a ramp from
/// dark blue through red and yellow to white, scaled so that the largest difference is white. Even a
/// difference of 1 level shows as dark blue. Pixels a mask ignores (see compare_images) are black.
/// Throws std::invalid_argument if sizes differ.
ImageRgb8 difference_heat_map(const ImageRgb8& a, const ImageRgb8& b, const ImageRgb8* mask = nullptr);

}  // namespace raycast
