// Which version of a file was read, so that a program that reads it again when it changes (the
// viewer) can tell whether it has.
#pragma once

#include <sys/stat.h>

#include <cstdint>
#include <string>

namespace raycast {

/// A file's modification time and size.
struct FileVersion {
    int64_t modified_ns = 0;
    int64_t size = -1;  ///< -1: unknown (a mesh parsed from memory, a file that is not there)
    bool operator==(const FileVersion& other) const { return modified_ns == other.modified_ns && size == other.size; }
    bool operator!=(const FileVersion& other) const { return !(*this == other); }
};

/// The version a stat() or fstat() saw.
inline FileVersion version_of(const struct stat& info) {
    return {int64_t{info.st_mtim.tv_sec} * 1000000000 + info.st_mtim.tv_nsec, static_cast<int64_t>(info.st_size)};
}

/// The version of the file `path` names now; unknown when it cannot be looked at.
inline FileVersion current_version(const std::string& path) {
    struct stat info;
    return ::stat(path.c_str(), &info) == 0 ? version_of(info) : FileVersion{};
}

}  // namespace raycast
