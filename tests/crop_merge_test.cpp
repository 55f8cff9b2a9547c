// Rendering a frame in pieces (--crop) on separate runs and assembling them (raycast merge) gives
// the file a single full render writes, byte for byte: the pieces may use different thread counts
// and tile sizes, and samples per pixel are seeded by the pixel's place in the full frame.
#include <gtest/gtest.h>

#include <string>

#include "test_support.h"

namespace raycast {
namespace {

struct MergeCase {
    const char* name;
    const char* scene;
    const char* options;
};

class CropMerge : public ::testing::TestWithParam<MergeCase> {};

TEST_P(CropMerge, MergedPiecesEqualTheFullRenderByteForByte) {
    const MergeCase& c = GetParam();
    const std::string dir = test::temp_dir(std::string("crop-merge-") + c.name);
    const std::string scene = test::source_dir() + "/" + c.scene;
    const std::string options = std::string(" --quiet ") + c.options;

    test::RunResult run = test::run_raycast("'" + scene + "' '" + dir + "/full.ppm' --threads 2" + options);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    // Three uneven pieces, each with its own thread count and tile size (the frame is 200x200).
    const char* pieces[] = {"0,0,200,61 --threads 1 --tile 7", "0,61,97,200 --threads 2 --tile 16",
                            "97,61,200,200 --threads 3 --tile 64"};
    std::string piece_files;
    for (int i = 0; i < 3; ++i) {
        const std::string piece = dir + "/piece" + std::to_string(i) + ".ppm";
        run = test::run_raycast("'" + scene + "' '" + piece + "' --crop " + pieces[i] + options);
        ASSERT_EQ(run.exit_code, 0) << run.output;
        piece_files += " '" + piece + "'";
    }
    run = test::run_raycast("merge -o '" + dir + "/merged.ppm'" + piece_files);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const std::string full = test::read_file(dir + "/full.ppm");
    ASSERT_FALSE(full.empty());
    EXPECT_TRUE(full == test::read_file(dir + "/merged.ppm")) << "the merged image differs from the full render";

    // Merging into another format gives that format's file of the same pixels.
    run = test::run_raycast("merge -o '" + dir + "/merged.bmp'" + piece_files);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    run = test::run_raycast("compare '" + dir + "/full.ppm' '" + dir + "/merged.bmp'");
    EXPECT_NE(run.output.find("differing pixels: 0 of 40000"), std::string::npos) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    Modes, CropMerge,
    ::testing::Values(MergeCase{"shaded", "testcases/scene01_basic.txt", ""},
                      MergeCase{"mesh_spp_shadows", "testcases/scene06_torus.txt", "--spp 4 --shadows"},
                      MergeCase{"normals", "testcases/scene03_sphere.txt", "--mode normals"},
                      MergeCase{"depth", "testcases/scene02_cube.txt", "--mode depth --depth-range 5,15"},
                      MergeCase{"cost", "testcases/scene05_blob.txt", "--mode cost"},
                      MergeCase{"thin_lens", "testcases/scene01_basic.txt", "--aperture 0.5 --focus-distance 10 --spp 4"}),
    [](const ::testing::TestParamInfo<MergeCase>& param_info) { return std::string(param_info.param.name); });

TEST(CropMergeErrors, DepthPiecesNeedAFixedRange) {
    const std::string dir = test::temp_dir("crop-merge-depth-range");
    const test::RunResult run = test::run_raycast("testcases/scene02_cube.txt '" + dir +
                                                  "/piece.ppm' --mode depth --crop 0,0,10,10",
                                                  test::source_dir());
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_NE(run.output.find("--crop with a depth image needs --depth-range NEAR,FAR"), std::string::npos)
        << run.output;
    EXPECT_FALSE(test::file_exists(dir + "/piece.ppm"));
}

TEST(CropMergeErrors, CropOutsideTheImageIsAUsageError) {
    const std::string dir = test::temp_dir("crop-merge-outside");
    const test::RunResult run =
        test::run_raycast("testcases/scene01_basic.txt '" + dir + "/piece.ppm' --crop 0,0,201,10", test::source_dir());
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_NE(run.output.find("--crop 0,0,201,10 reaches outside the 200x200 image"), std::string::npos) << run.output;
}

TEST(CropMergeErrors, IncompleteSetIsRefusedAndWritesNothing) {
    const std::string dir = test::temp_dir("crop-merge-gap");
    test::RunResult run = test::run_raycast("testcases/scene01_basic.txt '" + dir + "/a.ppm' --crop 0,0,200,100 -q",
                                            test::source_dir());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    run = test::run_raycast("merge -o '" + dir + "/merged.ppm' '" + dir + "/a.ppm'");
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_NE(run.output.find("merge: error: the pieces leave pixel (0, 100) of the 200x200 frame uncovered"),
              std::string::npos)
        << run.output;
    EXPECT_FALSE(test::file_exists(dir + "/merged.ppm"));
}

TEST(CropMergeErrors, MergeWithoutOutputIsAUsageError) {
    const test::RunResult run = test::run_raycast("merge a.ppm");
    EXPECT_EQ(run.exit_code, 2);
    EXPECT_NE(run.output.find("merge needs -o OUTPUT"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace raycast
