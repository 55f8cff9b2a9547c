#include "test_support.h"

#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace raycast::test {

std::string source_dir() { return RAYCAST_SOURCE_DIR; }

std::string shared_dir() {
    const std::string candidate = source_dir() + "/../shared";
    struct stat info;
    return ::stat(candidate.c_str(), &info) == 0 && S_ISDIR(info.st_mode) ? candidate : std::string();
}

std::string temp_dir(const std::string& name) {
    const std::string path = std::string(RAYCAST_BINARY_DIR) + "/test-output/" + name;
    std::system(("rm -rf '" + path + "' && mkdir -p '" + path + "'").c_str());
    return path;
}

RunResult run_raycast(const std::string& arguments, const std::string& working_dir) {
    std::string command;
    if (!working_dir.empty()) command = "cd '" + working_dir + "' && ";
    command += std::string("'") + RAYCAST_EXECUTABLE + "' " + arguments + " 2>&1";
    RunResult result;
    std::FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return result;
    char buffer[4096];
    size_t got;
    while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.output.append(buffer, got);
    const int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

bool file_exists(const std::string& path) {
    struct stat info;
    return ::stat(path.c_str(), &info) == 0;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

}  // namespace raycast::test
