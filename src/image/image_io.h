// Image files: BMP (the course's output), PPM, TGA (MIT 6.837's output) and, when libpng is found, PNG.
// Entry points: write_image and read_image by path; encode_image and decode_image on bytes in memory.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"

namespace raycast {

/// The image file formats raycast reads and writes.
enum class ImageFormat { Bmp, Ppm, Tga, Png };

/// The format named by a path's extension, case-insensitive (.bmp .ppm .tga .png); nullopt otherwise.
std::optional<ImageFormat> image_format_for_path(const std::string& path);

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

}  // namespace raycast
