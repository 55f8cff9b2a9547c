// Helpers shared by the end-to-end tests: where the data is, running the raycast program, and
// reading files.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace raycast::test {

/// The repository root (tests run from there).
std::string source_dir();
/// ../shared next to the repository, or "" when it is not there (tests that need it skip).
std::string shared_dir();
/// A fresh empty folder under the build tree for one test's files.
std::string temp_dir(const std::string& name);

struct RunResult {
    int exit_code = -1;
    std::string output;  ///< stdout and stderr together
};

/// Runs a shell command line and collects its stdout (add 2>&1 for stderr) and exit code.
RunResult run_command(const std::string& command);

/// Runs the raycast program with `arguments` (already shell-quoted as needed) in `working_dir`.
RunResult run_raycast(const std::string& arguments, const std::string& working_dir = "");

bool file_exists(const std::string& path);
/// The names in a folder, without "." and ".."; empty if it cannot be read.
std::set<std::string> files_in(const std::string& dir);
/// A binary PPM (P6, maxval 255) read by the format's rules, independently of raycast's reader;
/// ok is false unless the header is right and the pixel bytes fill the file exactly.
struct Ppm {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
    bool ok = false;
};
Ppm parse_ppm(const std::string& bytes);

/// The text up to the first newline.
std::string first_line(const std::string& text);
/// The lines of a text, without their newlines.
std::vector<std::string> lines_of(const std::string& text);
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

/// A scene's text: a glass ball between two facing mirrors, the camera between them, `side`
/// pixels square. With the weight cutoff off, each camera ray's tree doubles at every meeting
/// with the glass, up to the sample's limit of rays.
std::string mirrors_and_glass_scene(int side);

}  // namespace raycast::test
