#include "image/image_io.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/write_file.h"

namespace raycast {
namespace {

// ---- helpers ----

std::vector<uint8_t> bytes_of(const std::string& text) { return std::vector<uint8_t>(text.begin(), text.end()); }

std::vector<uint8_t> concat(std::vector<uint8_t> a, const std::vector<uint8_t>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// The 3x2 image used for byte-level checks: pixel (x, y) = (1 + 3i, 2 + 3i, 3 + 3i) with i = 3y + x, so
// the bottom row (y = 0) holds 1..9 and the top row 10..18.
ImageRgb8 small_image() {
    ImageRgb8 image(3, 2);
    for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<uint8_t>(i + 1);
    return image;
}

// Pixels that differ everywhere, so a flipped row or swapped channel cannot round-trip unnoticed.
ImageRgb8 pattern_image(int width, int height, uint32_t seed) {
    ImageRgb8 image(width, height);
    std::mt19937 random(seed);
    for (uint8_t& value : image.rgb) value = static_cast<uint8_t>(random() & 0xff);
    return image;
}

void expect_pixel(const ImageRgb8& image, int x, int y, int r, int g, int b) {
    const uint8_t* p = image.at(x, y);
    EXPECT_EQ(int{p[0]}, r) << "red at (" << x << ", " << y << ")";
    EXPECT_EQ(int{p[1]}, g) << "green at (" << x << ", " << y << ")";
    EXPECT_EQ(int{p[2]}, b) << "blue at (" << x << ", " << y << ")";
}

// The message of the InputError that `action` throws; checks that it names `file`.
std::string input_error(const std::function<void()>& action, const std::string& file) {
    try {
        action();
    } catch (const InputError& error) {
        EXPECT_EQ(error.diagnostics().size(), 1u);
        if (error.diagnostics().empty()) return "";
        EXPECT_EQ(error.diagnostics()[0].location.file, file);
        return error.diagnostics()[0].message;
    }
    ADD_FAILURE() << "no InputError was thrown";
    return "";
}

std::string decode_error(const std::vector<uint8_t>& bytes, ImageFormat format) {
    return input_error([&] { decode_image(bytes, format, "input"); }, "input");
}

const char* const kPngUnsupportedMessage =
    "PNG images need libpng: rebuild raycast with libpng-dev installed, or use .bmp, .ppm or .tga";

// A BMP header written out field by field, for hand-made files.
std::vector<uint8_t> bmp_header(int32_t width, int32_t height, uint16_t bits, uint32_t compression,
                                uint32_t pixel_bytes) {
    std::vector<uint8_t> out = {'B', 'M'};
    auto u16 = [&out](uint32_t v) {
        out.push_back(static_cast<uint8_t>(v & 0xff));
        out.push_back(static_cast<uint8_t>(v >> 8 & 0xff));
    };
    auto u32 = [&](uint32_t v) {
        u16(v & 0xffff);
        u16(v >> 16);
    };
    u32(54 + pixel_bytes);
    u32(0);
    u32(54);
    u32(40);
    u32(static_cast<uint32_t>(width));
    u32(static_cast<uint32_t>(height));
    u16(1);
    u16(bits);
    u32(compression);
    u32(pixel_bytes);
    for (int i = 0; i < 4; ++i) u32(0);
    return out;
}

std::vector<uint8_t> tga_header(uint8_t type, uint16_t width, uint16_t height, uint8_t bits, uint8_t descriptor) {
    return {0,
            0,
            type,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
            0,
            static_cast<uint8_t>(width & 0xff),
            static_cast<uint8_t>(width >> 8),
            static_cast<uint8_t>(height & 0xff),
            static_cast<uint8_t>(height >> 8),
            bits,
            descriptor};
}

// PNG files made by hand (chunks written out, zlib-compressed rows); the comment above each says what
// its pixels are, top row first as PNG stores them.

// 3x2, gray, 1 bit: top row 1 0 1, bottom row 0 1 1.
const std::vector<uint8_t> kPngGray1Bit3x2 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x03, 0x00, 0x00, 0x00, 0x02, 0x01, 0x00, 0x00, 0x00, 0x00, 0xb5, 0x0f, 0x5b, 0xb7, 0x00, 0x00, 0x00,
    0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x58, 0xc0, 0x90, 0x00, 0x00, 0x02, 0x44, 0x01, 0x01, 0x50,
    0xb8, 0x20, 0x6c, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 2x2, palette 0 = (10, 20, 30), 1 = (200, 100, 50), 2 = (0, 255, 0), tRNS alphas 0 and 128:
// top row 0 1, bottom row 2 0.
const std::vector<uint8_t> kPngPalette2x2 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x03, 0x00, 0x00, 0x00, 0x45, 0x68, 0xfd, 0x16, 0x00, 0x00, 0x00,
    0x09, 0x50, 0x4c, 0x54, 0x45, 0x0a, 0x14, 0x1e, 0xc8, 0x64, 0x32, 0x00, 0xff, 0x00, 0x81, 0x52, 0x3b, 0x10,
    0x00, 0x00, 0x00, 0x02, 0x74, 0x52, 0x4e, 0x53, 0x00, 0x80, 0x9b, 0x2b, 0x4e, 0x18, 0x00, 0x00, 0x00, 0x0e,
    0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x60, 0x64, 0x60, 0x62, 0x00, 0x00, 0x00, 0x0e, 0x00, 0x04,
    0xdb, 0xe0, 0x32, 0x8e, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 2x1, RGB, 16 bits: (0x0000, 0x0101, 0xffff), (0x8080, 0x7fff, 0x8000).
const std::vector<uint8_t> kPngRgb16Bit2x1 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x10, 0x02, 0x00, 0x00, 0x00, 0x2b, 0xd0, 0x34,
    0x9e, 0x00, 0x00, 0x00, 0x15, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x60, 0x60, 0x64,
    0xfc, 0xff, 0xbf, 0xa1, 0xa1, 0xfe, 0x7f, 0x03, 0x03, 0x00, 0x1a, 0x8a, 0x04, 0xff, 0x74, 0x4f,
    0x3e, 0xe4, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 1x2, gray + alpha, 8 bits: top (200, alpha 0), bottom (7, alpha 255).
const std::vector<uint8_t> kPngGrayAlpha1x2 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x08, 0x04, 0x00, 0x00, 0x00, 0x33, 0x88, 0x7e, 0xac, 0x00, 0x00, 0x00,
    0x0e, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x38, 0xc1, 0xc0, 0xc0, 0xfe, 0x1f, 0x00, 0x04, 0xfb, 0x01,
    0xcf, 0xbf, 0x2a, 0xfb, 0x7f, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 3x3, RGBA, 8 bits, Adam7 interlaced: column c of row r (from the top) is
// (10c + r, 100 + r, 200 + c, alpha 255 - c).
const std::vector<uint8_t> kPngRgbaInterlaced3x3 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x08, 0x06, 0x00, 0x00, 0x01, 0x21, 0x2f, 0x85, 0x29, 0x00, 0x00, 0x00,
    0x31, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x48, 0x39, 0xf1, 0x9f, 0x41, 0x24, 0xe5, 0xd4, 0x5f,
    0x06, 0xa6, 0xb4, 0x13, 0xff, 0xc5, 0xd2, 0x80, 0x0c, 0xae, 0x94, 0x93, 0xff, 0x18, 0x78, 0xd2, 0x80, 0x04,
    0x63, 0xea, 0x89, 0xff, 0xdc, 0xa9, 0x27, 0xff, 0x89, 0xa6, 0x9e, 0xfa, 0x0b, 0x00, 0x89, 0x70, 0x13, 0xf0,
    0x5f, 0xa5, 0x02, 0x69, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 16385x1, gray, 8 bits, with a valid IHDR: one pixel too wide.
const std::vector<uint8_t> kPngTooWide = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
    0x00, 0x40, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0xec, 0x36, 0x82, 0xba, 0x00,
    0x00, 0x00, 0x0a, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x00, 0x00, 0x00, 0x02, 0x00, 0x01,
    0xe5, 0x27, 0xde, 0xfc, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// 68 bytes whose header promises an 8000x8000 RGB image, with 16 bytes of it deflated: deflate
// packs at most 1032 bytes into one, so no file this small can hold the image.
const std::vector<uint8_t> kPngPromisesTooMuch = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
    0x52, 0x00, 0x00, 0x1f, 0x40, 0x00, 0x00, 0x1f, 0x40, 0x08, 0x02, 0x00, 0x00, 0x00, 0x89,
    0x93, 0x3a, 0xa3, 0x00, 0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60,
    0x40, 0x05, 0x00, 0x00, 0x10, 0x00, 0x01, 0x39, 0xbd, 0x8f, 0x65, 0x00, 0x00, 0x00, 0x00,
    0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
};

// A fresh directory per test, removed afterwards.
class ImageFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        std::string pattern = ::testing::TempDir() + "raycast_image_io_XXXXXX";
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    std::string path(const std::string& name) const { return dir_ + "/" + name; }

    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& entry : std::filesystem::directory_iterator(dir_))
            names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    static std::vector<uint8_t> read_bytes(const std::string& file) {
        std::ifstream in(file, std::ios::binary);
        return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }

    static void write_bytes(const std::string& file, const std::vector<uint8_t>& bytes) {
        std::ofstream out(file, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }

    std::string dir_;
};

// ---- formats by name ----

// The course's conversion: clamp to [0, 1], then truncate c·255; NaN is 0.
TEST(ToByte, ClampsThenTruncates) {
    EXPECT_EQ(to_byte(0.0f), 0);
    EXPECT_EQ(to_byte(-0.0f), 0);
    EXPECT_EQ(to_byte(-2.0f), 0);
    EXPECT_EQ(to_byte(-INFINITY), 0);
    EXPECT_EQ(to_byte(NAN), 0);
    EXPECT_EQ(to_byte(1e-30f), 0);
    EXPECT_EQ(to_byte(0.5f), 127);      // 127.5, truncated
    EXPECT_EQ(to_byte(0.999f), 254);    // 254.745
    EXPECT_EQ(to_byte(0.99999994f), 254);  // the float below 1: 254.99998
    EXPECT_EQ(to_byte(1.0f), 255);
    EXPECT_EQ(to_byte(1.5f), 255);
    EXPECT_EQ(to_byte(INFINITY), 255);
    EXPECT_EQ(to_byte(3.0f / 255.0f), 3);  // times 255 is 3 exactly: truncation keeps it
    uint8_t rgb[3];
    to_bytes({0.5f, NAN, 2.0f}, rgb);
    EXPECT_EQ(rgb[0], 127);
    EXPECT_EQ(rgb[1], 0);
    EXPECT_EQ(rgb[2], 255);
}

// The row conversion (SIMD) gives to_byte's byte for every float: the special values, then
// about a million bit patterns spread over all of them (both signs, NaNs, infinities, denormals).
TEST(ToByte, ARowConvertsEveryFloatAsToByteDoes) {
    std::vector<float> values = {0.0f, -0.0f, 1e-45f, 1e-30f, 0.5f, 0.99999994f, 1.0f, 1.0000001f, 255.0f,
                                 INFINITY, -INFINITY, NAN, -NAN, 3.0f / 255.0f, -1.0f};
    for (uint64_t bits = 0; bits <= 0xffffffffu; bits += 4099) {
        const uint32_t pattern = static_cast<uint32_t>(bits);
        float value;
        std::memcpy(&value, &pattern, sizeof value);
        values.push_back(value);
    }
    while (values.size() % 3 != 0) values.push_back(0.25f);
    std::vector<Vec3f> colors(values.size() / 3);
    for (size_t i = 0; i < colors.size(); ++i) colors[i] = {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
    std::vector<uint8_t> rgb(values.size(), 77);
    to_bytes(colors.data(), colors.size(), rgb.data());
    int mismatches = 0;
    for (size_t i = 0; i < values.size(); ++i)
        if (rgb[i] != to_byte(values[i])) ++mismatches;
    EXPECT_EQ(mismatches, 0);
    std::fill(rgb.begin(), rgb.end(), 77);
    to_bytes(colors.data(), 0, rgb.data());  // nothing to convert, nothing written
    EXPECT_EQ(std::count(rgb.begin(), rgb.end(), 77), static_cast<std::ptrdiff_t>(rgb.size()));
}

TEST(ImageFormatForPath, KnownExtensionsInAnyCase) {
    EXPECT_EQ(image_format_for_path("out.bmp"), ImageFormat::Bmp);
    EXPECT_EQ(image_format_for_path("OUT.BMP"), ImageFormat::Bmp);
    EXPECT_EQ(image_format_for_path("dir/a.Ppm"), ImageFormat::Ppm);
    EXPECT_EQ(image_format_for_path("/tmp/x.y/scene.tga"), ImageFormat::Tga);
    EXPECT_EQ(image_format_for_path("render.PNG"), ImageFormat::Png);
}

TEST(ImageFormatForPath, OtherNamesHaveNone) {
    EXPECT_EQ(image_format_for_path("photo.jpg"), std::nullopt);
    EXPECT_EQ(image_format_for_path("image"), std::nullopt);
    EXPECT_EQ(image_format_for_path("dir.bmp/image"), std::nullopt);
    EXPECT_EQ(image_format_for_path("image.bmp.gz"), std::nullopt);
    EXPECT_EQ(image_format_for_path("image."), std::nullopt);
    EXPECT_EQ(image_format_for_path(""), std::nullopt);
}

TEST(ImageFormatNamed, TheFourNamesInAnyCaseAndNothingElse) {
    EXPECT_EQ(image_format_named("bmp"), ImageFormat::Bmp);
    EXPECT_EQ(image_format_named("PPM"), ImageFormat::Ppm);
    EXPECT_EQ(image_format_named("Tga"), ImageFormat::Tga);
    EXPECT_EQ(image_format_named("png"), ImageFormat::Png);
    EXPECT_EQ(image_format_named(".ppm"), std::nullopt);  // a name, not an extension
    EXPECT_EQ(image_format_named("jpg"), std::nullopt);
    EXPECT_EQ(image_format_named("ppm "), std::nullopt);
    EXPECT_EQ(image_format_named(""), std::nullopt);
}

// ---- encoding, byte by byte ----

TEST(BmpEncode, Header200x200IsTheCourses) {
    const std::vector<uint8_t> bytes = encode_image(ImageRgb8(200, 200), ImageFormat::Bmp);
    // The first 54 bytes of a 200x200 BMP written by the course's SaveBMP: file size 120054 = 0x1d4f6, pixel
    // offset 54, info header 40, 200 = 0xc8 by 200, 1 plane, 24 bits, BI_RGB, image size 120000 = 0x1d4c0,
    // then zero resolution and no palette.
    // clang-format off
    const std::vector<uint8_t> expected = {
        0x42, 0x4d, 0xf6, 0xd4, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x36, 0x00, 0x00, 0x00,  // BITMAPFILEHEADER
        0x28, 0x00, 0x00, 0x00, 0xc8, 0x00, 0x00, 0x00, 0xc8, 0x00, 0x00, 0x00, 0x01, 0x00, 0x18, 0x00,
        0x00, 0x00, 0x00, 0x00, 0xc0, 0xd4, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
    // clang-format on
    ASSERT_EQ(bytes.size(), 120054u);
    EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 54), expected);
}

TEST(BmpEncode, RowsArePaddedWithZerosBottomRowFirst) {
    // Width 3 gives 9 bytes of pixels and a stride of 12, so 54 + 2 * 12 = 78 bytes.
    // clang-format off
    const std::vector<uint8_t> expected = {
        0x42, 0x4d, 78, 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0,                     // file header
        40,   0,    0,  0, 3, 0, 0, 0, 2, 0, 0,  0, 1, 0, 24, 0,  0, 0, 0, 0,  // size, 3 x 2, planes, bits, BI_RGB
        24,   0,    0,  0, 0, 0, 0, 0, 0, 0, 0,  0, 0, 0, 0,  0,  0, 0, 0, 0,  // image size 24, zeros
        3,    2,    1,  6, 5, 4, 9, 8, 7, 0, 0,  0,                           // y = 0, B G R, then padding
        12,   11,   10, 15, 14, 13, 18, 17, 16, 0, 0, 0};                     // y = 1
    // clang-format on
    EXPECT_EQ(encode_image(small_image(), ImageFormat::Bmp), expected);
}

TEST(PpmEncode, TopRowFirst) {
    const std::vector<uint8_t> expected =
        concat(bytes_of("P6\n3 2\n255\n"), {10, 11, 12, 13, 14, 15, 16, 17, 18, 1, 2, 3, 4, 5, 6, 7, 8, 9});
    EXPECT_EQ(encode_image(small_image(), ImageFormat::Ppm), expected);
}

TEST(TgaEncode, UncompressedBottomLeftOriginBgr) {
    // clang-format off
    const std::vector<uint8_t> expected = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 2, 0, 24, 0,  // 18-byte header
                                           3, 2, 1, 6, 5, 4, 9, 8, 7,  // y = 0: (0, 0) comes first
                                           12, 11, 10, 15, 14, 13, 18, 17, 16};
    // clang-format on
    EXPECT_EQ(encode_image(small_image(), ImageFormat::Tga), expected);
}

TEST(PngEncode, EightBitRgbHeader) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const std::vector<uint8_t> bytes = encode_image(small_image(), ImageFormat::Png);
    // Signature, then IHDR: length 13, "IHDR", width 3, height 2, depth 8, colour type 2 (RGB), no interlace.
    // clang-format off
    const std::vector<uint8_t> expected = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                           0,    0,   0,   3,   0,    0,    0,    2,    8, 2, 0, 0,  0};
    // clang-format on
    ASSERT_GE(bytes.size(), expected.size());
    EXPECT_EQ(std::vector<uint8_t>(bytes.begin(), bytes.begin() + static_cast<long>(expected.size())), expected);
    // The decoder reads hand-made PNGs top row first (PngDecode tests), so this pins the writer's row order.
    const ImageRgb8 decoded = decode_image(bytes, ImageFormat::Png, "x.png");
    expect_pixel(decoded, 0, 0, 1, 2, 3);
    expect_pixel(decoded, 2, 1, 16, 17, 18);
}

TEST(EncodeImage, RejectsInconsistentImages) {
    ImageRgb8 short_buffer(2, 2);
    short_buffer.rgb.pop_back();
    EXPECT_THROW(encode_image(short_buffer, ImageFormat::Bmp), std::invalid_argument);
    EXPECT_THROW(encode_image(ImageRgb8(), ImageFormat::Ppm), std::invalid_argument);
    EXPECT_THROW(encode_image(ImageRgb8(kMaxImageSide + 1, 1), ImageFormat::Tga), std::invalid_argument);
}

// ---- round trips ----

TEST(RoundTrip, EveryFormatAndSize) {
    const int sizes[][2] = {{1, 1}, {3, 2}, {2, 3}, {5, 3}, {17, 9}, {64, 1}, {1, 64}};
    for (ImageFormat format : {ImageFormat::Bmp, ImageFormat::Ppm, ImageFormat::Tga, ImageFormat::Png}) {
        if (format == ImageFormat::Png && !png_supported()) continue;
        for (const auto& size : sizes) {
            SCOPED_TRACE(testing::Message()
                         << "format " << static_cast<int>(format) << ", " << size[0] << "x" << size[1]);
            const ImageRgb8 image = pattern_image(size[0], size[1], static_cast<uint32_t>(size[0] * 100 + size[1]));
            const ImageRgb8 decoded = decode_image(encode_image(image, format), format, "memory");
            EXPECT_EQ(decoded.width, image.width);
            EXPECT_EQ(decoded.height, image.height);
            EXPECT_EQ(decoded.rgb, image.rgb);
        }
    }
}

TEST_F(ImageFileTest, WriteThenReadEveryExtension) {
    const ImageRgb8 image = pattern_image(7, 5, 42);
    for (const char* name : {"a.bmp", "b.ppm", "c.tga", "d.png", "E.BMP"}) {
        SCOPED_TRACE(name);
        if (image_format_for_path(name) == ImageFormat::Png && !png_supported()) continue;
        write_image(path(name), image);
        const ImageRgb8 read = read_image(path(name));
        EXPECT_EQ(read.width, 7);
        EXPECT_EQ(read.height, 5);
        EXPECT_EQ(read.rgb, image.rgb);
    }
}

TEST_F(ImageFileTest, ReadsBySignatureWhateverTheName) {
    const ImageRgb8 image = pattern_image(4, 3, 7);
    write_bytes(path("bmp.dat"), encode_image(image, ImageFormat::Bmp));
    write_bytes(path("bmp.tga"), encode_image(image, ImageFormat::Bmp));
    write_bytes(path("ppm"), encode_image(image, ImageFormat::Ppm));
    write_bytes(path("tga.TGA"), encode_image(image, ImageFormat::Tga));
    for (const char* name : {"bmp.dat", "bmp.tga", "ppm", "tga.TGA"}) {
        SCOPED_TRACE(name);
        EXPECT_EQ(read_image(path(name)).rgb, image.rgb);
    }
    if (png_supported()) {
        write_bytes(path("png.bmp"), encode_image(image, ImageFormat::Png));
        EXPECT_EQ(read_image(path("png.bmp")).rgb, image.rgb);
    }
}

// ---- BMP decoding ----

TEST(BmpDecode, ReadsTheCourseLayout) {
    // clang-format off
    const std::vector<uint8_t> bytes = concat(bmp_header(3, 2, 24, 0, 24), {
        3,  2,  1,  6,  5,  4,  9,  8,  7,  0, 0, 0,   // y = 0
        12, 11, 10, 15, 14, 13, 18, 17, 16, 0, 0, 0}); // y = 1
    // clang-format on
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Bmp, "in.bmp");
    EXPECT_EQ(image.width, 3);
    EXPECT_EQ(image.height, 2);
    EXPECT_EQ(image.rgb, small_image().rgb);
}

TEST(BmpDecode, TopDownRowsWithNegativeHeight) {
    // Height -2: the first stored row is the top one, y = 1.
    const std::vector<uint8_t> bytes = concat(bmp_header(1, -2, 24, 0, 8), {30, 20, 10, 0, 60, 50, 40, 0});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Bmp, "in.bmp");
    ASSERT_EQ(image.height, 2);
    expect_pixel(image, 0, 1, 10, 20, 30);
    expect_pixel(image, 0, 0, 40, 50, 60);
}

TEST(BmpDecode, ThirtyTwoBitsPerPixelDropAlpha) {
    // BGRA, 4 bytes a pixel, so rows need no padding.
    const std::vector<uint8_t> bytes = concat(bmp_header(2, 1, 32, 0, 8), {3, 2, 1, 255, 6, 5, 4, 0});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Bmp, "in.bmp");
    ASSERT_EQ(image.width, 2);
    expect_pixel(image, 0, 0, 1, 2, 3);
    expect_pixel(image, 1, 0, 4, 5, 6);
}

TEST(BmpDecode, ThirtyTwoBitsWithStandardBitfields) {
    // BI_BITFIELDS (3) with masks R 0x00ff0000, G 0x0000ff00, B 0x000000ff after the header; pixels at 66.
    std::vector<uint8_t> bytes = bmp_header(1, 1, 32, 3, 4);
    bytes[10] = 66;
    bytes = concat(bytes, {0, 0, 0xff, 0, 0, 0xff, 0, 0, 0xff, 0, 0, 0, 9, 8, 7, 0});
    expect_pixel(decode_image(bytes, ImageFormat::Bmp, "in.bmp"), 0, 0, 7, 8, 9);
    bytes[54] = 0xff;  // a red mask of 0x00ff00ff
    EXPECT_EQ(decode_error(bytes, ImageFormat::Bmp),
              "unsupported BMP file: colour masks other than 8-bit R, G, B (raycast reads only those)");
}

TEST(BmpDecode, ToleratesAMissingLastPadding) {
    std::vector<uint8_t> bytes = encode_image(small_image(), ImageFormat::Bmp);
    bytes.resize(bytes.size() - 3);
    EXPECT_EQ(decode_image(bytes, ImageFormat::Bmp, "in.bmp").rgb, small_image().rgb);
}

TEST(BmpDecode, Errors) {
    const std::vector<uint8_t> good = encode_image(small_image(), ImageFormat::Bmp);
    EXPECT_EQ(decode_error({}, ImageFormat::Bmp), "not a BMP file: it does not start with 'BM'");
    EXPECT_EQ(decode_error(bytes_of("P6 1 1 255\n"), ImageFormat::Bmp), "not a BMP file: it does not start with 'BM'");
    EXPECT_EQ(decode_error(std::vector<uint8_t>(good.begin(), good.begin() + 10), ImageFormat::Bmp),
              "truncated BMP file: the header needs 54 bytes, the file has 10");
    EXPECT_EQ(decode_error(std::vector<uint8_t>(good.begin(), good.begin() + 30), ImageFormat::Bmp),
              "truncated BMP file: the header needs 54 bytes, the file has 30");
    // 78 bytes less 4: the pixels need 12 + 9 = 21 bytes after offset 54, and 20 are there.
    EXPECT_EQ(decode_error(std::vector<uint8_t>(good.begin(), good.end() - 4), ImageFormat::Bmp),
              "truncated BMP file: the pixels need 21 bytes but only 20 are there");

    std::vector<uint8_t> core = good;
    core[14] = 12;  // OS/2 BITMAPCOREHEADER
    EXPECT_EQ(decode_error(core, ImageFormat::Bmp),
              "unsupported BMP file: a 12-byte info header (raycast reads headers of 40 bytes or more)");
    EXPECT_EQ(decode_error(concat(bmp_header(3, 2, 8, 0, 8), std::vector<uint8_t>(1024 + 8)), ImageFormat::Bmp),
              "unsupported BMP file: 8 bits per pixel (raycast reads 24 and 32)");
    EXPECT_EQ(decode_error(concat(bmp_header(3, 2, 24, 1, 24), std::vector<uint8_t>(24)), ImageFormat::Bmp),
              "unsupported BMP file: compression type 1 (raycast reads only uncompressed BMP)");
    EXPECT_EQ(decode_error(concat(bmp_header(0, 2, 24, 0, 0), {}), ImageFormat::Bmp),
              "bad image size 0x2: width and height must be at least 1");
    EXPECT_EQ(decode_error(bmp_header(-3, 2, 24, 0, 24), ImageFormat::Bmp),
              "bad image size -3x2: width and height must be at least 1");
    EXPECT_EQ(decode_error(bmp_header(16385, 2, 24, 0, 0), ImageFormat::Bmp),
              "image too large: 16385x2 is more than raycast's limit of 16384 a side and 67108864 pixels");
    EXPECT_EQ(decode_error(bmp_header(8193, -8193, 24, 0, 0), ImageFormat::Bmp),
              "image too large: 8193x8193 is more than raycast's limit of 16384 a side and 67108864 pixels");
    EXPECT_EQ(decode_error(bmp_header(1, INT32_MIN, 24, 0, 0), ImageFormat::Bmp),
              "image too large: 1x2147483648 is more than raycast's limit of 16384 a side and 67108864 pixels");
    // A pixel offset past the end of the file.
    std::vector<uint8_t> far = good;
    far[13] = 0x7f;
    EXPECT_EQ(decode_error(far, ImageFormat::Bmp), "truncated BMP file: the pixels need 21 bytes but only 0 are there");
}

// ---- PPM decoding ----

TEST(PpmDecode, BinaryWithComments) {
    const std::vector<uint8_t> bytes =
        concat(bytes_of("P6 # made by hand\n2 # width\r\n# a whole comment line\n2\n255\n"),
               {1, 2, 3, 4, 5, 6, /* bottom row: */ 7, 8, 9, 10, 11, 12});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Ppm, "in.ppm");
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    expect_pixel(image, 0, 1, 1, 2, 3);  // the first pixel in the file is the top-left one
    expect_pixel(image, 1, 1, 4, 5, 6);
    expect_pixel(image, 0, 0, 7, 8, 9);
    expect_pixel(image, 1, 0, 10, 11, 12);
}

TEST(PpmDecode, TextWithComments) {
    const std::string text = "P3\n# made by hand\n2 2 # size\n255\n0 128 255  10 20 30 # top row\n1 2 3\n4 5 6\n";
    const ImageRgb8 image = decode_image(bytes_of(text), ImageFormat::Ppm, "in.ppm");
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    expect_pixel(image, 0, 1, 0, 128, 255);
    expect_pixel(image, 1, 1, 10, 20, 30);
    expect_pixel(image, 0, 0, 1, 2, 3);
    expect_pixel(image, 1, 0, 4, 5, 6);
}

TEST(PpmDecode, SixteenBitSamplesScaleTo8Bits) {
    // Big-endian samples; v·255/65535 rounded: 257 -> 1, 0x7fff -> 127.498 -> 127, 0x8080 -> 128 exactly,
    // 0x8000 -> 128.002 -> 128.
    const std::vector<uint8_t> bytes =
        concat(bytes_of("P6\n2 1\n65535\n"), {0x00, 0x00, 0x01, 0x01, 0xff, 0xff, 0x80, 0x80, 0x7f, 0xff, 0x80, 0x00});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Ppm, "in.ppm");
    expect_pixel(image, 0, 0, 0, 1, 255);
    expect_pixel(image, 1, 0, 128, 127, 128);
    const ImageRgb8 text = decode_image(bytes_of("P3 1 1 65535 257 32767 65535"), ImageFormat::Ppm, "in.ppm");
    expect_pixel(text, 0, 0, 1, 127, 255);
}

TEST(PpmDecode, SmallMaximumValuesRoundToNearest) {
    // maxval 2: 1 -> 127.5, rounded up to 128. maxval 15: 7 -> 119, 8 -> 136.
    expect_pixel(decode_image(bytes_of("P3 1 1 2 0 1 2"), ImageFormat::Ppm, "in.ppm"), 0, 0, 0, 128, 255);
    expect_pixel(decode_image(bytes_of("P3 1 1 15 7 8 15"), ImageFormat::Ppm, "in.ppm"), 0, 0, 119, 136, 255);
    expect_pixel(decode_image(concat(bytes_of("P6 1 1 15\n"), {7, 8, 15}), ImageFormat::Ppm, "in.ppm"), 0, 0, 119, 136,
                 255);
}

TEST(PpmDecode, MaximumValue255IsExact) {
    std::vector<uint8_t> bytes = bytes_of("P6\n256 1\n255\n");
    for (int v = 0; v < 256; ++v) bytes.insert(bytes.end(), {uint8_t(v), uint8_t(255 - v), uint8_t(v)});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Ppm, "in.ppm");
    for (int v = 0; v < 256; ++v) expect_pixel(image, v, 0, v, 255 - v, v);
}

TEST(PpmDecode, Errors) {
    auto ppm_error = [](const std::string& text) { return decode_error(bytes_of(text), ImageFormat::Ppm); };
    EXPECT_EQ(ppm_error(""), "not a PPM file: it does not start with P6 or P3");
    EXPECT_EQ(ppm_error("P5 1 1 255\n\x01"), "not a PPM file: it does not start with P6 or P3");
    EXPECT_EQ(ppm_error("P65 1 255\n\x01\x02\x03"), "not a PPM file: it does not start with P6 or P3");
    EXPECT_EQ(ppm_error("P6"), "truncated PPM file: the header ends before the width");
    EXPECT_EQ(ppm_error("P6 3 "), "truncated PPM file: the header ends before the height");
    EXPECT_EQ(ppm_error("P6 3 2 # no maximum value\n"), "truncated PPM file: the header ends before the maximum value");
    EXPECT_EQ(ppm_error("P6 -3 2 255\n"), "bad PPM file: the width is not a number");
    EXPECT_EQ(ppm_error("P3 3 x 255\n"), "bad PPM file: the height is not a number");
    EXPECT_EQ(ppm_error("P6 1 1 0\n"), "bad PPM file: the maximum value 0 is not in 1..65535");
    EXPECT_EQ(ppm_error("P6 1 1 65536\n"), "bad PPM file: the maximum value 65536 is not in 1..65535");
    EXPECT_EQ(ppm_error("P6 1 1 255x\x01\x02\x03"), "bad PPM file: no whitespace after the maximum value");
    EXPECT_EQ(ppm_error("P6 2 1 255\n\x01\x02\x03\x04\x05"),
              "truncated PPM file: the pixels need 6 bytes but only 5 are there");
    EXPECT_EQ(ppm_error("P6 2 1 255"), "truncated PPM file: the pixels need 6 bytes but only 0 are there");
    EXPECT_EQ(ppm_error("P6 2 1 65535\n\x01\x02\x03\x04\x05\x06"),
              "truncated PPM file: the pixels need 12 bytes but only 6 are there");
    EXPECT_EQ(ppm_error("P3 2 1 255 1 2 3 4"), "truncated PPM file: the pixels need 6 values but only 4 are there");
    EXPECT_EQ(ppm_error("P3 1 1 255 1 x 3"), "bad PPM file: a sample value is not a number");
    EXPECT_EQ(ppm_error("P3 1 1 255 1 -2 3"), "bad PPM file: a sample value is not a number");
    EXPECT_EQ(ppm_error("P3 1 1 15 1 16 3"), "bad PPM file: the sample value 16 is more than the maximum value 15");
    EXPECT_EQ(ppm_error("P6 1 1 100\n\x01\xc8\x03"),
              "bad PPM file: the sample value 200 is more than the maximum value 100");
    EXPECT_EQ(ppm_error("P3 0 0 255"), "bad image size 0x0: width and height must be at least 1");
    EXPECT_EQ(ppm_error("P6 16385 1 255\n"),
              "image too large: 16385x1 is more than raycast's limit of 16384 a side and 67108864 pixels");
    EXPECT_EQ(ppm_error("P6 16384 4097 255\n"),
              "image too large: 16384x4097 is more than raycast's limit of 16384 a side and 67108864 pixels");
    // Sizes beyond 2^31 - 1 saturate rather than overflow.
    EXPECT_EQ(ppm_error("P6 99999999999999999999 1 255\n"),
              "image too large: 2147483647x1 is more than raycast's limit of 16384 a side and 67108864 pixels");
}

// ---- TGA decoding ----

TEST(TgaDecode, UncompressedTopLeftOrigin) {
    // Descriptor 0x20: the first stored row is the top one.
    const std::vector<uint8_t> bytes =
        concat(tga_header(2, 2, 2, 24, 0x20), {3, 2, 1, 6, 5, 4, /* bottom row: */ 9, 8, 7, 12, 11, 10});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Tga, "in.tga");
    expect_pixel(image, 0, 1, 1, 2, 3);
    expect_pixel(image, 1, 1, 4, 5, 6);
    expect_pixel(image, 0, 0, 7, 8, 9);
    expect_pixel(image, 1, 0, 10, 11, 12);
}

TEST(TgaDecode, UncompressedRightToLeft) {
    // Descriptor 0x10: each row is stored from its right end.
    const std::vector<uint8_t> bytes = concat(tga_header(2, 2, 1, 24, 0x10), {3, 2, 1, 6, 5, 4});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Tga, "in.tga");
    expect_pixel(image, 1, 0, 1, 2, 3);
    expect_pixel(image, 0, 0, 4, 5, 6);
}

TEST(TgaDecode, RunLengthEncodedBottomLeft) {
    // 3x2: a run of 3 grey (0x82 = run, count 3) for y = 0, then a raw packet of 3 (0x02) for y = 1.
    const std::vector<uint8_t> bytes =
        concat(tga_header(10, 3, 2, 24, 0), {0x82, 50, 60, 70, 0x02, 3, 2, 1, 6, 5, 4, 9, 8, 7});
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Tga, "in.tga");
    for (int x = 0; x < 3; ++x) expect_pixel(image, x, 0, 70, 60, 50);
    expect_pixel(image, 0, 1, 1, 2, 3);
    expect_pixel(image, 1, 1, 4, 5, 6);
    expect_pixel(image, 2, 1, 7, 8, 9);
}

TEST(TgaDecode, RunLengthEncoded32BitTopLeftWithIdAndColourMap) {
    // An ID of 2 bytes and a 2-entry, 24-bit colour map precede the pixels; both are skipped. The raw packet
    // (count 1) and the run (count 3) cross the row boundary of this 2x2 image; alpha is dropped.
    std::vector<uint8_t> header = tga_header(10, 2, 2, 32, 0x28);
    header[0] = 2;  // ID length
    header[1] = 1;  // colour map present
    header[5] = 2;  // two entries
    header[7] = 24;
    // clang-format off
    const std::vector<uint8_t> bytes = concat(header, {'i', 'd', 1, 1, 1, 2, 2, 2,  // ID, colour map
                                                       0x00, 3, 2, 1, 128,        // raw: one pixel
                                                       0x82, 9, 8, 7, 0});        // run of three
    // clang-format on
    const ImageRgb8 image = decode_image(bytes, ImageFormat::Tga, "in.tga");
    expect_pixel(image, 0, 1, 1, 2, 3);
    expect_pixel(image, 1, 1, 7, 8, 9);
    expect_pixel(image, 0, 0, 7, 8, 9);
    expect_pixel(image, 1, 0, 7, 8, 9);
}

TEST(TgaDecode, Errors) {
    EXPECT_EQ(decode_error({0, 0, 2, 0, 0}, ImageFormat::Tga),
              "truncated TGA file: the header needs 18 bytes, the file has 5");
    EXPECT_EQ(decode_error(tga_header(1, 2, 2, 8, 0), ImageFormat::Tga),
              "unsupported TGA file: image type 1 (raycast reads true-colour TGA, types 2 and 10)");
    EXPECT_EQ(decode_error(tga_header(0, 2, 2, 24, 0), ImageFormat::Tga),
              "unsupported TGA file: image type 0 (raycast reads true-colour TGA, types 2 and 10)");
    EXPECT_EQ(decode_error(tga_header(2, 2, 2, 16, 0), ImageFormat::Tga),
              "unsupported TGA file: 16 bits per pixel (raycast reads 24 and 32)");
    std::vector<uint8_t> bad_map = tga_header(2, 1, 1, 24, 0);
    bad_map[1] = 2;
    EXPECT_EQ(decode_error(concat(bad_map, {1, 2, 3}), ImageFormat::Tga),
              "bad TGA file: colour map type 2 is not 0 or 1");
    EXPECT_EQ(decode_error(tga_header(2, 0, 2, 24, 0), ImageFormat::Tga),
              "bad image size 0x2: width and height must be at least 1");
    EXPECT_EQ(decode_error(tga_header(2, 20000, 1, 24, 0), ImageFormat::Tga),
              "image too large: 20000x1 is more than raycast's limit of 16384 a side and 67108864 pixels");
    EXPECT_EQ(decode_error(tga_header(10, 9000, 9000, 24, 0), ImageFormat::Tga),
              "image too large: 9000x9000 is more than raycast's limit of 16384 a side and 67108864 pixels");
    EXPECT_EQ(decode_error(concat(tga_header(2, 3, 2, 24, 0), std::vector<uint8_t>(17)), ImageFormat::Tga),
              "truncated TGA file: the pixels need 18 bytes but only 17 are there");
    EXPECT_EQ(decode_error(concat(tga_header(10, 3, 2, 24, 0), {0x82, 1, 2, 3, 0x01, 1, 2, 3}), ImageFormat::Tga),
              "truncated TGA file: the RLE data ends after 3 of 6 pixels");
    EXPECT_EQ(decode_error(concat(tga_header(10, 3, 2, 24, 0), {0x82, 1, 2, 3, 0x82}), ImageFormat::Tga),
              "truncated TGA file: the RLE data ends after 3 of 6 pixels");
    EXPECT_EQ(decode_error(concat(tga_header(10, 3, 2, 24, 0), {0x82, 1, 2}), ImageFormat::Tga),
              "truncated TGA file: 3 bytes of RLE data hold at most 0 of the 6 pixels");
    // Refused from its size, before 192 MB of pixels are made for it: 4 bytes make at most one packet
    // of 128 pixels (within the pixel limit, 8000x8000 is not refused for its size alone).
    EXPECT_EQ(decode_error(concat(tga_header(10, 8000, 8000, 24, 0), {0xff, 1, 2, 3}), ImageFormat::Tga),
              "truncated TGA file: 4 bytes of RLE data hold at most 128 of the 64000000 pixels");
    EXPECT_EQ(decode_error(concat(tga_header(10, 3, 2, 24, 0), {0x82, 1, 2, 3, 0x83, 4, 5, 6}), ImageFormat::Tga),
              "bad TGA file: an RLE packet runs past the last pixel");
}

// The size bound above is exact: one run-length packet of 1 + 3 bytes gives 128 pixels, not 129.
TEST(TgaDecode, FourBytesOfRleDataHold128Pixels) {
    const ImageRgb8 image =
        decode_image(concat(tga_header(10, 128, 1, 24, 0), {0xff, 1, 2, 3}), ImageFormat::Tga, "in.tga");
    ASSERT_EQ(image.width, 128);
    expect_pixel(image, 0, 0, 3, 2, 1);
    expect_pixel(image, 127, 0, 3, 2, 1);
    EXPECT_EQ(decode_error(concat(tga_header(10, 129, 1, 24, 0), {0xff, 1, 2, 3}), ImageFormat::Tga),
              "truncated TGA file: 4 bytes of RLE data hold at most 128 of the 129 pixels");
}

// ---- PNG decoding ----

TEST(PngDecode, GrayOneBit) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 image = decode_image(kPngGray1Bit3x2, ImageFormat::Png, "in.png");
    ASSERT_EQ(image.width, 3);
    ASSERT_EQ(image.height, 2);
    expect_pixel(image, 0, 1, 255, 255, 255);  // top row 1 0 1
    expect_pixel(image, 1, 1, 0, 0, 0);
    expect_pixel(image, 2, 1, 255, 255, 255);
    expect_pixel(image, 0, 0, 0, 0, 0);  // bottom row 0 1 1
    expect_pixel(image, 1, 0, 255, 255, 255);
    expect_pixel(image, 2, 0, 255, 255, 255);
}

TEST(PngDecode, PaletteWithTransparencyDropsAlpha) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 image = decode_image(kPngPalette2x2, ImageFormat::Png, "in.png");
    expect_pixel(image, 0, 1, 10, 20, 30);  // entry 0, fully transparent: alpha is dropped, not composited
    expect_pixel(image, 1, 1, 200, 100, 50);
    expect_pixel(image, 0, 0, 0, 255, 0);
    expect_pixel(image, 1, 0, 10, 20, 30);
}

TEST(PngDecode, SixteenBitScalesLikePpm) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 image = decode_image(kPngRgb16Bit2x1, ImageFormat::Png, "in.png");
    expect_pixel(image, 0, 0, 0, 1, 255);
    expect_pixel(image, 1, 0, 128, 127, 128);
}

TEST(PngDecode, GrayWithAlpha) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 image = decode_image(kPngGrayAlpha1x2, ImageFormat::Png, "in.png");
    expect_pixel(image, 0, 1, 200, 200, 200);
    expect_pixel(image, 0, 0, 7, 7, 7);
}

TEST(PngDecode, InterlacedRgba) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 image = decode_image(kPngRgbaInterlaced3x3, ImageFormat::Png, "in.png");
    for (int row = 0; row < 3; ++row)
        for (int column = 0; column < 3; ++column)
            expect_pixel(image, column, 2 - row, 10 * column + row, 100 + row, 200 + column);
}

TEST(PngDecode, Errors) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    EXPECT_EQ(decode_error({}, ImageFormat::Png), "not a PNG file: it does not start with the PNG signature");
    EXPECT_EQ(decode_error(bytes_of("BM whatever"), ImageFormat::Png),
              "not a PNG file: it does not start with the PNG signature");
    EXPECT_EQ(
        decode_error(std::vector<uint8_t>(kPngGray1Bit3x2.begin(), kPngGray1Bit3x2.begin() + 5), ImageFormat::Png),
        "truncated PNG file: it ends before the image is complete");
    EXPECT_EQ(
        decode_error(std::vector<uint8_t>(kPngGray1Bit3x2.begin(), kPngGray1Bit3x2.begin() + 40), ImageFormat::Png),
        "truncated PNG file: it ends before the image is complete");
    std::vector<uint8_t> bad_crc = kPngGray1Bit3x2;
    bad_crc[20] ^= 1;  // the width in IHDR, now off its CRC
    EXPECT_EQ(decode_error(bad_crc, ImageFormat::Png), "bad PNG file: IHDR: CRC error");
    EXPECT_EQ(decode_error(kPngTooWide, ImageFormat::Png),
              "image too large: 16385x1 is more than raycast's limit of 16384 a side and 67108864 pixels");
    // Refused from its size, before 192 MB of image are made for it.
    EXPECT_EQ(decode_error(kPngPromisesTooMuch, ImageFormat::Png),
              "truncated PNG file: it ends before the image is complete");
}

// The bound above holds for the most compressible image there is: one colour, which deflate packs
// nearly 1032 to 1. raycast's own PNG of a black 2048x2048 image reads back.
TEST(PngDecode, ABigImageOfOneColourIsNotTakenForATruncatedOne) {
    if (!png_supported()) GTEST_SKIP() << "built without libpng";
    const ImageRgb8 black(2048, 2048);
    const std::vector<uint8_t> png = encode_image(black, ImageFormat::Png);
    const ImageRgb8 image = decode_image(png, ImageFormat::Png, "black.png");
    EXPECT_EQ(image.rgb, black.rgb) << png.size() << " bytes";
}

TEST_F(ImageFileTest, PngWithoutLibpng) {
    if (png_supported()) GTEST_SKIP() << "built with libpng";
    EXPECT_EQ(decode_error(kPngGray1Bit3x2, ImageFormat::Png), kPngUnsupportedMessage);
    EXPECT_EQ(input_error([&] { write_image(path("out.png"), small_image()); }, path("out.png")),
              kPngUnsupportedMessage);
    EXPECT_EQ(entries(), std::vector<std::string>{});
    write_bytes(path("in.png"), kPngGray1Bit3x2);
    EXPECT_EQ(input_error([&] { read_image(path("in.png")); }, path("in.png")), kPngUnsupportedMessage);
    EXPECT_EQ(input_error([&] { encode_image(small_image(), ImageFormat::Png); }, "png"), kPngUnsupportedMessage);
}

// ---- robustness: what a fuzzer would try ----

struct Sample {
    const char* what;
    ImageFormat format;
    std::vector<uint8_t> bytes;
    size_t shortest_valid;  // prefixes of at least this many bytes still decode
};

std::vector<Sample> samples() {
    const ImageRgb8 image = pattern_image(3, 2, 5);
    std::vector<Sample> list;
    list.push_back({"bmp", ImageFormat::Bmp, encode_image(image, ImageFormat::Bmp), 78 - 3});  // last padding optional
    list.push_back({"bmp 32", ImageFormat::Bmp, concat(bmp_header(2, -2, 32, 0, 16), std::vector<uint8_t>(16, 9)), 70});
    list.push_back({"ppm", ImageFormat::Ppm, encode_image(image, ImageFormat::Ppm), 0});
    list.push_back(
        {"ppm 16", ImageFormat::Ppm, concat(bytes_of("P6 # c\n1 2 65535\n"), std::vector<uint8_t>(12, 1)), 0});
    list.push_back({"tga", ImageFormat::Tga, encode_image(image, ImageFormat::Tga), 0});
    list.push_back(
        {"tga rle", ImageFormat::Tga,
         concat(tga_header(10, 3, 2, 32, 0x20), {0x82, 1, 2, 3, 4, 0x02, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16}),
         0});
    for (auto& sample : list)
        sample.shortest_valid = sample.shortest_valid ? sample.shortest_valid : sample.bytes.size();
    if (png_supported()) {
        for (const std::vector<uint8_t>* png : {&kPngGray1Bit3x2, &kPngPalette2x2, &kPngRgbaInterlaced3x3}) {
            // The pixels are complete once the IDAT chunk (and its CRC) has been read: 12 bytes of IEND may go.
            list.push_back({"png", ImageFormat::Png, *png, png->size() - 12});
        }
        const std::vector<uint8_t> encoded = encode_image(image, ImageFormat::Png);
        list.push_back({"png encoded", ImageFormat::Png, encoded, encoded.size() - 12});
    }
    return list;
}

TEST(DecodeImage, EveryTruncationIsRejected) {
    for (const Sample& sample : samples()) {
        for (size_t length = 0; length < sample.bytes.size(); ++length) {
            SCOPED_TRACE(testing::Message() << sample.what << " cut to " << length << " of " << sample.bytes.size());
            const std::vector<uint8_t> prefix(sample.bytes.begin(), sample.bytes.begin() + static_cast<long>(length));
            if (length < sample.shortest_valid)
                EXPECT_THROW(decode_image(prefix, sample.format, "cut"), InputError);
            else
                EXPECT_NO_THROW(decode_image(prefix, sample.format, "cut"));
        }
    }
}

TEST(DecodeImage, CorruptedBytesGiveAnImageOrAnInputError) {
    const uint32_t seed = 20240611;
    std::mt19937 random(seed);
    for (const Sample& sample : samples()) {
        for (int round = 0; round < 3000; ++round) {
            std::vector<uint8_t> bytes = sample.bytes;
            const int changes = 1 + static_cast<int>(random() % 4);
            for (int i = 0; i < changes; ++i) {
                const size_t at = random() % bytes.size();
                // Extreme values find more edge cases than uniform ones.
                const uint8_t choices[] = {0, 1, 0x7f, 0x80, 0xff, static_cast<uint8_t>(random())};
                bytes[at] = choices[random() % 6];
            }
            if (random() % 4 == 0) bytes.resize(random() % (bytes.size() + 1));
            SCOPED_TRACE(testing::Message() << sample.what << ", seed " << seed << ", round " << round);
            try {
                const ImageRgb8 image = decode_image(bytes, sample.format, "fuzz");
                EXPECT_GE(image.width, 1);
                EXPECT_GE(image.height, 1);
                EXPECT_EQ(image.rgb.size(), 3 * size_t(image.width) * size_t(image.height));
            } catch (const InputError&) {
            }
        }
    }
}

// ---- files ----

TEST_F(ImageFileTest, ReadErrors) {
    EXPECT_EQ(input_error([&] { read_image(path("missing.bmp")); }, path("missing.bmp")),
              "cannot read image: No such file or directory");
    std::filesystem::create_directory(path("folder.bmp"));
    EXPECT_EQ(input_error([&] { read_image(path("folder.bmp")); }, path("folder.bmp")),
              "cannot read image: Is a directory");
    write_bytes(path("notes.txt"), bytes_of("hello"));
    EXPECT_EQ(input_error([&] { read_image(path("notes.txt")); }, path("notes.txt")),
              "unknown image format: the file is not a BMP, PPM or PNG image, and only names ending in .tga are read "
              "as TGA");
    // A name that promises a format gets that format's complaint.
    write_bytes(path("notes.bmp"), bytes_of("hello"));
    EXPECT_EQ(input_error([&] { read_image(path("notes.bmp")); }, path("notes.bmp")),
              "not a BMP file: it does not start with 'BM'");
    write_bytes(path("empty.tga"), {});
    EXPECT_EQ(input_error([&] { read_image(path("empty.tga")); }, path("empty.tga")),
              "truncated TGA file: the header needs 18 bytes, the file has 0");
}

TEST_F(ImageFileTest, WriteRejectsUnknownAndMissingExtensions) {
    EXPECT_EQ(input_error([&] { write_image(path("out.jpg"), small_image()); }, path("out.jpg")),
              "unknown image format '.jpg': use .bmp, .ppm, .tga or .png");
    EXPECT_EQ(input_error([&] { write_image(path("out.Jpeg"), small_image()); }, path("out.Jpeg")),
              "unknown image format '.Jpeg': use .bmp, .ppm, .tga or .png");
    EXPECT_EQ(input_error([&] { write_image(path("out"), small_image()); }, path("out")),
              "no image format: the file name needs an extension .bmp, .ppm, .tga or .png");
    EXPECT_EQ(entries(), std::vector<std::string>{});
}

TEST_F(ImageFileTest, WriteIntoAMissingDirectory) {
    const std::string target = path("missing/out.bmp");
    EXPECT_EQ(input_error([&] { write_image(target, small_image()); }, target),
              "cannot write image: No such file or directory");
    EXPECT_EQ(entries(), std::vector<std::string>{});
}

TEST_F(ImageFileTest, WriteOverADirectoryLeavesNoTemporary) {
    std::filesystem::create_directory(path("taken.bmp"));
    write_bytes(path("taken.bmp/inside"), bytes_of("keep"));
    EXPECT_EQ(input_error([&] { write_image(path("taken.bmp"), small_image()); }, path("taken.bmp")),
              "cannot write image: Is a directory");
    EXPECT_EQ(entries(), std::vector<std::string>{"taken.bmp"});
    EXPECT_EQ(read_bytes(path("taken.bmp/inside")), bytes_of("keep"));
}

TEST_F(ImageFileTest, WriteReplacesAnExistingFile) {
    write_bytes(path("out.ppm"), bytes_of("old contents that are longer than the new file"));
    write_image(path("out.ppm"), small_image());
    EXPECT_EQ(read_bytes(path("out.ppm")), encode_image(small_image(), ImageFormat::Ppm));
    EXPECT_EQ(entries(), std::vector<std::string>{"out.ppm"});
}

TEST_F(ImageFileTest, NewFilesGetTheUmaskPermissions) {
    // A temporary from mkstemp would be 0600; the image must be as readable as any other new file.
    const mode_t old_mask = ::umask(022);
    write_image(path("out.tga"), small_image());
    ::umask(old_mask);
    struct stat info {};
    ASSERT_EQ(::stat(path("out.tga").c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 0777, 0644u);
}

// Runs `write` with files limited to 4 KiB, so that writing a 120 KB image fails part way (EFBIG
// instead of SIGXFSZ), and returns where and why the InputError it threw says it failed ("FILE:
// MESSAGE"), or "no error". Nothing else may run while the limit holds: even a test failure
// message could hit it.
std::string error_under_a_4_kib_file_limit(const std::function<void()>& write) {
    struct rlimit saved {};
    if (::getrlimit(RLIMIT_FSIZE, &saved) != 0) return "getrlimit failed";
    struct sigaction ignore {
    }, saved_action{};
    ignore.sa_handler = SIG_IGN;
    if (::sigaction(SIGXFSZ, &ignore, &saved_action) != 0) return "sigaction failed";
    struct rlimit limited = saved;
    limited.rlim_cur = 4096;
    std::string message = "no error";
    if (::setrlimit(RLIMIT_FSIZE, &limited) != 0) {
        message = "setrlimit failed";
    } else {
        try {
            write();
        } catch (const InputError& error) {
            message = error.diagnostics()[0].location.file + ": " + error.diagnostics()[0].message;
        }
        ::setrlimit(RLIMIT_FSIZE, &saved);
    }
    ::sigaction(SIGXFSZ, &saved_action, nullptr);
    return message;
}

TEST_F(ImageFileTest, FailedWriteLeavesTheExistingFileUntouched) {
    const std::vector<uint8_t> old = encode_image(small_image(), ImageFormat::Bmp);
    write_bytes(path("out.bmp"), old);
    EXPECT_EQ(error_under_a_4_kib_file_limit([&] { write_image(path("out.bmp"), ImageRgb8(200, 200)); }),
              path("out.bmp") + ": cannot write image: File too large");
    EXPECT_EQ(read_bytes(path("out.bmp")), old);
    EXPECT_EQ(entries(), std::vector<std::string>{"out.bmp"});
}

// Files written together (an image and its --depth): when one fails, none is replaced. The first
// had been written whole before the second failed (a full disk), so a run that reported failure
// had still replaced the image.
TEST_F(ImageFileTest, FilesWrittenTogetherAreAllReplacedOrNone) {
    write_bytes(path("image.bmp"), bytes_of("old image"));
    write_bytes(path("depth.bmp"), bytes_of("old depth"));
    const std::vector<uint8_t> small = encode_image(small_image(), ImageFormat::Bmp);  // within the limit below
    const std::vector<uint8_t> large = encode_image(ImageRgb8(200, 200), ImageFormat::Bmp);
    ASSERT_LT(small.size(), 4096u);
    EXPECT_EQ(error_under_a_4_kib_file_limit([&] {
                  write_files_atomically({{path("image.bmp"), small}, {path("depth.bmp"), large}}, "image");
              }),
              path("depth.bmp") + ": cannot write image: File too large");
    EXPECT_EQ(read_bytes(path("image.bmp")), bytes_of("old image"));
    EXPECT_EQ(read_bytes(path("depth.bmp")), bytes_of("old depth"));
    EXPECT_EQ(entries(), (std::vector<std::string>{"depth.bmp", "image.bmp"}));
    // Both fit: both are replaced.
    write_files_atomically({{path("image.bmp"), small}, {path("depth.bmp"), large}}, "image");
    EXPECT_EQ(read_bytes(path("image.bmp")), small);
    EXPECT_EQ(read_bytes(path("depth.bmp")), large);
    EXPECT_EQ(entries(), (std::vector<std::string>{"depth.bmp", "image.bmp"}));
}

TEST_F(ImageFileTest, FailedEncodeLeavesTheExistingFileUntouched) {
    write_bytes(path("out.tga"), bytes_of("old"));
    ImageRgb8 broken(2, 2);
    broken.rgb.resize(5);
    EXPECT_THROW(write_image(path("out.tga"), broken), std::invalid_argument);
    EXPECT_EQ(read_bytes(path("out.tga")), bytes_of("old"));
    EXPECT_EQ(entries(), std::vector<std::string>{"out.tga"});
}

}  // namespace
}  // namespace raycast
