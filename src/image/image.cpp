#include "image/image.h"

namespace raycast {

ImageRgb8 quantize(const Image& image) {
    ImageRgb8 out(image.width, image.height);
    for (size_t i = 0; i < image.pixels.size(); ++i) to_bytes(image.pixels[i], &out.rgb[3 * i]);
    return out;
}

}  // namespace raycast
