#include "image/image.h"

namespace raycast {

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
