// Image regression: the project's own scenes (tests/image_regression_cases.txt) rendered by the
// program must match the reviewed pictures in tests/references/. Tolerance: at most 0.1% of the
// pixels may differ by more than one level in any channel, the same bar as the course's
// references; in practice a change shows up as thousands of pixels. The references are PNG, so
// this test needs a build with libpng (tools/test.sh installs it) and skips without.
// After an intended change: bash tools/update_references.sh, then review every changed picture.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "image/compare_images.h"
#include "image/image_io.h"
#include "test_support.h"

namespace raycast {
namespace {

struct RegressionCase {
    std::string name, arguments, scene;
};

std::string trim(const std::string& text) {
    const size_t first = text.find_first_not_of(" \t");
    if (first == std::string::npos) return "";
    return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::vector<RegressionCase> read_cases() {
    std::vector<RegressionCase> cases;
    std::ifstream in(std::string(RAYCAST_SOURCE_DIR) + "/tests/image_regression_cases.txt");
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        RegressionCase c;
        std::getline(fields, c.name, '|');
        std::getline(fields, c.arguments, '|');
        std::getline(fields, c.scene);
        cases.push_back({trim(c.name), trim(c.arguments), trim(c.scene)});
    }
    return cases;
}

class ImageRegression : public ::testing::TestWithParam<RegressionCase> {};

TEST_P(ImageRegression, MatchesTheReviewedReference) {
    if (!png_supported()) GTEST_SKIP() << "the references are PNG and this build has no libpng";
    const RegressionCase& c = GetParam();
    const std::string output = test::temp_dir("regression-" + c.name) + "/" + c.name + ".png";
    const test::RunResult run =
        test::run_raycast("--quiet " + c.scene + " '" + output + "' " + c.arguments, test::source_dir());
    ASSERT_EQ(run.exit_code, 0) << run.output;

    const ImageRgb8 ours = read_image(output);
    const ImageRgb8 reference = read_image(test::source_dir() + "/tests/references/" + c.name + ".png");
    ASSERT_EQ(ours.width, reference.width);
    ASSERT_EQ(ours.height, reference.height);
    const ImageComparison comparison = compare_images(ours, reference);
    EXPECT_LE(comparison.pixels_beyond(1), comparison.pixel_count / 1000)
        << c.name << ": " << comparison.pixels_beyond(1) << " of " << comparison.pixel_count
        << " pixels differ by more than one level (max " << comparison.max_error << ")";
}

TEST(ImageRegressionCases, ListIsNotEmptyAndEveryReferenceExists) {
    const std::vector<RegressionCase> cases = read_cases();
    ASSERT_GE(cases.size(), 7u);
    for (const RegressionCase& c : cases)
        EXPECT_TRUE(test::file_exists(test::source_dir() + "/tests/references/" + c.name + ".png")) << c.name;
}

INSTANTIATE_TEST_SUITE_P(OwnScenes, ImageRegression, ::testing::ValuesIn(read_cases()),
                         [](const ::testing::TestParamInfo<RegressionCase>& param_info) { return param_info.param.name; });

}  // namespace
}  // namespace raycast
