// MIT 6.837 (Fall 2004), assignments 1-3: every row of ../shared/reference/mit6837-f04/cases.tsv is
// run the way the MIT course ran it (from the scene's folder, `-input SCENE -size W H -output FILE`
// plus `-depth NEAR FAR FILE`, `-normals FILE`, `-shade_back`, and `-specular_fix` for the `fix`
// rows), and each of the 59 official images must match with at least 99.9% of its pixels within one
// level. Assignment 4 (shadows, mirrors, glass: cases-a4.tsv, with -shadows -bounces N -weight W)
// has 20 consensus images, not official ones, which even the agreeing student renders match only to
// about 0.5% of pixels (see the README there): each must match with at least 99.5% of its pixels
// within one level. Needs ../shared; skipped without it.
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

struct MitCase {
    std::string dir;                      ///< a1, a2 or a3
    std::string scene;                    ///< file name inside dir
    std::vector<std::string> arguments;   ///< cases.tsv's args, split on spaces
    std::vector<std::string> references;  ///< official images, in -output, -depth, -normals order
    bool specular_fix = false;
    std::string name;                     ///< unique test name
    size_t allowed_per_mille = 1;         ///< pixels allowed beyond one level, per thousand
};

std::string cases_path(const char* file) {
    const std::string shared = test::shared_dir();
    return shared.empty() ? std::string() : shared + "/reference/mit6837-f04/" + file;
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::string part;
    std::istringstream in(text);
    while (std::getline(in, part, separator)) {
        if (separator != ' ' || !part.empty()) parts.push_back(part);
    }
    return parts;
}

std::string test_name(const std::string& reference) {
    // "ref/output3_09_fix.ppm" -> "output3_09_fix"
    std::string name = reference.substr(reference.find('/') + 1);
    return name.substr(0, name.find('.'));
}

// Reads a cases file when it is there; otherwise one placeholder case, which skips.
std::vector<MitCase> read_cases(const char* file, size_t allowed_per_mille) {
    std::vector<MitCase> cases;
    std::ifstream in(cases_path(file));
    std::string line;
    bool header_seen = false;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (!header_seen) {  // "dir	scene	args	refs	spec	repro"
            header_seen = true;
            continue;
        }
        const std::vector<std::string> fields = split(line, '\t');
        if (fields.size() < 5) continue;
        MitCase c;
        c.dir = fields[0];
        c.scene = fields[1];
        c.arguments = split(fields[2], ' ');
        c.references = split(fields[3], ' ');
        c.specular_fix = fields[4] == "fix";
        c.name = test_name(c.references.front());
        c.allowed_per_mille = allowed_per_mille;
        cases.push_back(c);
    }
    if (cases.empty()) {
        MitCase placeholder;
        placeholder.name = "shared_folder_absent";
        cases.push_back(placeholder);
    }
    return cases;
}

class Mit6837Reference : public ::testing::TestWithParam<MitCase> {};

TEST_P(Mit6837Reference, MatchesTheReferenceImagesWithinOneLevel) {
    const MitCase& c = GetParam();
    if (c.scene.empty()) GTEST_SKIP() << "../shared/reference/mit6837-f04 is not here";
    const std::string folder = test::shared_dir() + "/reference/mit6837-f04/" + c.dir;
    const std::string out_dir = test::temp_dir("mit6837-" + c.name);

    // Rebuild the course's command line, inserting our output file names where the course had its
    // own: -output FILE, -depth NEAR FAR FILE, -normals FILE (the order of refs in cases.tsv).
    std::vector<std::string> outputs = {out_dir + "/output.ppm"};
    std::string command = "-input " + c.scene + " -output '" + outputs[0] + "'";
    for (size_t i = 0; i < c.arguments.size(); ++i) {
        const std::string& argument = c.arguments[i];
        if (argument == "-depth") {
            ASSERT_LT(i + 2, c.arguments.size()) << "-depth needs NEAR FAR in cases.tsv";
            outputs.push_back(out_dir + "/depth.ppm");
            command += " -depth " + c.arguments[i + 1] + " " + c.arguments[i + 2] + " '" + outputs.back() + "'";
            i += 2;
        } else if (argument == "-normals") {
            outputs.push_back(out_dir + "/normals.ppm");
            command += " -normals '" + outputs.back() + "'";
        } else {
            command += " " + argument;
        }
    }
    if (c.specular_fix) command += " -specular_fix";

    const test::RunResult run = test::run_raycast(command, folder);
    ASSERT_EQ(run.exit_code, 0) << command << "\n" << run.output;
    ASSERT_EQ(outputs.size(), c.references.size()) << "cases.tsv lists one official image per output";

    for (size_t i = 0; i < outputs.size(); ++i) {
        const ImageRgb8 ours = read_image(outputs[i]);
        const ImageRgb8 official = read_image(folder + "/" + c.references[i]);
        ASSERT_EQ(ours.width, official.width) << c.references[i];
        ASSERT_EQ(ours.height, official.height) << c.references[i];
        const ImageComparison comparison = compare_images(ours, official);
        const size_t allowed = comparison.pixel_count * c.allowed_per_mille / 1000;
        EXPECT_LE(comparison.pixels_beyond(1), allowed)
            << c.references[i] << ": " << comparison.pixels_beyond(1) << " pixels differ by more than 1 level";
        std::printf("%s/%s: %zu pixels differ, %zu by more than 1 level\n", c.dir.c_str(), c.references[i].c_str(),
                    comparison.differing_pixels, comparison.pixels_beyond(1));
    }
}

std::string case_name(const ::testing::TestParamInfo<MitCase>& param_info) { return param_info.param.name; }

INSTANTIATE_TEST_SUITE_P(Official, Mit6837Reference, ::testing::ValuesIn(read_cases("cases.tsv", 1)), case_name);
INSTANTIATE_TEST_SUITE_P(Assignment4, Mit6837Reference, ::testing::ValuesIn(read_cases("cases-a4.tsv", 5)), case_name);

}  // namespace
}  // namespace raycast
