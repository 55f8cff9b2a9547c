// Rendering one frame as several pieces and putting them back together: `raycast --crop` writes a
// piece, `raycast merge` assembles pieces into the image a full render would have written, byte for
// byte. A piece is a binary PPM whose header records its window and the full frame's size:
//   P6
//   # raycast-crop 0,0,512,256 of 1024x512
// Windows use the command line's coordinates: columns x0..x1-1 and rows y0..y1-1, row 0 at the top.
#pragma once

#include <string>
#include <vector>

#include "image/image.h"

namespace raycast {

struct CropPlacement {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< the window, row 0 at the top
    int full_width = 0, full_height = 0;
};

struct CropPiece {
    std::string path;
    CropPlacement placement;
    ImageRgb8 image;  ///< (x1 - x0) × (y1 - y0) pixels
};

/// The header comment that records a placement: "raycast-crop X0,Y0,X1,Y1 of WxH".
std::string crop_comment(const CropPlacement& placement);

/// Writes a piece as PPM with its placement recorded (atomically, like write_image). A path that is
/// not .ppm throws InputError: only PPM carries the placement.
void write_crop_piece(const std::string& path, const ImageRgb8& image, const CropPlacement& placement);

/// The bytes write_crop_piece writes: a binary PPM with the crop record in its header.
std::vector<uint8_t> encode_crop_piece(const ImageRgb8& image, const CropPlacement& placement);

/// Reads a piece; InputError(path, ...) if it is not a PPM with a valid, consistent placement.
CropPiece read_crop_piece(const std::string& path);

/// The full image from pieces that cover the frame exactly once. InputError names the piece at fault
/// for a different frame size, an overlap, or (naming the first uncovered pixel) a gap.
ImageRgb8 merge_crop_pieces(const std::vector<CropPiece>& pieces);

}  // namespace raycast
