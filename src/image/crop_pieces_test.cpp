// Crop pieces: the window recorded in a PPM header, and merge_crop_pieces putting pieces back
// exactly where they came from (window rows count from the top, images store y = 0 at the bottom).
#include "image/crop_pieces.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "base/error.h"
#include "base/write_file.h"
#include "image/image_io.h"

namespace raycast {
namespace {

// A frame whose every pixel is distinct: (x, y) -> (x, y, x ^ y), y = 0 the bottom row.
ImageRgb8 numbered_frame(int width, int height) {
    ImageRgb8 image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t* p = image.at(x, y);
            p[0] = static_cast<uint8_t>(x);
            p[1] = static_cast<uint8_t>(y);
            p[2] = static_cast<uint8_t>(x ^ y);
        }
    return image;
}

// What --crop renders: the window's pixels, window row 0 being the frame's top row.
CropPiece cut(const ImageRgb8& frame, CropPlacement p, const std::string& name) {
    CropPiece piece{name, p, ImageRgb8(p.x1 - p.x0, p.y1 - p.y0)};
    for (int row = p.y0; row < p.y1; ++row)
        for (int x = p.x0; x < p.x1; ++x) {
            const uint8_t* from = frame.at(x, frame.height - 1 - row);
            uint8_t* to = piece.image.at(x - p.x0, p.y1 - 1 - row);
            to[0] = from[0], to[1] = from[1], to[2] = from[2];
        }
    return piece;
}

std::string temp_path(const std::string& name) { return ::testing::TempDir() + "crop_pieces_test_" + name; }

TEST(CropPiecesTest, CommentSpellsTheWindowAndTheFrame) {
    EXPECT_EQ(crop_comment(CropPlacement{1, 2, 30, 40, 64, 48}), "raycast-crop 1,2,30,40 of 64x48");
}

TEST(CropPiecesTest, MergingFourUnevenPiecesGivesBackTheFrame) {
    const ImageRgb8 frame = numbered_frame(37, 23);
    const std::vector<CropPiece> pieces = {
        cut(frame, {0, 0, 37, 5, 37, 23}, "top"),        // a full-width band at the top
        cut(frame, {0, 5, 11, 23, 37, 23}, "left"),      // the rest of the left side
        cut(frame, {11, 5, 37, 6, 37, 23}, "one-row"),   // a single row
        cut(frame, {11, 6, 37, 23, 37, 23}, "bottom"),   // the bottom right
    };
    const ImageRgb8 merged = merge_crop_pieces(pieces);
    ASSERT_EQ(merged.width, 37);
    ASSERT_EQ(merged.height, 23);
    EXPECT_EQ(merged.rgb, frame.rgb);
}

TEST(CropPiecesTest, PieceRoundTripsThroughAPpmFileWithItsWindow) {
    const ImageRgb8 frame = numbered_frame(16, 8);
    const CropPiece piece = cut(frame, {3, 1, 10, 7, 16, 8}, "piece");
    const std::string path = temp_path("roundtrip.ppm");
    write_crop_piece(path, piece.image, piece.placement);
    const CropPiece back = read_crop_piece(path);
    EXPECT_EQ(back.placement.x0, 3);
    EXPECT_EQ(back.placement.y0, 1);
    EXPECT_EQ(back.placement.x1, 10);
    EXPECT_EQ(back.placement.y1, 7);
    EXPECT_EQ(back.placement.full_width, 16);
    EXPECT_EQ(back.placement.full_height, 8);
    EXPECT_EQ(back.image.rgb, piece.image.rgb);
    // The record is an ordinary PPM comment: any PPM reader still reads the pixels.
    EXPECT_EQ(read_image(path).rgb, piece.image.rgb);
    std::remove(path.c_str());
}

std::string error_of(const std::vector<CropPiece>& pieces) {
    try {
        merge_crop_pieces(pieces);
    } catch (const InputError& error) {
        return error.diagnostics().front().location.file + ": " + error.diagnostics().front().message;
    }
    return "no error";
}

TEST(CropPiecesTest, OverlapNamesBothPiecesAndThePixel) {
    const ImageRgb8 frame = numbered_frame(10, 10);
    EXPECT_EQ(error_of({cut(frame, {0, 0, 10, 6, 10, 10}, "a.ppm"), cut(frame, {0, 5, 10, 10, 10, 10}, "b.ppm")}),
              "b.ppm: it overlaps 'a.ppm' at pixel (0, 5)");
}

TEST(CropPiecesTest, GapNamesTheFirstUncoveredPixel) {
    const ImageRgb8 frame = numbered_frame(10, 10);
    EXPECT_EQ(error_of({cut(frame, {0, 0, 10, 4, 10, 10}, "a.ppm"), cut(frame, {0, 4, 7, 10, 10, 10}, "b.ppm")}),
              "merge: the pieces leave pixel (7, 4) of the 10x10 frame uncovered (row 0 at the top)");
}

TEST(CropPiecesTest, PiecesOfDifferentFramesAreRefused) {
    EXPECT_EQ(error_of({cut(numbered_frame(10, 10), {0, 0, 10, 5, 10, 10}, "a.ppm"),
                        cut(numbered_frame(10, 12), {0, 5, 10, 12, 10, 12}, "b.ppm")}),
              "b.ppm: it belongs to a 10x12 frame but 'a.ppm' to a 10x10 one");
}

TEST(CropPiecesTest, PlainPpmIsNotAPiece) {
    const std::string path = temp_path("plain.ppm");
    write_image(path, numbered_frame(4, 4));
    try {
        read_crop_piece(path);
        ADD_FAILURE() << "a PPM without a crop record was read as a piece";
    } catch (const InputError& error) {
        EXPECT_EQ(error.diagnostics().front().message,
                  "not a crop piece: no 'raycast-crop' record in its header (write pieces with --crop)");
    }
    std::remove(path.c_str());
}

TEST(CropPiecesTest, RecordThatDisagreesWithTheImageSizeIsRefused) {
    const std::string path = temp_path("liar.ppm");
    // The record claims a 5x5 window, the pixels are 4x4.
    write_file_atomically(path, encode_ppm_with_comment(numbered_frame(4, 4), "raycast-crop 0,0,5,5 of 8x8"), "image");
    try {
        read_crop_piece(path);
        ADD_FAILURE() << "a piece whose size disagrees with its window was accepted";
    } catch (const InputError& error) {
        EXPECT_EQ(error.diagnostics().front().message, "the image is 4x4 but its crop window 0,0,5,5 is 5x5");
    }
    std::remove(path.c_str());
}

TEST(CropPiecesTest, MalformedRecordsAreRefused) {
    // Also: past int's range (4294967297 had wrapped to 1, and the merge went ahead), a frame past
    // the pixel limit (16384x16384: merge allocated 1.8 GB first), and spacing of its own.
    for (const char* record : {"raycast-crop 0,0,5", "raycast-crop 0,0,5,5 of 4x4", "raycast-crop 3,0,2,4 of 8x8",
                               "raycast-crop 0,0,4,4 of 8x8 extra", "raycast-crop -1,0,3,4 of 8x8",
                               "raycast-crop 0,0,4294967300,4 of 4x4", "raycast-crop 0,0,4,4 of 4294967300x4",
                               "raycast-crop 0,0,4,4 of 16384x16384", "raycast-crop  0,0,4,4 of 4x4",
                               "raycast-crop 0, 0,4,4 of 4x4", "raycast-crop 0,0,4,4 of 4x4 ", "raycast-crop 0,0,4,4 of 4x"}) {
        const std::string path = temp_path("bad.ppm");
        write_file_atomically(path, encode_ppm_with_comment(numbered_frame(4, 4), record), "image");
        try {
            read_crop_piece(path);
            ADD_FAILURE() << "accepted: " << record;
        } catch (const InputError& error) {
            EXPECT_EQ(error.diagnostics().front().message,
                      std::string("bad crop record '") + record + "': expected 'raycast-crop X0,Y0,X1,Y1 of WxH'");
        }
        std::remove(path.c_str());
    }
    // The record written for a piece of the largest frame reads back.
    const std::string path = temp_path("largest.ppm");
    write_file_atomically(path, encode_ppm_with_comment(numbered_frame(4, 4), "raycast-crop 8188,0,8192,4 of 8192x8192"), "image");
    EXPECT_EQ(read_crop_piece(path).placement.x0, 8188);
    std::remove(path.c_str());
}

TEST(CropPiecesTest, OnlyPpmCanHoldAPiece) {
    EXPECT_THROW(write_crop_piece(temp_path("piece.bmp"), numbered_frame(2, 2), CropPlacement{0, 0, 2, 2, 2, 2}),
                 InputError);
}

TEST(CropPiecesTest, HeaderCommentsAreReadInOrderAndOnlyFromTheHeader) {
    const std::string text = "P6\n# first\n#second\n2 # third\n1\n255\n# not a comment: pixel bytes";
    const std::vector<uint8_t> bytes(text.begin(), text.end());
    EXPECT_EQ(ppm_header_comments(bytes), (std::vector<std::string>{"first", "second", "third"}));
    EXPECT_TRUE(ppm_header_comments(std::vector<uint8_t>{'B', 'M'}).empty());
}

}  // namespace
}  // namespace raycast
