#include "test_support.h"

#include <dirent.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cctype>
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
    return run_command(command);
}

RunResult run_command(const std::string& command) {
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

std::set<std::string> files_in(const std::string& dir) {
    std::set<std::string> names;
    if (DIR* d = ::opendir(dir.c_str())) {
        while (const dirent* entry = ::readdir(d)) {
            const std::string name = entry->d_name;
            if (name != "." && name != "..") names.insert(name);
        }
        ::closedir(d);
    }
    return names;
}

Ppm parse_ppm(const std::string& bytes) {
    Ppm ppm;
    size_t pos = 0;
    auto skip_space_and_comments = [&] {
        while (pos < bytes.size()) {
            if (bytes[pos] == '#') {
                while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
            } else if (std::isspace(static_cast<unsigned char>(bytes[pos]))) {
                ++pos;
            } else {
                break;
            }
        }
    };
    auto number = [&] {
        skip_space_and_comments();
        int value = 0;
        while (pos < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[pos])))
            value = value * 10 + (bytes[pos++] - '0');
        return value;
    };
    if (bytes.compare(0, 2, "P6") != 0) return ppm;
    pos = 2;
    ppm.width = number();
    ppm.height = number();
    const int maxval = number();
    ++pos;  // the single whitespace byte before the pixels
    const size_t size = 3 * static_cast<size_t>(ppm.width) * static_cast<size_t>(ppm.height);
    if (maxval != 255 || pos + size != bytes.size()) return ppm;
    ppm.rgb.assign(bytes.begin() + static_cast<std::ptrdiff_t>(pos), bytes.end());
    ppm.ok = true;
    return ppm;
}

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
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

std::string mirrors_and_glass_scene(int side) {
    const std::string size = std::to_string(side);
    return "PerspectiveCamera {\n"
           "    center 0 0 0.5  direction 0 0 -1  up 0 1 0  angle 30  width " + size + "  height " + size + "\n"
           "}\n"
           "Lights { numLights 1 PointLight { position 0 0.5 0 color 1 1 1 } }\n"
           "Background { color 0 0 0 }\n"
           "Materials {\n"
           "    numMaterials 2\n"
           "    Material { diffuseColor 0.1 0.1 0.1 reflectiveColor 0.9 0.9 0.9 }\n"
           "    Material { diffuseColor 0 0 0 reflectiveColor 0.5 0.5 0.5 transparentColor 0.5 0.5 0.5 "
           "indexOfRefraction 1.5 }\n"
           "}\n"
           "Group {\n"
           "    numObjects 3\n"
           "    MaterialIndex 0\n"
           "    Plane { normal 0 0 1 offset -2 }\n"
           "    Plane { normal 0 0 -1 offset -2 }\n"
           "    MaterialIndex 1\n"
           "    Sphere { center 0 0 -1 radius 0.5 }\n"
           "}\n";
}

}  // namespace raycast::test
