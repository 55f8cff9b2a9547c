#include "image/image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <new>
#include <stdexcept>

#include "base/error.h"
#include "base/write_file.h"

#ifdef RAYCAST_HAVE_PNG
#include <png.h>

#include <csetjmp>
#include <cstdio>
#endif

namespace raycast {

namespace {

const char* const kPngUnsupported =
    "PNG images need libpng: rebuild raycast with libpng-dev installed, or use .bmp, .ppm or .tga";

const uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// Readers call this before allocating anything, so a forged header cannot make raycast ask for gigabytes.
void check_image_size(const std::string& name, int64_t width, int64_t height) {
    const auto w = static_cast<long long>(width);
    const auto h = static_cast<long long>(height);
    if (width <= 0 || height <= 0)
        throw InputError(name, string_printf("bad image size %lldx%lld: width and height must be at least 1", w, h));
    if (width > kMaxImageSide || height > kMaxImageSide || width * height > kMaxImagePixels)
        throw InputError(name, string_printf("image too large: %lldx%lld is more than raycast's limit of %d a side "
                                             "and %lld pixels",
                                             w, h, kMaxImageSide, static_cast<long long>(kMaxImagePixels)));
}

[[noreturn]] void throw_truncated_pixels(const std::string& name, const char* format, size_t need, size_t have) {
    throw InputError(
        name, string_printf("truncated %s file: the pixels need %zu bytes but only %zu are there", format, need, have));
}

// Bytes available from `offset` to the end, zero when the offset lies past the end.
size_t bytes_after(const std::vector<uint8_t>& bytes, size_t offset) {
    return offset < bytes.size() ? bytes.size() - offset : 0;
}

bool starts_with(const std::vector<uint8_t>& bytes, const uint8_t* prefix, size_t length) {
    return bytes.size() >= length && std::memcmp(bytes.data(), prefix, length) == 0;
}

// Little-endian fields; callers have checked that the bytes exist.
uint16_t get_u16(const std::vector<uint8_t>& bytes, size_t at) {
    return static_cast<uint16_t>(bytes[at] | bytes[at + 1] << 8);
}

uint32_t get_u32(const std::vector<uint8_t>& bytes, size_t at) {
    return uint32_t{bytes[at]} | uint32_t{bytes[at + 1]} << 8 | uint32_t{bytes[at + 2]} << 16 |
           uint32_t{bytes[at + 3]} << 24;
}

void put_u16(std::vector<uint8_t>& bytes, uint32_t value) {
    bytes.push_back(static_cast<uint8_t>(value & 0xff));
    bytes.push_back(static_cast<uint8_t>(value >> 8 & 0xff));
}

void put_u32(std::vector<uint8_t>& bytes, uint32_t value) {
    put_u16(bytes, value & 0xffff);
    put_u16(bytes, value >> 16);
}

// ---- BMP ----

constexpr size_t kBmpHeaderSize = 54;

size_t bmp_stride(size_t width, size_t bytes_per_pixel) { return (width * bytes_per_pixel + 3) & ~size_t{3}; }

std::vector<uint8_t> encode_bmp(const ImageRgb8& image) {
    const size_t stride = bmp_stride(static_cast<size_t>(image.width), 3);
    const size_t pixel_bytes = stride * static_cast<size_t>(image.height);
    std::vector<uint8_t> out;
    out.reserve(kBmpHeaderSize + pixel_bytes);
    // BITMAPFILEHEADER
    out.push_back('B');
    out.push_back('M');
    put_u32(out, static_cast<uint32_t>(kBmpHeaderSize + pixel_bytes));
    put_u32(out, 0);  // two reserved 16-bit fields
    put_u32(out, kBmpHeaderSize);
    // BITMAPINFOHEADER
    put_u32(out, 40);
    put_u32(out, static_cast<uint32_t>(image.width));
    put_u32(out, static_cast<uint32_t>(image.height));  // positive: bottom-up, like the course
    put_u16(out, 1);                                    // planes
    put_u16(out, 24);                                   // bits per pixel
    put_u32(out, 0);                                    // BI_RGB
    put_u32(out, static_cast<uint32_t>(pixel_bytes));
    put_u32(out, 0);  // pixels per metre, x and y
    put_u32(out, 0);
    put_u32(out, 0);  // colours used, colours important: no palette
    put_u32(out, 0);
    // The course leaves the padding uninitialised; zeros make our output reproducible byte for byte.
    out.resize(kBmpHeaderSize + pixel_bytes, 0);
    for (int y = 0; y < image.height; ++y) {
        uint8_t* row = out.data() + kBmpHeaderSize + static_cast<size_t>(y) * stride;
        for (int x = 0; x < image.width; ++x) {
            const uint8_t* p = image.at(x, y);
            row[3 * x + 0] = p[2];
            row[3 * x + 1] = p[1];
            row[3 * x + 2] = p[0];
        }
    }
    return out;
}

void throw_truncated_bmp_header(const std::string& name, size_t need, size_t have) {
    throw InputError(name,
                     string_printf("truncated BMP file: the header needs %zu bytes, the file has %zu", need, have));
}

ImageRgb8 decode_bmp(const std::vector<uint8_t>& bytes, const std::string& name) {
    const size_t size = bytes.size();
    if (size < 2 || bytes[0] != 'B' || bytes[1] != 'M')
        throw InputError(name, "not a BMP file: it does not start with 'BM'");
    if (size < 18) throw_truncated_bmp_header(name, kBmpHeaderSize, size);
    const uint32_t info_size = get_u32(bytes, 14);
    // BITMAPV4/V5 headers extend BITMAPINFOHEADER, so its 40 bytes are all we read; the 12-byte OS/2
    // header has 16-bit sizes and a different layout.
    if (info_size < 40)
        throw InputError(name, string_printf("unsupported BMP file: a %u-byte info header (raycast reads headers of "
                                             "40 bytes or more)",
                                             info_size));
    if (size < kBmpHeaderSize) throw_truncated_bmp_header(name, kBmpHeaderSize, size);
    const auto width = static_cast<int32_t>(get_u32(bytes, 18));
    const auto height_field = static_cast<int32_t>(get_u32(bytes, 22));
    const uint16_t bits = get_u16(bytes, 28);
    const uint32_t compression = get_u32(bytes, 30);
    if (bits != 24 && bits != 32)
        throw InputError(name,
                         string_printf("unsupported BMP file: %u bits per pixel (raycast reads 24 and 32)", bits));
    constexpr uint32_t kBiRgb = 0, kBiBitfields = 3;
    if (compression == kBiBitfields && bits == 32) {
        // Many tools write 32-bit BMPs as BI_BITFIELDS with the standard masks, which mean the same as BI_RGB.
        // The three masks follow the 40-byte header, whether inside a longer header or on their own.
        if (size < kBmpHeaderSize + 12) throw_truncated_bmp_header(name, kBmpHeaderSize + 12, size);
        if (get_u32(bytes, 54) != 0x00ff0000 || get_u32(bytes, 58) != 0x0000ff00 || get_u32(bytes, 62) != 0x000000ff)
            throw InputError(name,
                             "unsupported BMP file: colour masks other than 8-bit R, G, B (raycast reads only "
                             "those)");
    } else if (compression != kBiRgb) {
        throw InputError(name, string_printf("unsupported BMP file: compression type %u (raycast reads only "
                                             "uncompressed BMP)",
                                             compression));
    }
    // A negative height marks rows stored top first.
    const bool top_down = height_field < 0;
    const int64_t height = top_down ? -int64_t{height_field} : int64_t{height_field};
    check_image_size(name, width, height);

    const size_t bytes_per_pixel = bits / 8u;
    const size_t w = static_cast<size_t>(width), h = static_cast<size_t>(height);
    const size_t stride = bmp_stride(w, bytes_per_pixel);
    // Some writers leave out the last row's padding; the pixels themselves must all be there.
    const size_t need = stride * (h - 1) + w * bytes_per_pixel;
    const size_t offset = get_u32(bytes, 10);
    const size_t have = bytes_after(bytes, offset);
    if (have < need) throw_truncated_pixels(name, "BMP", need, have);

    ImageRgb8 image(width, static_cast<int>(height));
    for (size_t row = 0; row < h; ++row) {
        const uint8_t* src = bytes.data() + offset + row * stride;
        const int y = static_cast<int>(top_down ? h - 1 - row : row);
        for (int x = 0; x < width; ++x, src += bytes_per_pixel) {
            uint8_t* p = image.at(x, y);
            p[0] = src[2];
            p[1] = src[1];
            p[2] = src[0];
        }
    }
    return image;
}

// ---- PPM ----

std::vector<uint8_t> encode_ppm(const ImageRgb8& image, const std::string& comment = "") {
    const std::string comment_line = comment.empty() ? std::string() : "# " + comment + "\n";
    const std::string header = string_printf("P6\n%s%d %d\n255\n", comment_line.c_str(), image.width, image.height);
    std::vector<uint8_t> out(header.begin(), header.end());
    out.reserve(header.size() + image.rgb.size());
    // PPM stores the top row first, and our y = 0 is the bottom row.
    const size_t row_bytes = 3 * static_cast<size_t>(image.width);
    for (int y = image.height - 1; y >= 0; --y) out.insert(out.end(), image.at(0, y), image.at(0, y) + row_bytes);
    return out;
}

bool is_ppm_space(uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r'; }

bool is_digit(uint8_t c) { return c >= '0' && c <= '9'; }

// Reads the text parts of a PPM file: header fields, and every sample of a P3 file.
class PpmParser {
public:
    PpmParser(const std::vector<uint8_t>& bytes, const std::string& name) : bytes_(bytes), name_(name) {}

    size_t position() const { return pos_; }
    void set_position(size_t pos) { pos_ = pos; }

    /// Skips whitespace and '#' comments (which run to the end of the line).
    void skip_space() {
        while (pos_ < bytes_.size()) {
            if (is_ppm_space(bytes_[pos_])) {
                ++pos_;
            } else if (bytes_[pos_] == '#') {
                while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
            } else {
                break;
            }
        }
    }

    bool at_end() const { return pos_ >= bytes_.size(); }

    /// Reads a decimal number at the current position. Values saturate at 2^31 - 1 so that absurd
    /// sizes fail the size check instead of overflowing. Returns nullopt if no digit is there.
    std::optional<int64_t> number() {
        if (pos_ >= bytes_.size() || !is_digit(bytes_[pos_])) return std::nullopt;
        constexpr int64_t kSaturated = 0x7fffffff;
        int64_t value = 0;
        while (pos_ < bytes_.size() && is_digit(bytes_[pos_])) {
            value = std::min(kSaturated, value * 10 + (bytes_[pos_] - '0'));
            ++pos_;
        }
        return value;
    }

    int64_t header_number(const char* what) {
        skip_space();
        if (at_end()) throw InputError(name_, string_printf("truncated PPM file: the header ends before the %s", what));
        const std::optional<int64_t> value = number();
        if (!value) throw InputError(name_, string_printf("bad PPM file: the %s is not a number", what));
        return *value;
    }

private:
    const std::vector<uint8_t>& bytes_;
    const std::string& name_;
    size_t pos_ = 0;
};

[[noreturn]] void throw_ppm_sample_too_big(const std::string& name, int64_t value, int64_t maxval) {
    throw InputError(name, string_printf("bad PPM file: the sample value %lld is more than the maximum value %lld",
                                         static_cast<long long>(value), static_cast<long long>(maxval)));
}

ImageRgb8 decode_ppm(const std::vector<uint8_t>& bytes, const std::string& name) {
    const bool binary = bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '6';
    const bool text = bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] == '3';
    // "P6" must end at whitespace or a comment: "P65 ..." is not a PPM file.
    if ((!binary && !text) || (bytes.size() > 2 && !is_ppm_space(bytes[2]) && bytes[2] != '#'))
        throw InputError(name, "not a PPM file: it does not start with P6 or P3");
    PpmParser parser(bytes, name);
    parser.set_position(2);
    const int64_t width = parser.header_number("width");
    const int64_t height = parser.header_number("height");
    check_image_size(name, width, height);
    const int64_t maxval = parser.header_number("maximum value");
    if (maxval < 1 || maxval > 65535)
        throw InputError(name, string_printf("bad PPM file: the maximum value %lld is not in 1..65535",
                                             static_cast<long long>(maxval)));

    const int w = static_cast<int>(width), h = static_cast<int>(height);
    const size_t sample_count = 3 * static_cast<size_t>(w) * static_cast<size_t>(h);
    const auto max = static_cast<uint32_t>(maxval);
    // value·255/maxval, rounded; exact for maxval 255.
    auto to_8_bits = [max](uint32_t value) { return static_cast<uint8_t>((value * 255 + max / 2) / max); };

    // Samples arrive top row first; sample i belongs to row y = h - 1 - i / (3w) of our bottom-up image.
    // Made no larger than the file can fill: a header of a few bytes may claim 64M pixels (the
    // image fuzzer's inputs did, allocating 192 MB each and running at a hundredth of its speed).
    std::vector<uint8_t> samples;
    if (binary) {
        // Exactly one whitespace byte separates the header from the binary samples.
        size_t pos = parser.position();
        if (pos < bytes.size() && !is_ppm_space(bytes[pos]))
            throw InputError(name, "bad PPM file: no whitespace after the maximum value");
        ++pos;
        const size_t bytes_per_sample = max > 255 ? 2 : 1;
        const size_t need = sample_count * bytes_per_sample;
        const size_t have = bytes_after(bytes, pos);
        if (have < need) throw_truncated_pixels(name, "PPM", need, have);
        samples.resize(sample_count);
        const uint8_t* src = bytes.data() + pos;
        for (size_t i = 0; i < sample_count; ++i) {
            // 16-bit samples are big-endian.
            const uint32_t value = bytes_per_sample == 2 ? uint32_t{src[2 * i]} << 8 | src[2 * i + 1] : src[i];
            if (value > max) throw_ppm_sample_too_big(name, value, maxval);
            samples[i] = to_8_bits(value);
        }
    } else {
        // Every value but the last takes a digit and a separator at least.
        samples.reserve(std::min(sample_count, bytes_after(bytes, parser.position()) / 2 + 1));
        for (size_t i = 0; i < sample_count; ++i) {
            parser.skip_space();
            if (parser.at_end())
                throw InputError(name, string_printf("truncated PPM file: the pixels need %zu values but only %zu are "
                                                     "there",
                                                     sample_count, i));
            const std::optional<int64_t> value = parser.number();
            if (!value) throw InputError(name, "bad PPM file: a sample value is not a number");
            if (*value > maxval) throw_ppm_sample_too_big(name, *value, maxval);
            samples.push_back(to_8_bits(static_cast<uint32_t>(*value)));
        }
    }

    ImageRgb8 image(w, h);
    const size_t row_bytes = 3 * static_cast<size_t>(w);
    for (int row = 0; row < h; ++row)
        std::memcpy(image.at(0, h - 1 - row), samples.data() + static_cast<size_t>(row) * row_bytes, row_bytes);
    return image;
}

// ---- TGA ----

constexpr size_t kTgaHeaderSize = 18;

std::vector<uint8_t> encode_tga(const ImageRgb8& image) {
    std::vector<uint8_t> out;
    out.reserve(kTgaHeaderSize + image.rgb.size());
    out.push_back(0);                              // no image ID
    out.push_back(0);                              // no colour map
    out.push_back(2);                              // uncompressed true colour
    for (int i = 0; i < 5; ++i) out.push_back(0);  // colour map specification
    put_u16(out, 0);                               // x origin
    put_u16(out, 0);                               // y origin
    put_u16(out, static_cast<uint32_t>(image.width));
    put_u16(out, static_cast<uint32_t>(image.height));
    out.push_back(24);
    out.push_back(0);  // descriptor: no alpha bits, origin bottom-left, so rows go from y = 0 up
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const uint8_t* p = image.at(x, y);
            out.push_back(p[2]);
            out.push_back(p[1]);
            out.push_back(p[0]);
        }
    }
    return out;
}

ImageRgb8 decode_tga(const std::vector<uint8_t>& bytes, const std::string& name) {
    const size_t size = bytes.size();
    if (size < kTgaHeaderSize)
        throw InputError(name, string_printf("truncated TGA file: the header needs %zu bytes, the file has %zu",
                                             kTgaHeaderSize, size));
    const uint8_t id_length = bytes[0];
    const uint8_t colour_map_type = bytes[1];
    const uint8_t image_type = bytes[2];
    const uint16_t colour_map_length = get_u16(bytes, 5);
    const uint8_t colour_map_entry_bits = bytes[7];
    const uint16_t width = get_u16(bytes, 12);
    const uint16_t height = get_u16(bytes, 14);
    const uint8_t bits = bytes[16];
    const uint8_t descriptor = bytes[17];
    const bool rle = image_type == 10;
    if (image_type != 2 && !rle)
        throw InputError(name,
                         string_printf("unsupported TGA file: image type %u (raycast reads true-colour TGA, types "
                                       "2 and 10)",
                                       image_type));
    if (colour_map_type > 1)
        throw InputError(name, string_printf("bad TGA file: colour map type %u is not 0 or 1", colour_map_type));
    if (bits != 24 && bits != 32)
        throw InputError(name,
                         string_printf("unsupported TGA file: %u bits per pixel (raycast reads 24 and 32)", bits));
    check_image_size(name, width, height);

    // A true-colour image may still carry a colour map, which we skip.
    const size_t colour_map_bytes =
        colour_map_type == 1 ? size_t{colour_map_length} * ((colour_map_entry_bits + 7u) / 8u) : 0;
    size_t pos = kTgaHeaderSize + id_length + colour_map_bytes;
    const size_t bytes_per_pixel = bits / 8u;
    const size_t pixel_count = size_t{width} * height;

    // Pixels in file order (BGR or BGRA), decompressed.
    std::vector<uint8_t> stored;
    const uint8_t* pixels = nullptr;
    if (!rle) {
        const size_t need = pixel_count * bytes_per_pixel;
        const size_t have = bytes_after(bytes, pos);
        if (have < need) throw_truncated_pixels(name, "TGA", need, have);
        pixels = bytes.data() + pos;
    } else {
        // Every packet takes at least 1 + bytes_per_pixel bytes and gives at most 128 pixels, so a few
        // bytes that promise millions of pixels are refused before the pixels' memory is made.
        const size_t rle_bytes = bytes_after(bytes, pos);
        const size_t most_pixels = rle_bytes / (1 + bytes_per_pixel) * 128;
        if (pixel_count > most_pixels)
            throw InputError(name, string_printf("truncated TGA file: %zu bytes of RLE data hold at most %zu of the "
                                                 "%zu pixels",
                                                 rle_bytes, most_pixels, pixel_count));
        stored.resize(pixel_count * bytes_per_pixel);
        size_t done = 0;
        auto truncated = [&] {
            return InputError(name, string_printf("truncated TGA file: the RLE data ends after %zu of %zu pixels", done,
                                                  pixel_count));
        };
        while (done < pixel_count) {
            if (pos >= size) throw truncated();
            const uint8_t packet = bytes[pos++];
            const size_t count = (packet & 0x7fu) + 1u;
            if (count > pixel_count - done)
                throw InputError(name, "bad TGA file: an RLE packet runs past the last pixel");
            uint8_t* dst = stored.data() + done * bytes_per_pixel;
            if (packet & 0x80) {
                // Run-length packet: one pixel, repeated.
                if (bytes_after(bytes, pos) < bytes_per_pixel) throw truncated();
                for (size_t i = 0; i < count; ++i)
                    std::memcpy(dst + i * bytes_per_pixel, bytes.data() + pos, bytes_per_pixel);
                pos += bytes_per_pixel;
            } else {
                // Raw packet: `count` pixels as they are.
                if (bytes_after(bytes, pos) < count * bytes_per_pixel) throw truncated();
                std::memcpy(dst, bytes.data() + pos, count * bytes_per_pixel);
                pos += count * bytes_per_pixel;
            }
            done += count;
        }
        pixels = stored.data();
    }

    // Descriptor bit 5: rows stored top first; bit 4: pixels stored right to left. Alpha is dropped.
    const bool top_first = descriptor & 0x20;
    const bool right_to_left = descriptor & 0x10;
    ImageRgb8 image(width, height);
    for (int row = 0; row < height; ++row) {
        const int y = top_first ? height - 1 - row : row;
        for (int column = 0; column < width; ++column) {
            const int x = right_to_left ? width - 1 - column : column;
            const uint8_t* src =
                pixels + (static_cast<size_t>(row) * width + static_cast<size_t>(column)) * bytes_per_pixel;
            uint8_t* p = image.at(x, y);
            p[0] = src[2];
            p[1] = src[1];
            p[2] = src[0];
        }
    }
    return image;
}

// ---- PNG ----

#ifdef RAYCAST_HAVE_PNG

// libpng reports errors by longjmp. Each function below that calls setjmp holds no object with a
// destructor and allocates nothing, so a longjmp never skips a destructor; the C++ around them owns
// all memory.

struct PngErrorText {
    char text[256] = {};
};

void png_error_to_text(png_structp png, png_const_charp message) {
    auto* error = static_cast<PngErrorText*>(png_get_error_ptr(png));
    std::snprintf(error->text, sizeof error->text, "%s", message);
    png_longjmp(png, 1);
}

// Warnings concern ancillary data (bad gamma, unknown chunks) that we do not use.
void png_ignore_warning(png_structp, png_const_charp) {}

struct PngSource {
    const uint8_t* data = nullptr;
    size_t size = 0;
    size_t pos = 0;
    bool truncated = false;
};

void png_read_from_memory(png_structp png, png_bytep out, size_t length) {
    auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
    if (length > source->size - source->pos) {
        source->truncated = true;
        png_error(png, "truncated");
    }
    std::memcpy(out, source->data + source->pos, length);
    source->pos += length;
}

struct PngReadStructs {
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~PngReadStructs() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

bool png_read_header(png_structp png, png_infop info, png_uint_32* width, png_uint_32* height) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_info(png, info);
    *width = png_get_image_width(png, info);
    *height = png_get_image_height(png, info);
    return true;
}

bool png_set_rgb8_output(png_structp png, png_infop info, size_t* row_bytes) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_expand(png);    // palette to RGB, gray below 8 bits to 8 bits, tRNS to alpha
    png_set_scale_16(png);  // 16 to 8 bits as value·255/65535 rounded, like the PPM reader
    png_set_strip_alpha(png);
    png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    *row_bytes = png_get_rowbytes(png, info);
    return true;
}

bool png_read_rows(png_structp png, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_image(png, rows);
    return true;
}

ImageRgb8 decode_png(const std::vector<uint8_t>& bytes, const std::string& name) {
    if (bytes.empty() || std::memcmp(bytes.data(), kPngSignature, std::min(bytes.size(), sizeof kPngSignature)) != 0)
        throw InputError(name, "not a PNG file: it does not start with the PNG signature");
    PngErrorText error;
    PngSource source{bytes.data(), bytes.size(), 0, false};
    auto fail = [&]() -> InputError {
        if (source.truncated) return InputError(name, "truncated PNG file: it ends before the image is complete");
        return InputError(name, std::string("bad PNG file: ") + error.text);
    };
    PngReadStructs structs;
    structs.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, png_error_to_text, png_ignore_warning);
    if (!structs.png) throw std::bad_alloc();
    structs.info = png_create_info_struct(structs.png);
    if (!structs.info) throw std::bad_alloc();
    png_set_read_fn(structs.png, &source, png_read_from_memory);
    // libpng's own limit (a million a side) would pre-empt ours with a different message.
    png_set_user_limits(structs.png, 0x7fffffff, 0x7fffffff);

    png_uint_32 width = 0, height = 0;
    if (!png_read_header(structs.png, structs.info, &width, &height)) throw fail();
    check_image_size(name, width, height);
    // Deflate packs at most 1032 bytes into one, so the file must be at least that fraction of
    // the rows it promises (a filter byte and the samples each, fewest when not interlaced). A
    // header of a few bytes may promise 64M pixels: found so, it is refused before the image is
    // made (the image fuzzer's inputs allocated 192 MB each otherwise).
    const uint64_t bits_per_pixel = uint64_t{png_get_bit_depth(structs.png, structs.info)} *
                                    png_get_channels(structs.png, structs.info);
    const uint64_t least_data = uint64_t{height} * (1 + (uint64_t{width} * bits_per_pixel + 7) / 8);
    if (least_data > 1032 * uint64_t{bytes.size()})
        throw InputError(name, "truncated PNG file: it ends before the image is complete");
    size_t row_bytes = 0;
    if (!png_set_rgb8_output(structs.png, structs.info, &row_bytes)) throw fail();
    if (row_bytes != 3 * size_t{width})
        throw InputError(name,
                         string_printf("bad PNG file: %zu bytes per row after conversion to 8-bit RGB", row_bytes));

    ImageRgb8 image(static_cast<int>(width), static_cast<int>(height));
    // PNG rows go top first; point each at its row of our bottom-up image.
    std::vector<png_bytep> rows(height);
    for (png_uint_32 row = 0; row < height; ++row) rows[row] = image.at(0, static_cast<int>(height - 1 - row));
    if (!png_read_rows(structs.png, rows.data())) throw fail();
    return image;
}

struct PngSink {
    std::vector<uint8_t>* out = nullptr;
};

void png_write_to_memory(png_structp png, png_bytep data, size_t length) {
    auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
    bool out_of_memory = false;
    try {
        sink->out->insert(sink->out->end(), data, data + length);
    } catch (const std::bad_alloc&) {
        out_of_memory = true;
    }
    // Outside the catch block: a longjmp must not leave a handler with a live exception.
    if (out_of_memory) png_error(png, "out of memory");
}

void png_flush_nothing(png_structp) {}

struct PngWriteStructs {
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~PngWriteStructs() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

bool png_write_rows(png_structp png, png_infop info, const ImageRgb8* image) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, static_cast<png_uint_32>(image->width), static_cast<png_uint_32>(image->height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = image->height - 1; y >= 0; --y) png_write_row(png, image->at(0, y));  // top row first
    png_write_end(png, nullptr);
    return true;
}

std::vector<uint8_t> encode_png(const ImageRgb8& image) {
    std::vector<uint8_t> out;
    PngErrorText error;
    PngSink sink{&out};
    PngWriteStructs structs;
    structs.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, png_error_to_text, png_ignore_warning);
    if (!structs.png) throw std::bad_alloc();
    structs.info = png_create_info_struct(structs.png);
    if (!structs.info) throw std::bad_alloc();
    png_set_write_fn(structs.png, &sink, png_write_to_memory, png_flush_nothing);
    // Nothing in a valid image makes libpng fail here but memory.
    if (!png_write_rows(structs.png, structs.info, &image)) throw std::bad_alloc();
    return out;
}

#else

ImageRgb8 decode_png(const std::vector<uint8_t>&, const std::string& name) { throw InputError(name, kPngUnsupported); }

std::vector<uint8_t> encode_png(const ImageRgb8&) { throw InputError("png", kPngUnsupported); }

#endif

// ---- files ----

std::string path_extension(const std::string& path) {
    const size_t slash = path.rfind('/');
    const size_t name_start = slash == std::string::npos ? 0 : slash + 1;
    const size_t dot = path.rfind('.');
    if (dot == std::string::npos || dot < name_start) return "";
    return path.substr(dot);
}

ImageFormat format_for_writing(const std::string& path) {
    const std::string extension = path_extension(path);
    if (extension.empty())
        throw InputError(path, "no image format: the file name needs an extension .bmp, .ppm, .tga or .png");
    const std::optional<ImageFormat> format = image_format_for_path(path);
    if (!format)
        throw InputError(path,
                         string_printf("unknown image format '%s': use .bmp, .ppm, .tga or .png", extension.c_str()));
    return *format;
}

std::vector<uint8_t> read_file_impl(const std::string& path) {
    auto cannot_read = [&path](int error) {
        return InputError(path, std::string("cannot read image: ") + std::strerror(error));
    };
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw cannot_read(errno);
    struct stat info {};
    if (::fstat(fd, &info) == 0 && S_ISDIR(info.st_mode)) {
        ::close(fd);
        throw cannot_read(EISDIR);
    }
    std::vector<uint8_t> bytes;
    // A plain file's size is known; pipes and devices are read in chunks until end of file.
    if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0)
        bytes.reserve(static_cast<size_t>(info.st_size));
    uint8_t chunk[65536];
    for (;;) {
        const ssize_t got = ::read(fd, chunk, sizeof chunk);
        if (got < 0) {
            if (errno == EINTR) continue;
            const int error = errno;
            ::close(fd);
            throw cannot_read(error);
        }
        if (got == 0) break;
        bytes.insert(bytes.end(), chunk, chunk + got);
    }
    ::close(fd);
    return bytes;
}

}  // namespace

std::optional<ImageFormat> image_format_for_path(const std::string& path) {
    const std::string extension = path_extension(path);
    if (extension.empty()) return std::nullopt;
    return image_format_named(extension.substr(1));
}

std::optional<ImageFormat> image_format_named(const std::string& name) {
    std::string lower = name;
    for (char& c : lower)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (lower == "bmp") return ImageFormat::Bmp;
    if (lower == "ppm") return ImageFormat::Ppm;
    if (lower == "tga") return ImageFormat::Tga;
    if (lower == "png") return ImageFormat::Png;
    return std::nullopt;
}

bool png_supported() {
#ifdef RAYCAST_HAVE_PNG
    return true;
#else
    return false;
#endif
}

std::vector<uint8_t> encode_image(const ImageRgb8& image, ImageFormat format) {
    if (image.width <= 0 || image.height <= 0 || image.width > kMaxImageSide || image.height > kMaxImageSide ||
        image.rgb.size() != 3 * static_cast<size_t>(image.width) * static_cast<size_t>(image.height))
        throw std::invalid_argument(string_printf("encode_image: a %dx%d image with %zu bytes cannot be written",
                                                  image.width, image.height, image.rgb.size()));
    switch (format) {
        case ImageFormat::Bmp:
            return encode_bmp(image);
        case ImageFormat::Ppm:
            return encode_ppm(image);
        case ImageFormat::Tga:
            return encode_tga(image);
        case ImageFormat::Png:
            return encode_png(image);
    }
    throw std::invalid_argument("encode_image: unknown format");
}

ImageRgb8 decode_image(const std::vector<uint8_t>& bytes, ImageFormat format, const std::string& name) {
    switch (format) {
        case ImageFormat::Bmp:
            return decode_bmp(bytes, name);
        case ImageFormat::Ppm:
            return decode_ppm(bytes, name);
        case ImageFormat::Tga:
            return decode_tga(bytes, name);
        case ImageFormat::Png:
            return decode_png(bytes, name);
    }
    throw std::invalid_argument("decode_image: unknown format");
}

void write_image(const std::string& path, const ImageRgb8& image) {
    write_file_atomically(path, encode_image_for_path(path, image), "image");
}

ImageRgb8 read_image(const std::string& path) {
    const std::vector<uint8_t> bytes = read_file_impl(path);
    const uint8_t bmp[2] = {'B', 'M'}, ppm_binary[2] = {'P', '6'}, ppm_text[2] = {'P', '3'};
    if (starts_with(bytes, bmp, 2)) return decode_bmp(bytes, path);
    if (starts_with(bytes, ppm_binary, 2) || starts_with(bytes, ppm_text, 2)) return decode_ppm(bytes, path);
    if (starts_with(bytes, kPngSignature, sizeof kPngSignature)) return decode_png(bytes, path);
    // TGA has no signature, and a file that names another format gets that format's own complaint.
    if (const std::optional<ImageFormat> format = image_format_for_path(path))
        return decode_image(bytes, *format, path);
    throw InputError(path,
                     "unknown image format: the file is not a BMP, PPM or PNG image, and only names ending in "
                     ".tga are read as TGA");
}

std::vector<uint8_t> encode_ppm_with_comment(const ImageRgb8& image, const std::string& comment) {
    if (comment.find_first_of("\r\n") != std::string::npos)
        throw std::invalid_argument("encode_ppm_with_comment: the comment must be one line");
    (void)encode_image(image, ImageFormat::Ppm);  // the same size checks as every other image
    return encode_ppm(image, comment);
}

std::vector<std::string> ppm_header_comments(const std::vector<uint8_t>& bytes) {
    std::vector<std::string> comments;
    if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '6' && bytes[1] != '3')) return comments;
    // The header is the magic number and three numbers (width, height, maximum value), with
    // whitespace and comments anywhere between them.
    size_t pos = 2;
    int numbers = 0;
    while (pos < bytes.size() && numbers < 3) {
        if (is_ppm_space(bytes[pos])) {
            ++pos;
        } else if (bytes[pos] == '#') {
            const size_t start = ++pos;
            while (pos < bytes.size() && bytes[pos] != '\n' && bytes[pos] != '\r') ++pos;
            std::string text(bytes.begin() + static_cast<std::ptrdiff_t>(start), bytes.begin() + static_cast<std::ptrdiff_t>(pos));
            if (!text.empty() && text[0] == ' ') text.erase(0, 1);
            comments.push_back(text);
        } else {
            while (pos < bytes.size() && !is_ppm_space(bytes[pos]) && bytes[pos] != '#') ++pos;
            ++numbers;
        }
    }
    return comments;
}

std::vector<uint8_t> encode_image_for_path(const std::string& path, const ImageRgb8& image) {
    const ImageFormat format = format_for_writing(path);
    if (format == ImageFormat::Png && !png_supported()) throw InputError(path, kPngUnsupported);
    return encode_image(image, format);
}

std::vector<uint8_t> read_file_bytes(const std::string& path) { return read_file_impl(path); }

}  // namespace raycast
