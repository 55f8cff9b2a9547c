#include "image/image.h"

#include <algorithm>

#include "base/simd_clones.h"

namespace raycast {

static_assert(sizeof(Vec3f) == 3 * sizeof(float), "an array of Vec3f is flat float data");

RAYCAST_SIMD_CLONES
void to_bytes(const Vec3f* colors, size_t count, uint8_t* rgb) {
    if (count == 0) return;
    const float* channel = &colors[0].x;
    constexpr size_t kChunk = 48;  // channels: a 16-pixel row of a tile
    for (size_t first = 0; first < 3 * count; first += kChunk) {
        const size_t n = std::min(kChunk, 3 * count - first);
        float clamped[kChunk];
        for (size_t i = 0; i < n; ++i) {  // to_byte's clamp: NaN and c <= 0 to 0, c >= 1 to 1
            const float c = channel[first + i];
            const float low = c > 0 ? c : 0.0f;
            clamped[i] = low < 1 ? low : 1.0f;
        }
        // 1 becomes 255 and 0 becomes 0, as to_byte returns them; the rest truncates alike.
        for (size_t i = 0; i < n; ++i) rgb[first + i] = static_cast<uint8_t>(static_cast<int>(clamped[i] * 255.0f));
    }
}

ImageRgb8 quantize(const Image& image) {
    ImageRgb8 out(image.width, image.height);
    to_bytes(image.pixels.data(), image.pixels.size(), out.rgb.data());
    return out;
}

}  // namespace raycast
