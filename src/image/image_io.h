// Image files: BMP (the course's output), PPM, TGA (MIT 6.837's output) and, when libpng is found, PNG.
// Entry points: write_image and read_image by path; encode_image and decode_image on bytes in memory.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"

namespace raycast {

/// The image file formats raycast reads and writes.
enum class ImageFormat { Bmp, Ppm, Tga, Png };

/// The format named by a path's extension, case-insensitive (.bmp .ppm .tga .png); nullopt otherwise.
std::optional<ImageFormat> image_format_for_path(const std::string& path);

/// The format a name gives, case-insensitive (bmp ppm tga png, as `--format` takes it); nullopt otherwise.
std::optional<ImageFormat> image_format_named(const std::string& name);

/// Whether this build reads and writes PNG (libpng found at build time).
bool png_supported();

/// Bytes of a file in the given format. The image must have 1..kMaxImageSide pixels a side and
/// 3·width·height bytes (std::invalid_argument otherwise); PNG without libpng throws InputError("png", ...).
std::vector<uint8_t> encode_image(const ImageRgb8& image, ImageFormat format);

/// Decodes bytes; `name` labels errors. Throws InputError(name, message) on anything malformed,
/// and never reads outside `bytes`, whatever they hold.
ImageRgb8 decode_image(const std::vector<uint8_t>& bytes, ImageFormat format, const std::string& name);

/// Writes by extension, atomically: a temporary file in the same directory, then rename(). On any
/// failure the temporary is removed and an existing file at `path` is left untouched.
/// Throws InputError(path, message).
void write_image(const std::string& path, const ImageRgb8& image);

/// Reads by content signature where possible (BM, P6/P3, PNG signature), else by extension (TGA).
/// Throws InputError(path, message).
ImageRgb8 read_image(const std::string& path);

/// A binary PPM whose header holds `comment` (one line) as a `# comment` line: how `--crop`
/// records where a piece sits in the full frame. Throws std::invalid_argument like encode_image.
std::vector<uint8_t> encode_ppm_with_comment(const ImageRgb8& image, const std::string& comment);

/// The comments in a PPM file's header (the text after '#' and one space), in order; empty for
/// anything that is not a PPM file.
std::vector<std::string> ppm_header_comments(const std::vector<uint8_t>& bytes);

/// The bytes write_image would write to `path` (its format by extension). Throws InputError
/// (PNG without libpng) or std::invalid_argument (no known extension), as write_image does.
std::vector<uint8_t> encode_image_for_path(const std::string& path, const ImageRgb8& image);

/// A whole file's bytes. Throws InputError(path, "cannot read image: ...").
std::vector<uint8_t> read_file_bytes(const std::string& path);

}  // namespace raycast
