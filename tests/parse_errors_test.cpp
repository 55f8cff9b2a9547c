// Golden tests of raycast's diagnostics for malformed scenes: every tests/parse_errors/NAME.txt (one
// kind of mistake each: unknown keywords with suggestions, missing and unknown fields, count
// mismatches, bad numbers, unterminated blocks, stray braces, bad transforms, missing and malformed
// OBJ files, many errors at once, the error limit, nesting too deep, ...) is run through the program
// as a user would, `raycast NAME.txt OUT.bmp` from that folder, so file names in the messages are
// the bare names given on the command line. Each must exit with status 1, print exactly
// NAME.expected (file:line:col: error: message, the source line, a caret), and write no image.
// The folder is listed at run time: adding a case is adding two files.
//
// Regenerate the goldens with `bash tools/update_parse_error_goldens.sh [path/to/raycast]`, then
// READ every new or changed .expected by hand against its .txt (line, column, caret and wording):
// this test only notices changes, it cannot tell a wrong message from a right one.
//
// NAME starting with DISABLED_ marks a known bug: its .expected holds the correct output, written by
// hand; the case runs in the DISABLED_KnownBugs instantiation (see it fail with
// --gtest_also_run_disabled_tests), and the update script leaves its golden alone. Once the bug is
// fixed, drop the prefix from both files and regenerate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"

namespace raycast {
namespace {

std::string cases_dir() { return test::source_dir() + "/tests/parse_errors"; }

bool is_known_bug(const std::string& name) { return name.rfind("DISABLED_", 0) == 0; }

// Every NAME for which NAME.txt exists, sorted.
std::vector<std::string> case_names() {
    std::vector<std::string> names;
    std::error_code error;
    for (const auto& entry : std::filesystem::directory_iterator(cases_dir(), error))
        if (entry.path().extension() == ".txt") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

// The cases that must pass, or only the known bugs.
std::vector<std::string> case_names(bool known_bugs) {
    std::vector<std::string> names = case_names();
    names.erase(std::remove_if(names.begin(), names.end(),
                               [&](const std::string& n) { return is_known_bug(n) != known_bugs; }),
                names.end());
    return names;
}

class ParseErrorGolden : public ::testing::TestWithParam<std::string> {};

TEST_P(ParseErrorGolden, PrintsExactlyTheExpectedDiagnosticsAndWritesNoImage) {
    const std::string& name = GetParam();
    const std::string expected_path = cases_dir() + "/" + name + ".expected";
    ASSERT_TRUE(test::file_exists(expected_path)) << "no golden " << expected_path
                                                  << ": run tools/update_parse_error_goldens.sh and review it";
    const std::string expected = test::read_file(expected_path);
    ASSERT_NE(expected.find(": error: "), std::string::npos) << "the golden reports no error: " << expected_path;

    // The image goes to the build tree, not the source tree: the path never appears in the
    // diagnostics (all are about the scene), and the source tree may be read-only.
    const std::string image = test::temp_dir("parse-errors/" + name) + "/" + name + ".bmp";
    const test::RunResult run = test::run_raycast(name + ".txt '" + image + "'", cases_dir());
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(run.output, expected) << "raycast's output differs from " << expected_path;
    EXPECT_FALSE(test::file_exists(image)) << "raycast wrote an image for a scene with errors";
}

std::string param_name(const ::testing::TestParamInfo<std::string>& param_info) { return param_info.param; }

INSTANTIATE_TEST_SUITE_P(Cases, ParseErrorGolden, ::testing::ValuesIn(case_names(false)), param_name);
// Known bugs in their own instantiation, so that both gtest and CTest (whose gtest_discover_tests
// only looks for a DISABLED_ prefix on the suite or the test name) see them as disabled.
INSTANTIATE_TEST_SUITE_P(DISABLED_KnownBugs, ParseErrorGolden, ::testing::ValuesIn(case_names(true)), param_name);

TEST(ParseErrorGoldenFolder, HoldsAtLeastTwentyFiveCasesEachWithAGolden) {
    const std::vector<std::string> names = case_names();
    EXPECT_GE(case_names(false).size(), 25u);
    for (const std::string& name : names) {
        // Names become test names: letters, digits and underscores only.
        EXPECT_TRUE(std::all_of(name.begin(), name.end(),
                                [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }))
            << name;
        EXPECT_TRUE(test::file_exists(cases_dir() + "/" + name + ".expected")) << name << ".expected is missing";
    }
}

TEST(ParseErrorGoldenFolder, HasNoGoldenWithoutItsScene) {
    for (const auto& entry : std::filesystem::directory_iterator(cases_dir()))
        if (entry.path().extension() == ".expected") {
            const std::filesystem::path scene = entry.path().parent_path() / (entry.path().stem().string() + ".txt");
            EXPECT_TRUE(std::filesystem::exists(scene)) << entry.path() << " has no scene";
        }
}

}  // namespace
}  // namespace raycast
