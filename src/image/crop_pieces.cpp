#include "image/crop_pieces.h"

#include <cstdint>
#include <cstdio>
#include <cstring>

#include "base/error.h"
#include "base/write_file.h"
#include "base/limits.h"
#include "base/parse_number.h"
#include "image/image_io.h"

namespace raycast {
namespace {

constexpr const char* kCropKey = "raycast-crop";

// Within the frame, and a frame raycast could have rendered: a record claiming 16384x16384 (past
// the pixel limit) had merge allocate 1.8 GB before it found the piece alone.
bool placement_is_valid(const CropPlacement& p) {
    return p.full_width > 0 && p.full_height > 0 && p.full_width <= kMaxImageSide && p.full_height <= kMaxImageSide &&
           int64_t{p.full_width} * p.full_height <= kMaxImagePixels && 0 <= p.x0 && p.x0 < p.x1 &&
           p.x1 <= p.full_width && 0 <= p.y0 && p.y0 < p.y1 && p.y1 <= p.full_height;
}

// Reads "X0,Y0,X1,Y1 of WxH" (after the key and one space) exactly: whole numbers in int's range,
// nothing else. sscanf's %d had wrapped 4294967297 to 1 (undefined behaviour besides).
bool parse_placement(const std::string& text, CropPlacement& p) {
    const char* at = text.c_str();
    const char* const end = at + text.size();
    auto number = [&](int& out, const char* then) {
        int64_t value = 0;
        const NumberResult result = parse_int(at, end, value);
        if (result.status != NumberStatus::Ok || value < INT32_MIN || value > INT32_MAX) return false;
        out = static_cast<int>(value);
        at = result.end;
        const size_t length = std::strlen(then);
        if (static_cast<size_t>(end - at) < length || std::strncmp(at, then, length) != 0) return false;
        at += length;
        return true;
    };
    if (*at++ != ' ') return false;
    return number(p.x0, ",") && number(p.y0, ",") && number(p.x1, ",") && number(p.y1, " of ") &&
           number(p.full_width, "x") && number(p.full_height, "") && at == end;
}

}  // namespace

std::string crop_comment(const CropPlacement& p) {
    return string_printf("%s %d,%d,%d,%d of %dx%d", kCropKey, p.x0, p.y0, p.x1, p.y1, p.full_width, p.full_height);
}

void write_crop_piece(const std::string& path, const ImageRgb8& image, const CropPlacement& placement) {
    const std::optional<ImageFormat> format = image_format_for_path(path);
    if (format != ImageFormat::Ppm)
        throw InputError(path, "a --crop piece must be written as .ppm: only PPM records the window for 'raycast merge'");
    write_file_atomically(path, encode_crop_piece(image, placement), "image");
}

std::vector<uint8_t> encode_crop_piece(const ImageRgb8& image, const CropPlacement& placement) {
    return encode_ppm_with_comment(image, crop_comment(placement));
}

CropPiece read_crop_piece(const std::string& path) {
    const std::vector<uint8_t> bytes = read_file_bytes(path);
    CropPiece piece;
    piece.path = path;
    piece.image = decode_image(bytes, ImageFormat::Ppm, path);
    bool found = false;
    for (const std::string& comment : ppm_header_comments(bytes)) {
        if (comment.compare(0, std::strlen(kCropKey), kCropKey) != 0) continue;
        CropPlacement& p = piece.placement;
        if (!parse_placement(comment.substr(std::strlen(kCropKey)), p) || !placement_is_valid(p))
            throw InputError(path, "bad crop record '" + comment + "': expected 'raycast-crop X0,Y0,X1,Y1 of WxH'");
        found = true;
        break;
    }
    if (!found) throw InputError(path, "not a crop piece: no 'raycast-crop' record in its header (write pieces with --crop)");
    const CropPlacement& p = piece.placement;
    if (piece.image.width != p.x1 - p.x0 || piece.image.height != p.y1 - p.y0)
        throw InputError(path, string_printf("the image is %dx%d but its crop window %d,%d,%d,%d is %dx%d",
                                             piece.image.width, piece.image.height, p.x0, p.y0, p.x1, p.y1, p.x1 - p.x0,
                                             p.y1 - p.y0));
    return piece;
}

ImageRgb8 merge_crop_pieces(const std::vector<CropPiece>& pieces) {
    if (pieces.empty()) throw InputError("merge", "no pieces to merge");
    const int width = pieces.front().placement.full_width, height = pieces.front().placement.full_height;
    ImageRgb8 full(width, height);
    // Which piece owns each pixel (-1: none yet), to name the pieces in an overlap.
    std::vector<int> owner(static_cast<size_t>(width) * static_cast<size_t>(height), -1);
    for (size_t i = 0; i < pieces.size(); ++i) {
        const CropPiece& piece = pieces[i];
        const CropPlacement& p = piece.placement;
        if (p.full_width != width || p.full_height != height)
            throw InputError(piece.path, string_printf("it belongs to a %dx%d frame but '%s' to a %dx%d one",
                                                       p.full_width, p.full_height, pieces.front().path.c_str(), width,
                                                       height));
        for (int row = p.y0; row < p.y1; ++row) {
            // Window rows count from the top; images store y = 0 at the bottom.
            const int full_y = height - 1 - row, piece_y = (p.y1 - 1) - row;
            for (int x = p.x0; x < p.x1; ++x) {
                int& who = owner[static_cast<size_t>(full_y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
                if (who >= 0)
                    throw InputError(piece.path, string_printf("it overlaps '%s' at pixel (%d, %d)",
                                                               pieces[static_cast<size_t>(who)].path.c_str(), x, row));
                who = static_cast<int>(i);
                std::memcpy(full.at(x, full_y), piece.image.at(x - p.x0, piece_y), 3);
            }
        }
    }
    for (int row = 0; row < height; ++row)
        for (int x = 0; x < width; ++x)
            if (owner[static_cast<size_t>(height - 1 - row) * static_cast<size_t>(width) + static_cast<size_t>(x)] < 0)
                throw InputError("merge", string_printf("the pieces leave pixel (%d, %d) of the %dx%d frame uncovered "
                                                        "(row 0 at the top)",
                                                        x, row, width, height));
    return full;
}

}  // namespace raycast
