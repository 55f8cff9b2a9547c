// Helpers shared by the end-to-end tests: where the data is, running the raycast program, and
// reading files.
#pragma once

#include <string>

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

/// Runs the raycast program with `arguments` (already shell-quoted as needed) in `working_dir`.
RunResult run_raycast(const std::string& arguments, const std::string& working_dir = "");

bool file_exists(const std::string& path);
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

}  // namespace raycast::test
