// The course's seven PA1 scenes, rendered as the course's run_all.sh does (from the folder that
// holds testcases/ and mesh/), must match the course's reference images: at least 99.9% of the
// pixels within one level in every channel. Needs ../shared; skipped without it.
#include <gtest/gtest.h>

#include <string>

#include "image/compare_images.h"
#include "image/image_io.h"
#include "test_support.h"

namespace raycast {
namespace {

struct CourseScene {
    const char* file;
    const char* reference;
};

class CourseReference : public ::testing::TestWithParam<CourseScene> {};

TEST_P(CourseReference, MatchesTheCourseImageWithinOneLevel) {
    const std::string shared = test::shared_dir();
    if (shared.empty()) GTEST_SKIP() << "../shared is not here";
    const CourseScene& scene = GetParam();
    const std::string out_dir = test::temp_dir(std::string("course-") + scene.reference);
    const std::string output = out_dir + "/" + scene.reference + ".bmp";
    const test::RunResult run =
        test::run_raycast(std::string("testcases/") + scene.file + " '" + output + "'", shared + "/course");
    ASSERT_EQ(run.exit_code, 0) << run.output;

    const ImageRgb8 ours = read_image(output);
    const ImageRgb8 reference = read_image(shared + "/reference/course-pa1/" + scene.reference + ".bmp");
    ASSERT_EQ(ours.width, reference.width);
    ASSERT_EQ(ours.height, reference.height);
    const ImageComparison c = compare_images(ours, reference);
    // The tolerance a grader gives `raycast compare --max-diff 1 --max-fraction 0.001` (README).
    std::string why;
    EXPECT_TRUE(within_tolerance(c, ImageTolerance{1, 0.001}, &why)) << scene.file << ": " << why << " (max "
                                                                      << c.max_error << ")";
    std::printf("%s: %zu pixels differ, %zu by more than 1 level, PSNR %.1f dB\n", scene.file, c.differing_pixels,
                c.pixels_beyond(1), c.psnr);
}

INSTANTIATE_TEST_SUITE_P(Pa1, CourseReference,
                         ::testing::Values(CourseScene{"scene01_basic.txt", "scene01"},
                                           CourseScene{"scene02_cube.txt", "scene02"},
                                           CourseScene{"scene03_sphere.txt", "scene03"},
                                           CourseScene{"scene04_axes.txt", "scene04"},
                                           CourseScene{"scene05_bunny_200.txt", "scene05"},
                                           CourseScene{"scene06_bunny_1k.txt", "scene06"},
                                           CourseScene{"scene07_shine.txt", "scene07"}),
                         [](const ::testing::TestParamInfo<CourseScene>& param_info) { return std::string(param_info.param.reference); });

}  // namespace
}  // namespace raycast
