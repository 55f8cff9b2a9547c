// Images in memory: the float image the renderer fills, and the 8-bit image that files hold.
// Both store row y = 0 first, and y = 0 is the bottom row of the picture (the course's layout).
#pragma once

#include <cstdint>
#include <vector>

#include "base/large_allocator.h"
#include "base/limits.h"  // kMaxImageSide, kMaxImagePixels: the largest image read or written
#include "math/vec.h"

namespace raycast {

/// Linear RGB floats, one Vec3f per pixel, pixel (x, y) at index y·width + x.
struct Image {
    int width = 0, height = 0;
    LargeVector<Vec3f> pixels;

    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(static_cast<size_t>(w) * static_cast<size_t>(h)) {}
    Vec3f& at(int x, int y) { return pixels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]; }
    const Vec3f& at(int x, int y) const {
        return pixels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
    }
};

/// 8 bits per channel, RGB interleaved, pixel (x, y) at byte 3·(y·width + x).
struct ImageRgb8 {
    int width = 0, height = 0;
    LargeVector<uint8_t> rgb;

    ImageRgb8() = default;
    ImageRgb8(int w, int h) : width(w), height(h), rgb(3 * static_cast<size_t>(w) * static_cast<size_t>(h)) {}
    uint8_t* at(int x, int y) { return &rgb[3 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x))]; }
    const uint8_t* at(int x, int y) const {
        return &rgb[3 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x))];
    }
};

/// The course's conversion of a channel to 8 bits: clamp to [0, 1], then truncate c·255
/// (not round). NaN becomes 0, so no image ever holds a value from a NaN.
inline uint8_t to_byte(float c) {
    if (!(c > 0)) return 0;  // also NaN
    if (c >= 1) return 255;
    return static_cast<uint8_t>(c * 255.0f);
}

/// Writes a pixel's three channels, each with to_byte.
inline void to_bytes(Vec3f color, uint8_t* rgb) {
    rgb[0] = to_byte(color.x);
    rgb[1] = to_byte(color.y);
    rgb[2] = to_byte(color.z);
}

/// to_bytes for `count` pixels in a row, byte for byte the same, in SIMD: the clamp and the
/// conversion are two loops the compiler vectorises (in one, it would convert only where the
/// clamp left a value inside (0, 1), a conversion it cannot make SIMD since it might trap).
void to_bytes(const Vec3f* colors, size_t count, uint8_t* rgb);

/// Converts every pixel with to_byte.
ImageRgb8 quantize(const Image& image);

}  // namespace raycast
