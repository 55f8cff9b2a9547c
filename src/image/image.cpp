#include "image/image.h"

namespace raycast {

uint8_t to_byte(float c) {
    if (!(c > 0)) return 0;  // also NaN
    if (c >= 1) return 255;
    return static_cast<uint8_t>(c * 255.0f);
}

ImageRgb8 quantize(const Image& image) {
    ImageRgb8 out(image.width, image.height);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
        out.rgb[3 * i + 0] = to_byte(image.pixels[i].x);
        out.rgb[3 * i + 1] = to_byte(image.pixels[i].y);
        out.rgb[3 * i + 2] = to_byte(image.pixels[i].z);
    }
    return out;
}

}  // namespace raycast
