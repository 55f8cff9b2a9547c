// Fuzz target: decode_image on arbitrary bytes, as BMP, PPM, TGA and PNG in turn (each decoder
// rejects the others' files after a few bytes, so one input exercises all four). An InputError is
// an expected outcome; anything else is a finding: a crash, a sanitizer report, a hang, another
// exception, or a broken promise of image_io.h that this target checks:
//  - decode_image "never reads outside `bytes`": the vector holds exactly the fuzzer's bytes;
//  - a decoded image has 1..kMaxImageSide pixels a side, at most kMaxImagePixels, 3 bytes each;
//  - encoding is lossless: a decoded image (up to 2^16 pixels, to keep runs fast) encoded in
//    every format this build writes decodes to the same pixels.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/limits.h"
#include "image/image_io.h"

namespace {

using namespace raycast;

[[noreturn]] void finding(const char* what, const std::string& detail = "") {
    std::fprintf(stderr, "fuzz_image_decode: FINDING: %s%s%s\n", what, detail.empty() ? "" : ": ", detail.c_str());
    std::abort();
}

const ImageFormat kFormats[] = {ImageFormat::Bmp, ImageFormat::Ppm, ImageFormat::Tga, ImageFormat::Png};
const char* const kNames[] = {"fuzz.bmp", "fuzz.ppm", "fuzz.tga", "fuzz.png"};

void check_round_trips(const ImageRgb8& image, const char* decoded_as) {
    for (int f = 0; f < 4; ++f) {
        if (kFormats[f] == ImageFormat::Png && !png_supported()) continue;
        const std::vector<uint8_t> bytes = encode_image(image, kFormats[f]);
        ImageRgb8 back;
        try {
            back = decode_image(bytes, kFormats[f], kNames[f]);
        } catch (const InputError& error) {
            finding("an encoded image does not decode",
                    std::string(decoded_as) + " re-encoded as " + kNames[f] + ": " + error.what());
        }
        if (back.width != image.width || back.height != image.height || back.rgb != image.rgb)
            finding("an encoded image decodes to other pixels", std::string(decoded_as) + " re-encoded as " + kNames[f]);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // Exactly the fuzzer's bytes: no slack after them for a decoder to read unnoticed.
    const std::vector<uint8_t> bytes(data, data + size);
    for (int f = 0; f < 4; ++f) {
        ImageRgb8 image;
        try {
            image = decode_image(bytes, kFormats[f], kNames[f]);
        } catch (const InputError& error) {
            if (error.diagnostics().empty()) finding("InputError without diagnostics");
            continue;
        }
        if (image.width < 1 || image.height < 1 || image.width > kMaxImageSide || image.height > kMaxImageSide ||
            int64_t{image.width} * image.height > kMaxImagePixels)
            finding("decoded image size out of the limits",
                    std::to_string(image.width) + "x" + std::to_string(image.height));
        if (image.rgb.size() != 3 * size_t(image.width) * size_t(image.height)) finding("pixel bytes do not match the size");
        if (int64_t{image.width} * image.height <= (int64_t{1} << 16)) check_round_trips(image, kNames[f]);
    }
    return 0;
}
